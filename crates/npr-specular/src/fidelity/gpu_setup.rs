//! The GPU setup of [`super::FidelityRig::score_with`] and
//! [`super::turntable_coherence_with`]: the measured frames made wholly on the GPU, as
//! `npr` makes them on the GPU backend ([`GpuSetup::whole_frame`]).

use crate::snapshot::{FrameResources, HighlightScene, Renderer};
use crate::{HighlightSet, SpecularError, gpu::FrameOnGpu};
use glam::Mat4;
use npr_geometry::LightEye;

/// How many times a frame the GPU held for want of seeds' room is made again (each time
/// with twice the room) before the measure gives up on it.
const HELD_RETRIES: usize = 4;

/// The GPU setup of the measured frames: the whole frame's highlights, projectors
/// included, made and drawn on the GPU ([`FrameOnGpu`]). One per set and render mesh.
#[derive(Debug)]
pub struct GpuSetup {
    on_gpu: Box<FrameOnGpu>,
    /// The light, eye and transform of the last update (each highlight render makes that
    /// frame again on the GPU and draws what it made).
    last: Option<(LightEye, Mat4)>,
    /// The render triangles' face ids, to read the walk's stream back as faces.
    face_of: std::collections::HashMap<[u32; 3], u32>,
    resources: Option<FrameResources>,
    frame: npr_gpu::FrameId,
    /// Poses made on the GPU ([`GpuSetup::pose_on_gpu`]).
    posing: Option<Box<Posing>>,
}

/// The posed vertex buffer and its curvature, for whole frames of a moving mesh.
#[derive(Debug)]
struct Posing {
    mesh: npr_gpu::GpuMesh,
    pass: npr_gpu::CurvaturePass,
    curvature: npr_gpu::CurvatureObject,
}

impl GpuSetup {
    /// Uploads `set`'s tables for whole frames on the GPU ([`FrameOnGpu`], drawing
    /// textures none of which is a normal map, as [`super::FidelityRig`]'s): each update
    /// makes the frame on the GPU, waits for it and adopts its highlights
    /// ([`HighlightSet::adopt_gpu_frame`]: the ids, centres, footprints, fades, peaks and
    /// pieces the GPU made), and each highlight render makes that frame again (from the
    /// same table: its fades not advanced) and draws the projectors the GPU built.
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::MeshTooLarge`] where a table exceeds the device's bindings.
    pub fn whole_frame(
        device: &wgpu::Device,
        set: &HighlightSet,
        indices: &[u32],
    ) -> Result<Self, SpecularError> {
        let mut on_gpu = FrameOnGpu::new(device, set, indices)?;
        on_gpu.set_normal_maps(&[false]);
        Ok(Self {
            on_gpu: Box::new(on_gpu),
            last: None,
            face_of: indices
                .chunks_exact(3)
                .enumerate()
                .map(|(f, t)| ([t[0], t[1], t[2]], f as u32))
                .collect(),
            resources: None,
            frame: npr_gpu::FrameId::default(),
            posing: None,
        })
    }

    /// Makes this whole-frame setup's poses on the GPU, as npr's `search = "gpu-frame"`
    /// makes an animated model's: each [`GpuSetup::update_pose`] writes the pose into a
    /// vertex buffer of `rest` (the mesh `set` was built on), measures its curvature there
    /// (`npr_gpu::CurvaturePass` at [`npr_gpu::POSE_REACH`], `options`' radius) and makes
    /// its tables there ([`FrameOnGpu::pose_on_gpu`]); `set` is not reposed.
    ///
    /// # Errors
    /// The passes' errors.
    pub fn pose_on_gpu(
        &mut self,
        device: &wgpu::Device,
        set: &HighlightSet,
        (rest, options): (&npr_geometry::Mesh, &npr_geometry::CurvatureOptions),
    ) -> Result<(), SpecularError> {
        let on_gpu = &mut self.on_gpu;
        let mesh = npr_gpu::GpuMesh::upload(device, rest)?;
        let pass = npr_gpu::CurvaturePass::new(device);
        let curvature = pass.create_object_with_reach(
            device,
            &mesh,
            rest,
            options.radius,
            npr_gpu::POSE_REACH,
        )?;
        on_gpu.pose_on_gpu(device, set, (rest, &mesh), &curvature)?;
        self.posing = Some(Box::new(Posing {
            mesh,
            pass,
            curvature,
        }));
        Ok(())
    }

    /// [`GpuSetup::update`] for `pose` (of the rest mesh given to
    /// [`GpuSetup::pose_on_gpu`], same triangles), its tables made on the GPU first.
    ///
    /// # Errors
    /// [`SpecularError::Mismatch`] without [`GpuSetup::pose_on_gpu`]; a pose of other
    /// vertices; as [`GpuSetup::update`].
    pub fn update_pose(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &mut HighlightSet,
        pose: &npr_geometry::Mesh,
        frame: (LightEye, Mat4),
    ) -> Result<(), SpecularError> {
        let posing = self.posing.as_ref().ok_or_else(|| {
            SpecularError::Mismatch("no poses on the GPU (GpuSetup::pose_on_gpu)".into())
        })?;
        posing.mesh.write_vertices(queue, pose)?;
        self.update_with(device, queue, set, frame, true)
    }

    /// Updates `set` for this light, eye and transform on the GPU: the frame made on the
    /// GPU from the table of the last (from `set` where it starts a new sequence), waited
    /// for and adopted.
    ///
    /// # Errors
    /// The passes', or their readbacks'; [`SpecularError::GpuFrame`] for a whole frame the
    /// GPU held every time it was made.
    pub fn update(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &mut HighlightSet,
        frame: (LightEye, Mat4),
    ) -> Result<(), SpecularError> {
        self.update_with(device, queue, set, frame, false)
    }

    /// [`GpuSetup::update`], a new pose's tables made first where `posed`.
    fn update_with(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &mut HighlightSet,
        (light_eye, world_from_object): (LightEye, Mat4),
        posed: bool,
    ) -> Result<(), SpecularError> {
        let frame = (light_eye, world_from_object);
        let on_gpu = &mut self.on_gpu;
        if !set.is_tracking() {
            on_gpu.start_from(queue, set, world_from_object);
        }
        self.last = Some(frame);
        let mut posing = self.posing.as_deref_mut().filter(|_| posed);
        for _ in 0..HELD_RETRIES {
            self.frame = self.frame.next();
            let pose = posing.as_deref_mut();
            make_frame(on_gpu, (device, queue), set, (frame, self.frame), pose)?;
            let status = on_gpu.latest().map(|f| f.status);
            if status != Some(crate::gpu::GpuFrameStatus::Held) {
                break;
            }
        }
        // What the GPU drew, as it drew it (a frame cut short too); a frame it held every
        // time is no frame to measure.
        match on_gpu.latest() {
            Some(f) if f.status != crate::gpu::GpuFrameStatus::Held => set.adopt_gpu_frame(f),
            _ => return Err(SpecularError::GpuFrame(crate::gpu::GpuFrameStatus::Held)),
        }
        Ok(())
    }

    /// [`super::stretch_max`] of the projectors the GPU builds for the last update's
    /// frame, over the faces it walks for them (read back: a measure, not a frame); 0
    /// before any update.
    ///
    /// # Errors
    /// The walk's, or its readback's.
    pub fn stretch_max(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &HighlightSet,
    ) -> Result<f32, SpecularError> {
        self.frame = self.frame.next();
        let Some(frame) = self.last else {
            return Ok(0.0);
        };
        let on_gpu = &mut self.on_gpu;
        on_gpu.repeat_last_frame();
        let walked = make_frame(on_gpu, (device, queue), set, (frame, self.frame), None)?;
        let records = on_gpu
            .latest()
            .map(|f| f.projectors.clone())
            .unwrap_or_default();
        let read = on_gpu.receivers().read(device, queue, &walked)?;
        let lists = faces_of(&self.face_of, &read.stream, records.len());
        let drawn = records.iter().zip(lists).map(|(r, faces)| {
            let n = r.normal;
            (glam::Vec3::new(n[0], n[1], n[2]), r.axis_u[3], faces)
        });
        Ok(super::stretch_of(set, frame.1, drawn))
    }

    /// Renders `scene` with `renderer` and reads it back: the frame of the last update
    /// made again on the GPU (with `scene.set`'s settings and controls) and its
    /// projectors drawn; `scene.set`'s own highlights before any update.
    ///
    /// # Errors
    /// The passes' errors, or readback failure.
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        renderer: &Renderer,
        scene: &HighlightScene<'_>,
    ) -> Result<image::RgbaImage, SpecularError> {
        let res = self
            .resources
            .get_or_insert_with(|| renderer.resources(device, scene.mesh));
        // One frame count for every pass of the setup, the draw's included.
        res.frame = self.frame;
        match self.last {
            Some((light_eye, _)) => {
                // The update's frame again, not the next one: its fades as it left them.
                self.on_gpu.repeat_last_frame();
                let frame_gpu = (&mut *self.on_gpu, light_eye);
                renderer.submit_frame_on_gpu(device, queue, scene, res, frame_gpu)?;
            }
            None => renderer.submit(device, queue, scene, res)?,
        }
        self.frame = res.frame;
        Ok(npr_gpu::readback_rgba(
            device,
            queue,
            &renderer.target().color,
        )?)
    }
}

/// A walk's stream (per triangle corner: the vertex, and at the first corner the
/// projector's index) as each of `count` projectors' faces (`face_of`: the render
/// triangles' face ids).
fn faces_of(
    face_of: &std::collections::HashMap<[u32; 3], u32>,
    stream: &[[u32; 2]],
    count: usize,
) -> Vec<Vec<u32>> {
    let mut lists = vec![Vec::new(); count];
    for t in stream.chunks_exact(3) {
        if let (Some(list), Some(&f)) = (
            lists.get_mut(t[0][1] as usize),
            face_of.get(&[t[0][0], t[1][0], t[2][0]]),
        ) {
            list.push(f);
        }
    }
    lists
}

/// Makes `frame` (light and eye, transform; frame count) on the GPU in a submission of its
/// own, after `pose`'s curvature and tables where given, and waits for it to be read back
/// ([`FrameOnGpu::latest`]); returns its receivers' prepare.
fn make_frame(
    on_gpu: &mut FrameOnGpu,
    (device, queue): (&wgpu::Device, &wgpu::Queue),
    set: &HighlightSet,
    (frame, id): ((LightEye, Mat4), npr_gpu::FrameId),
    pose: Option<&mut Posing>,
) -> Result<npr_gpu::Prepared, SpecularError> {
    // A frame still on its way back (another thread's poll may finish it) is read
    // first, so that the read this frame asks for is its own.
    on_gpu.wait_for_read(device)?;
    let mut encoder = device.create_command_encoder(&Default::default());
    if let Some(p) = pose {
        let input = npr_gpu::CurvatureInput { frame: id };
        let measured = p.pass.prepare(queue, &mut p.curvature, &input)?;
        p.pass.record(&mut encoder, &p.curvature, &measured)?;
        on_gpu.record_pose(queue, &mut encoder, id)?;
    }
    let walked = on_gpu.record(queue, &mut encoder, set, frame, id)?;
    queue.submit([encoder.finish()]);
    on_gpu.read_after_submit(device, queue);
    on_gpu.wait_for_read(device)?;
    Ok(walked)
}
