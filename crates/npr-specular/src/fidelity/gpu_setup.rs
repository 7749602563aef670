//! The GPU setup of [`super::FidelityRig::score_with`] and
//! [`super::turntable_coherence_with`]: the measured frames set up as `npr` sets them up
//! with `[specular] search = "gpu"`.

use super::stretch_over;
use crate::snapshot::{FrameResources, HighlightScene, Renderer};
use crate::{HighlightSet, ReceiverObject, ReceiverPass, SetupOnGpu, SpecularError};
use glam::Mat4;
use npr_geometry::LightEye;

/// The GPU setup of the measured frames: the `N = H` search and the regions on the GPU
/// in one submission ([`SetupOnGpu`]), and the §4.2 receivers walked by [`ReceiverPass`]
/// in each highlight frame's submission and drawn from their stream. One per set and
/// render mesh.
#[derive(Debug)]
pub struct GpuSetup {
    setup: SetupOnGpu,
    walk_pass: ReceiverPass,
    walk: ReceiverObject,
    /// The render triangles' face ids, to read the walk's stream back as faces.
    face_of: std::collections::HashMap<[u32; 3], u32>,
    resources: Option<FrameResources>,
    frame: npr_gpu::FrameId,
}

impl GpuSetup {
    /// Uploads `set`'s search and walk tables (`indices`: the render mesh's triangles).
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::MeshTooLarge`] where a table exceeds the device's bindings.
    pub fn new(
        device: &wgpu::Device,
        set: &HighlightSet,
        indices: &[u32],
    ) -> Result<Self, SpecularError> {
        let walk_pass = ReceiverPass::new(device);
        // Walks of up to four times the default capacity (the whole mesh where smaller).
        let longest = (4 * crate::DEFAULT_WALK_CAPACITY).min(set.topology().face_count());
        Ok(Self {
            setup: SetupOnGpu::new(device, set)?,
            walk: walk_pass.create_object_with_capacity(device, set, indices, longest)?,
            walk_pass,
            face_of: indices
                .chunks_exact(3)
                .enumerate()
                .map(|(f, t)| ([t[0], t[1], t[2]], f as u32))
                .collect(),
            resources: None,
            frame: npr_gpu::FrameId::default(),
        })
    }

    /// Updates `set` for this light, eye and transform on the GPU ([`SetupOnGpu::update`]),
    /// the receivers left to the GPU walk (the CPU search's where the list overflowed or
    /// the mesh does not fit).
    ///
    /// # Errors
    /// The passes', or their readbacks'.
    pub fn update(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &mut HighlightSet,
        (light_eye, world_from_object): (LightEye, Mat4),
    ) -> Result<(), SpecularError> {
        set.receivers_on_gpu = true;
        let frame = (light_eye, world_from_object);
        if self.setup.update((device, queue), set, frame)?.is_none() {
            set.update(light_eye, world_from_object);
        }
        Ok(())
    }

    /// [`super::stretch_max`] of `set`'s highlights over the faces the GPU walks for them (read
    /// back: a measure, not a frame).
    ///
    /// # Errors
    /// The walk's, or its readback's.
    pub fn stretch_max(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &HighlightSet,
        world_from_object: Mat4,
    ) -> Result<f32, SpecularError> {
        self.frame = self.frame.next();
        let input = crate::ReceiverInput {
            frame: self.frame,
            set,
            world_from_object,
        };
        let prepared = self.walk_pass.prepare(queue, &mut self.walk, &input)?;
        let mut encoder = device.create_command_encoder(&Default::default());
        self.walk_pass.record(&mut encoder, &self.walk, &prepared)?;
        queue.submit([encoder.finish()]);
        let read = self.walk.read(device, queue, &prepared)?;
        let mut lists = vec![Vec::new(); set.highlights().len()];
        for t in read.stream.chunks_exact(3) {
            if let (Some(list), Some(&f)) = (
                lists.get_mut(t[0][1] as usize),
                self.face_of.get(&[t[0][0], t[1][0], t[2][0]]),
            ) {
                list.push(f);
            }
        }
        Ok(stretch_over(set, world_from_object, |k| lists[k].clone()))
    }

    /// Renders `scene` with `renderer`, its receivers walked on the GPU, and reads it
    /// back.
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
        renderer.submit_gpu_receivers(
            device,
            queue,
            scene,
            res,
            (&self.walk_pass, &mut self.walk),
        )?;
        Ok(npr_gpu::readback_rgba(
            device,
            queue,
            &renderer.target().color,
        )?)
    }
}
