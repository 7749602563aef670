//! The browser check's one-submission setup (`npr_specular::SetupOnGpu`'s passes, mapped
//! and polled as the page must): the `N = H` search with its peaks
//! (`CentreSearchPass::prepare_with_peaks`) and the regions seeded from its centres on the
//! GPU (`RegionPass::prepare_tracked`), in one submission, on a frame after one the CPU
//! updated; then the update on what came back, against the CPU's own update of the same
//! frame.

use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, HighlightCentre, LightEye, Mesh};
use npr_gpu::FrameId;
use npr_specular::{
    CentreSearchPass, HighlightSet, PendingSolutions, PendingTracked, RegionPass, SearchInput,
    SearchSolutions, TrackedInput, TrackedRegions,
};

/// The two frames: the first updated on the CPU by both sets, the second set up on the
/// GPU for one and on the CPU for the other. A point light over a knot, whose bright
/// parts include some without an `N = H` point.
fn frames() -> [(LightEye, Mat4); 2] {
    let eye = Vec3::new(0.0, 0.5, 4.0);
    let world = Mat4::from_rotation_y(0.4) * Mat4::from_rotation_x(-0.5);
    [
        (
            LightEye::Positions {
                light: Vec3::new(2.0, 3.0, 2.5),
                eye,
            },
            world,
        ),
        (
            LightEye::Positions {
                light: Vec3::new(2.2, 3.0, 2.3),
                eye,
            },
            world * Mat4::from_rotation_y(0.05),
        ),
    ]
}

/// The mesh's bounding radius about its box's centre.
pub(crate) fn bounding_radius(mesh: &Mesh) -> f32 {
    let (lo, hi) = mesh.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let c = 0.5 * (lo + hi);
    mesh.positions
        .iter()
        .map(|p| p.distance(c))
        .fold(0.0, f32::max)
}

/// The tracked frame on its way back.
pub struct TrackingCheck {
    /// The mesh's bounding radius (about its box's centre).
    radius: f32,
    cpu: HighlightSet,
    gpu: HighlightSet,
    search: PendingSolutions,
    regions: PendingTracked,
    solved: Option<SearchSolutions>,
    tracked: Option<TrackedRegions>,
}

impl TrackingCheck {
    /// Both sets updated on the first frame, then the second frame's search and tracked
    /// regions recorded in one submission and their maps asked for.
    ///
    /// # Errors
    /// A GPU or highlight error, as one line.
    pub fn start(device: &wgpu::Device, queue: &wgpu::Queue, mesh: &Mesh) -> Result<Self, String> {
        let options = CurvatureOptions::default();
        let mut cpu = HighlightSet::new(mesh, &options).map_err(|e| e.to_string())?;
        let mut gpu = HighlightSet::new(mesh, &options).map_err(|e| e.to_string())?;
        let [first, (light_eye, world_from_object)] = frames();
        cpu.update(first.0, first.1);
        gpu.update(first.0, first.1);
        let search_pass = CentreSearchPass::new(device);
        let mut search = search_pass
            .create_object_with_peaks(device, &gpu)
            .map_err(|e| e.to_string())?;
        let frame = FrameId(1);
        let input = SearchInput {
            frame,
            search: gpu.search(),
            light_eye,
            world_from_object,
        };
        let searched = search_pass
            .prepare_with_peaks(queue, &mut search, &input, Some(gpu.global.sigma))
            .map_err(|e| e.to_string())?;
        let region_pass = RegionPass::new(device);
        let mut regions = region_pass
            .create_object(device, &gpu)
            .map_err(|e| e.to_string())?;
        let tracked = TrackedInput {
            frame,
            set: &gpu,
            light_eye,
            world_from_object,
            search: (&search, &searched),
        };
        let grown = region_pass
            .prepare_tracked(queue, &mut regions, &tracked)
            .map_err(|e| e.to_string())?;
        let mut encoder = device.create_command_encoder(&Default::default());
        search_pass
            .record(&mut encoder, &search, &searched)
            .map_err(|e| e.to_string())?;
        region_pass
            .record(&mut encoder, &regions, &grown)
            .map_err(|e| e.to_string())?;
        queue.submit([encoder.finish()]);
        Ok(Self {
            radius: bounding_radius(mesh),
            cpu,
            gpu,
            search: search.map(&searched).map_err(|e| e.to_string())?,
            regions: regions
                .map_tracked(device, queue, &grown)
                .map_err(|e| e.to_string())?,
            solved: None,
            tracked: None,
        })
    }

    /// The report once both maps have completed (`None` before): whether the GPU seeded
    /// the update's regions, its peaks and the CPU's, and how far the GPU-setup
    /// highlights are from the CPU's (ids and counts, centres, footprints; of the mesh's
    /// bounding radius).
    ///
    /// # Errors
    /// A failed map, as one line.
    pub fn poll(&mut self) -> Result<Option<serde_json::Value>, String> {
        let radius = self.radius.max(f32::MIN_POSITIVE);
        if self.solved.is_none()
            && let Some(s) = self.search.try_take()
        {
            self.solved = Some(s.map_err(|e| e.to_string())?);
        }
        if self.tracked.is_none()
            && let Some(t) = self.regions.try_take()
        {
            self.tracked = Some(t.map_err(|e| e.to_string())?);
        }
        let (Some(solved), Some(tracked)) = (&self.solved, &self.tracked) else {
            return Ok(None);
        };
        let [_, (light_eye, world_from_object)] = frames();
        let want = self.cpu.update(light_eye, world_from_object).to_vec();
        let cpu_peaks = self.cpu.stats().peaks;
        let mut take =
            |_: &HighlightSet, seeds: &[(HighlightCentre, f32)]| tracked.for_seeds(seeds);
        let got = self
            .gpu
            .update_from_search(light_eye, world_from_object, solved, Some(&mut take))
            .to_vec();
        let seeded = self.gpu.stats().regions_on_gpu;
        let same = got.len() == want.len()
            && got
                .iter()
                .zip(&want)
                .all(|(g, w)| (g.id, g.found, g.piece, g.peak) == (w.id, w.found, w.piece, w.peak));
        let (mut centre, mut footprint) = (0f32, 0f32);
        for (g, w) in got.iter().zip(&want) {
            centre = centre.max(g.centre.position_world.distance(w.centre.position_world));
            let d = (g.projector.half_extent - w.projector.half_extent).abs();
            footprint = footprint.max(d.max_element());
        }
        Ok(Some(serde_json::json!({
            "tracked_seeded_on_gpu": seeded,
            "tracked_seeds": tracked.seeds.len(),
            "tracked_peaks_gpu": solved.peaks.as_ref().map_or(0, Vec::len),
            "tracked_peaks_cpu": cpu_peaks,
            "tracked_highlights": want.len(),
            "tracked_highlights_same": same,
            "tracked_centre_error_of_radius": centre / radius,
            "tracked_footprint_error_of_radius": footprint / radius,
        })))
    }
}
