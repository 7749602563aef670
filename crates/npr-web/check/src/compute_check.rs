//! The compute passes in the browser, against the CPU on the same frame: the curvature
//! tensor (`npr_gpu::CurvaturePass`), the `N = H` search (`npr_specular::gpu::CentreSearchPass`),
//! the regions `N·H ≥ σ` and their moment ellipses (`npr_specular::gpu::RegionPass`) and the §4.2
//! receivers (`npr_specular::gpu::ReceiverPass`) on a torus, and frames made wholly on the GPU
//! ([`crate::compute_frame`]) on a knot, on the page's own WebGPU device. Started by `ComputeCheck::start`,
//! read back over the next animation frames (a map completes only once control returns
//! to the page), and reported by `ComputeCheck::result` as JSON for the browser
//! check (`cargo xtask web --check`).

use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureField, CurvatureOptions, CurvatureRadius, LightEye, Mesh, generate};
use npr_gpu::{BufferReadback, CurvatureInput, CurvatureObject, CurvaturePass, FrameId, GpuMesh};
use npr_specular::cpu::region::{Region, RegionFrame, RegionGrower, RegionPatches};
use npr_specular::{
    HighlightPass, HighlightSet, ProjectorControls, gpu::CentreSearchPass, gpu::GpuRegion,
    gpu::PendingReceivers, gpu::PendingRegions, gpu::PendingSolutions, gpu::ReceiverInput,
    gpu::ReceiverPass, gpu::ReceiverReadback, gpu::RegionInput, gpu::RegionPass, gpu::SearchInput,
};
use std::collections::HashSet;

/// The light and eye of the check's search: a point light and eye under a turn (the
/// shader's object-space half vector per vertex).
fn light_eye() -> (LightEye, Mat4) {
    (
        LightEye::Positions {
            light: Vec3::new(2.0, 3.0, 2.5),
            eye: Vec3::new(0.0, 0.5, 4.0),
        },
        Mat4::from_rotation_y(0.4) * Mat4::from_rotation_x(-0.5),
    )
}

/// The check on its way: the GPU's field and list being read back.
pub struct ComputeCheck {
    mesh: Mesh,
    set: HighlightSet,
    curvature: CurvatureObject,
    field: BufferReadback,
    search: PendingSolutions,
    receivers: PendingReceivers,
    regions: PendingRegions,
    seeds: Vec<(npr_geometry::HighlightCentre, f32)>,
    field_bytes: Option<Vec<u8>>,
    solutions: Option<npr_specular::gpu::SearchSolutions>,
    walked: Option<ReceiverReadback>,
    grown: Option<Vec<GpuRegion>>,
    frames: crate::compute_frame::FrameCheck,
    frames_report: Option<serde_json::Value>,
}

impl ComputeCheck {
    /// Records and submits both passes on a torus and asks for the maps.
    ///
    /// # Errors
    /// A GPU or highlight error, as one line.
    pub fn start(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Self, String> {
        let mesh = generate::torus(1.0, 0.35, 48, 24);
        let gpu = GpuMesh::upload(device, &mesh).map_err(|e| e.to_string())?;
        let pass = CurvaturePass::new(device);
        let mut curvature = pass
            .create_object(device, &gpu, &mesh, CurvatureRadius::default())
            .map_err(|e| e.to_string())?;
        let frame = FrameId(1);
        let prepared = pass
            .prepare(queue, &mut curvature, &CurvatureInput { frame })
            .map_err(|e| e.to_string())?;
        let mut set =
            HighlightSet::new(&mesh, &CurvatureOptions::default()).map_err(|e| e.to_string())?;
        let search_pass = CentreSearchPass::new(device);
        let mut search = search_pass
            .create_object(device, set.search())
            .map_err(|e| e.to_string())?;
        let (light_eye, world_from_object) = light_eye();
        let input = SearchInput {
            frame,
            search: set.search(),
            light_eye,
            world_from_object,
        };
        let searched = search_pass
            .prepare(queue, &mut search, &input)
            .map_err(|e| e.to_string())?;
        // The CPU update (its receivers the reference), then the GPU walk of its highlights.
        set.update(light_eye, world_from_object);
        let walk_pass = ReceiverPass::new(device);
        let mut walk = walk_pass
            .create_object(device, &set, &mesh.indices)
            .map_err(|e| e.to_string())?;
        let walk_input = ReceiverInput {
            frame,
            set: &set,
            world_from_object,
        };
        let walked = walk_pass
            .prepare(queue, &mut walk, &walk_input)
            .map_err(|e| e.to_string())?;
        // The regions of the CPU search's centres, at the default σ.
        let sigma = ProjectorControls::default().sigma;
        let seeds: Vec<_> = set
            .search()
            .find(light_eye, world_from_object)
            .into_iter()
            .map(|c| (c, sigma))
            .collect();
        let region_pass = RegionPass::new(device);
        let mut regions = region_pass
            .create_object(device, &set)
            .map_err(|e| e.to_string())?;
        let region_input = RegionInput {
            frame,
            set: &set,
            seeds: &seeds,
            light_eye,
            world_from_object,
        };
        let grown = region_pass
            .prepare(queue, &mut regions, &region_input)
            .map_err(|e| e.to_string())?;
        let mut encoder = device.create_command_encoder(&Default::default());
        pass.record(&mut encoder, &curvature, &prepared)
            .map_err(|e| e.to_string())?;
        search_pass
            .record(&mut encoder, &search, &searched)
            .map_err(|e| e.to_string())?;
        walk_pass
            .record(&mut encoder, &walk, &walked)
            .map_err(|e| e.to_string())?;
        region_pass
            .record(&mut encoder, &regions, &grown)
            .map_err(|e| e.to_string())?;
        let size = curvature.output().size();
        let copy = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("npr compute check"),
            size,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_buffer_to_buffer(curvature.output(), 0, &copy, 0, size);
        queue.submit([encoder.finish()]);
        let pending = search.map(&searched).map_err(|e| e.to_string())?;
        let receivers = walk
            .map(device, queue, &walked)
            .map_err(|e| e.to_string())?;
        let regions = regions
            .map(device, queue, &grown)
            .map_err(|e| e.to_string())?;
        let frames =
            crate::compute_frame::FrameCheck::start(device, queue, &generate::paper_knot())?;
        Ok(Self {
            frames,
            frames_report: None,
            mesh,
            set,
            curvature,
            field: BufferReadback::map(copy),
            search: pending,
            receivers,
            regions,
            seeds,
            field_bytes: None,
            solutions: None,
            walked: None,
            grown: None,
        })
    }

    /// The report once both maps have completed (`None` before): the curvature's worst
    /// differences from the CPU field, and the centres of both searches.
    ///
    /// # Errors
    /// A failed map, as one line.
    pub fn poll(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<serde_json::Value>, String> {
        if self.frames_report.is_none() {
            self.frames_report = self.frames.poll(device, queue)?;
        }
        if self.field_bytes.is_none() {
            if let Some(bytes) = self.field.try_take() {
                self.field_bytes = Some(bytes.map_err(|e| e.to_string())?);
            }
        }
        if self.solutions.is_none() {
            if let Some(list) = self.search.try_take() {
                let list = list.map_err(|e| e.to_string())?;
                if !list.complete() {
                    return Err(format!(
                        "the search list overflowed: {} faces",
                        list.accepted
                    ));
                }
                self.solutions = Some(list);
            }
        }
        if self.walked.is_none() {
            if let Some(walked) = self.receivers.try_take() {
                self.walked = Some(walked.map_err(|e| e.to_string())?);
            }
        }
        if self.grown.is_none() {
            if let Some(grown) = self.regions.try_take() {
                self.grown = Some(grown.map_err(|e| e.to_string())?);
            }
        }
        let (Some(bytes), Some(solutions), Some(walked), Some(grown), Some(frames)) = (
            &self.field_bytes,
            &self.solutions,
            &self.walked,
            &self.grown,
            &self.frames_report,
        ) else {
            return Ok(None);
        };
        let (_, _, cpu) = CurvatureField::for_mesh(&self.mesh, &CurvatureOptions::default());
        let field = cpu.difference(&self.curvature.decode(bytes));
        let (light_eye, world_from_object) = light_eye();
        let want = self.set.search().find(light_eye, world_from_object);
        // The centres the GPU merged and computed (`cs_merge`, `cs_centres`), and the
        // CPU's merge of the same faces, which they must equal entry for entry.
        let search = self.set.search();
        let merged = solutions
            .centres
            .as_deref()
            .ok_or("the search's centres were not merged on the GPU")?;
        let got = merged.to_vec();
        let cpu_merge = search.centres_from_solutions(&solutions.faces, world_from_object);
        let merge_differs = got.len().abs_diff(cpu_merge.len())
            + got
                .iter()
                .zip(&cpu_merge)
                .filter(|(a, b)| (a.face, a.alpha, a.beta) != (b.face, b.alpha, b.beta))
                .count();
        let worst = want
            .iter()
            .map(|c| {
                got.iter()
                    .map(|d| d.position_object.distance(c.position_object))
                    .fold(f32::INFINITY, f32::min)
            })
            .fold(0.0, f32::max);
        // The torus's bounding radius: its major plus its minor radius.
        let radius = 1.35;
        // (highlight, render triangle) of each received face, CPU and GPU.
        let faces = |stream: &[[u32; 2]]| -> HashSet<(u32, [u32; 3])> {
            stream
                .chunks_exact(3)
                .map(|t| (t[0][1], [t[0][0], t[1][0], t[2][0]]))
                .collect()
        };
        let cpu_faces = faces(&HighlightPass::draw_list(&self.set, &self.mesh.indices));
        let gpu_faces = faces(&walked.stream);
        let both = cpu_faces.intersection(&gpu_faces).count();
        let either = cpu_faces.union(&gpu_faces).count();
        let regions = self.compare_regions(grown, light_eye, world_from_object, radius);
        let mut report = serde_json::json!({
            "curvature_kappa_error": field.kappa,
            "curvature_direction_error_deg": field.direction_deg,
            "curvature_normal_error_deg": field.normal_deg,
            "curvature_validity_differences": field.validity,
            "curvature_vertices": field.vertices,
            "centres_cpu": want.len(),
            "centres_gpu": got.len(),
            "centre_error_of_radius": worst / radius,
            "centres_merge_differs": merge_differs,
            "centres_accepted_faces": solutions.faces.len(),
            "receivers_cpu_faces": cpu_faces.len(),
            "receivers_gpu_faces": gpu_faces.len(),
            "receivers_agreement": both as f64 / either.max(1) as f64,
            "receivers_overflowed": walked.counts.iter().filter(|c| c.overflowed).count(),
            "regions_seeds": self.seeds.len(),
            "regions_cpu_fitted": regions.0,
            "regions_outcomes_differ": regions.1,
            "regions_centre_error_of_radius": regions.2,
            "regions_area_error": regions.3,
            "regions_overflowed": grown.iter().filter(|g| g.overflowed).count(),
        });
        if let (Some(all), Some(more)) = (report.as_object_mut(), frames.as_object()) {
            all.extend(more.clone());
        }
        Ok(Some(report))
    }

    /// The GPU's regions against the CPU growth of the same seeds: regions the CPU
    /// fitted, seeds whose outcome or faces differ, and the worst ellipse centre (of the
    /// radius) and relative area of the others.
    fn compare_regions(
        &self,
        grown: &[GpuRegion],
        light_eye: LightEye,
        world_from_object: Mat4,
        radius: f32,
    ) -> (usize, usize, f32, f32) {
        let (topology, normals) = (self.set.topology(), self.set.search().normals());
        let mut grower = RegionGrower::with_patches(RegionPatches::new(topology, normals));
        let frame = RegionFrame {
            topology,
            normals,
            world_from_object,
            light_eye,
        };
        let cpu = grower.grow_all(&frame, &self.seeds);
        let (mut fitted, mut differ, mut centre, mut area) = (0, 0, 0f32, 0f32);
        for (k, c) in cpu.iter().enumerate() {
            let g = grown.get(k).map(|g| g.region);
            match (c, g) {
                (Region::Fit(a, fa), Some(Region::Fit(b, fb))) if *fa == fb => {
                    fitted += 1;
                    centre = centre.max(a.offset.distance(b.offset) / radius);
                    let rel =
                        (a.region_area - b.region_area).abs() / a.region_area.abs().max(1e-12);
                    area = area.max(rel);
                }
                (c, Some(g)) if *c == g => {}
                _ => differ += 1,
            }
        }
        (fitted, differ, centre, area)
    }
}
