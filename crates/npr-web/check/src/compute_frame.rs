//! The browser check's frames made wholly on the GPU (`npr_specular::gpu::FrameOnGpu`: the
//! search with its peaks, the regions seeded on the GPU's own table of the last frame,
//! `cs_replace`, the projectors built by `cs_project`, the receivers walked from them),
//! on a mesh that sways (`generate::swaying`), each pose written into the vertex buffer
//! and taken on the GPU (`CurvaturePass` at `POSE_REACH`, `FrameOnGpu::record_pose`),
//! frame after frame with nothing read back between, each read back as the page must
//! (mapped, polled over animation frames) and compared with the CPU's repose and update of
//! the same frame: the same highlights (ids, found, peaks, opacities), centres, and
//! records for the highlight pass.

use glam::{Mat4, Vec3};
use npr_geometry::animation::Rig;
use npr_geometry::{CurvatureOptions, LightEye, Mesh};
use npr_gpu::{CurvatureObject, CurvaturePass, FrameId, GpuMesh};
use npr_specular::{HighlightSet, gpu::FrameOnGpu, gpu::projector_gpu};

/// Frames the check makes.
const FRAMES: usize = 4;

/// Frame `k`: a point light turning over the knot, which turns too.
fn frame(k: usize) -> (LightEye, Mat4) {
    let a = 0.15 * k as f32;
    (
        LightEye::Positions {
            light: Vec3::new(2.0 * a.cos() + 0.5, 3.0, 2.5 * a.sin() + 1.5),
            eye: Vec3::new(0.0, 0.5, 4.0),
        },
        Mat4::from_rotation_y(0.4 + 0.05 * k as f32) * Mat4::from_rotation_x(-0.5),
    )
}

/// The frames on their way.
pub struct FrameCheck {
    radius: f32,
    /// The swaying mesh, its upload and its curvature on the GPU.
    rig: Rig,
    gpu_mesh: GpuMesh,
    curvature: (CurvaturePass, CurvatureObject),
    cpu: HighlightSet,
    gpu: HighlightSet,
    on_gpu: FrameOnGpu,
    /// Frames recorded and compared so far.
    recorded: usize,
    compared: usize,
    same: bool,
    highlights: usize,
    peaks: usize,
    centre: f32,
    gap: f32,
    /// The first frame that differs, told in words.
    first_difference: Option<String>,
    /// The device's validation errors while the frames are recorded.
    errors: Vec<std::pin::Pin<Box<dyn std::future::Future<Output = Option<wgpu::Error>>>>>,
}

impl FrameCheck {
    /// The sets and the GPU's passes, and the first frame recorded and submitted.
    ///
    /// # Errors
    /// A GPU or highlight error, as one line.
    pub fn start(device: &wgpu::Device, queue: &wgpu::Queue, mesh: &Mesh) -> Result<Self, String> {
        let options = CurvatureOptions::default();
        let rigged = npr_geometry::generate::swaying(mesh.clone());
        let mesh = &rigged.mesh;
        let cpu = HighlightSet::new(mesh, &options).map_err(|e| e.to_string())?;
        let gpu = HighlightSet::new(mesh, &options).map_err(|e| e.to_string())?;
        let mut on_gpu = FrameOnGpu::new(device, &gpu, &mesh.indices).map_err(|e| e.to_string())?;
        let gpu_mesh = GpuMesh::upload(device, mesh).map_err(|e| e.to_string())?;
        let pass = CurvaturePass::new(device);
        let object = pass
            .create_object_with_reach(device, &gpu_mesh, mesh, options.radius, npr_gpu::POSE_REACH)
            .map_err(|e| e.to_string())?;
        on_gpu
            .pose_on_gpu(device, &gpu, (mesh, &gpu_mesh), &object)
            .map_err(|e| e.to_string())?;
        let mut check = Self {
            radius: bounding_radius(mesh),
            rig: rigged.rig,
            gpu_mesh,
            curvature: (pass, object),
            cpu,
            gpu,
            on_gpu,
            recorded: 0,
            compared: 0,
            same: true,
            highlights: 0,
            peaks: 0,
            centre: 0.0,
            gap: 0.0,
            first_difference: None,
            errors: Vec::new(),
        };
        check.record(device, queue)?;
        Ok(check)
    }

    fn record(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<(), String> {
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder = device.create_command_encoder(&Default::default());
        let k = self.recorded;
        let frame_id = FrameId(k as u64 + 1);
        let posed = self.pose(k);
        self.gpu_mesh
            .write_vertices(queue, &posed)
            .map_err(|e| e.to_string())?;
        let (pass, object) = &mut self.curvature;
        let measured = pass
            .prepare(queue, object, &npr_gpu::CurvatureInput { frame: frame_id })
            .map_err(|e| e.to_string())?;
        pass.record(&mut encoder, object, &measured)
            .map_err(|e| e.to_string())?;
        self.on_gpu
            .record_pose(queue, &mut encoder, frame_id)
            .map_err(|e| e.to_string())?;
        self.on_gpu
            .record(queue, &mut encoder, &self.gpu, frame(k), frame_id)
            .map_err(|e| e.to_string())?;
        queue.submit([encoder.finish()]);
        self.on_gpu.read_after_submit(device, queue);
        self.errors.push(Box::pin(scope.pop()));
        self.recorded += 1;
        Ok(())
    }

    /// Pose `k` of the sway (a tenth of its clip apart).
    fn pose(&self, k: usize) -> Mesh {
        let clip = &self.rig.clips()[0];
        let t = clip.duration() * (0.1 * k as f32 + 0.05);
        self.rig.pose_mesh(&self.rig.sample(clip, t))
    }

    /// The report once every frame has been read back and compared (`None` before).
    ///
    /// # Errors
    /// A GPU error, as one line.
    pub fn poll(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<serde_json::Value>, String> {
        let mut waker = std::task::Context::from_waker(std::task::Waker::noop());
        for e in &mut self.errors {
            if let std::task::Poll::Ready(Some(error)) = e.as_mut().poll(&mut waker) {
                return Err(format!("a frame made on the GPU: {error}"));
            }
        }
        if self.compared < self.recorded && self.on_gpu.frames_read() as usize > self.compared {
            let (light_eye, world) = frame(self.compared);
            let posed = self.pose(self.compared);
            self.cpu
                .repose(&posed, &CurvatureOptions::default())
                .map_err(|e| e.to_string())?;
            self.cpu.update(light_eye, world);
            let got = self.on_gpu.latest().cloned().ok_or("no frame read back")?;
            let want: Vec<_> = self
                .cpu
                .highlights()
                .iter()
                .filter(|h| h.piece == 0)
                .collect();
            let same = got.highlights.len() == want.len()
                && got.projectors.len() == self.cpu.highlights().len()
                && got.highlights.iter().zip(&want).all(|(g, w)| {
                    (g.id, g.found, g.peak, g.pieces) == (w.id, w.found, w.peak, w.pieces)
                        && (g.opacity - w.opacity).abs() <= 1e-5
                });
            if !same && self.first_difference.is_none() {
                let tell = |v: Vec<(u64, bool, bool, u8, f32)>| format!("{v:?}");
                self.first_difference = Some(format!(
                    "frame {} ({:?}): the GPU's {} projectors, (id, found, peak, pieces, \
                     opacity) {}; the CPU's {} projectors, {}",
                    self.compared,
                    got.status,
                    got.projectors.len(),
                    tell(
                        got.highlights
                            .iter()
                            .map(|g| (g.id, g.found, g.peak, g.pieces, g.opacity))
                            .collect()
                    ),
                    self.cpu.highlights().len(),
                    tell(
                        want.iter()
                            .map(|w| (w.id, w.found, w.peak, w.pieces, w.opacity))
                            .collect()
                    ),
                ));
            }
            self.same &= same;
            for (g, w) in got.highlights.iter().zip(&want) {
                let d = g.centre.position_world.distance(w.centre.position_world);
                self.centre = self.centre.max(d / self.radius.max(f32::MIN_POSITIVE));
            }
            // The records of the wholes (pieces are cut a patch at a time by the set's
            // grower, `tests/gpu_projectors.rs`).
            for (g, h) in got.projectors.iter().zip(self.cpu.highlights()) {
                if h.piece != 0 {
                    continue;
                }
                let w = projector_gpu(h, h.controls.texture_layer.min(7), false);
                let m = |p: &npr_specular::gpu::ProjectorGpu| p.tex_from_world.concat();
                let scale = m(&w).iter().fold(1e-12f32, |s, x| s.max(x.abs()));
                let gap = m(g)
                    .iter()
                    .zip(m(&w))
                    .fold(0f32, |s, (a, b)| s.max((a - b).abs() / scale));
                self.gap = self.gap.max(gap);
            }
            self.highlights += want.len();
            self.peaks += want.iter().filter(|h| h.peak).count();
            self.compared += 1;
            if self.recorded < FRAMES {
                self.record(device, queue)?;
            }
        }
        if self.compared < FRAMES {
            return Ok(None);
        }
        Ok(Some(serde_json::json!({
            "frame_frames": self.compared,
            "frame_highlights": self.highlights,
            "frame_peaks": self.peaks,
            "frame_highlights_same": self.same,
            "frame_centre_error_of_radius": self.centre,
            "frame_record_gap": self.gap,
            "frame_first_difference": self.first_difference,
        })))
    }
}

/// The largest distance of a vertex from the centre of the mesh's bounding box.
fn bounding_radius(mesh: &Mesh) -> f32 {
    let (lo, hi) = mesh.positions.iter().fold(
        (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let c = 0.5 * (lo + hi);
    mesh.positions
        .iter()
        .map(|p| p.distance(c))
        .fold(0.0, f32::max)
}
