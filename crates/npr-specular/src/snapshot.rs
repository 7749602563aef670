//! One-call rendering of a mesh with its highlights over a base shading, for tests,
//! demos and tools. It submits and waits; in a real renderer record
//! [`crate::HighlightPass::draw`] into your own pass instead.

use crate::{HighlightPass, HighlightSet, SpecularError};
use npr_gpu::{
    BaseShading, Camera, FrameUniforms, GpuMesh, Light, ObjectUniforms, OffscreenTarget,
    ShadingModel, TargetFormats, readback_rgba,
};

/// Everything [`render`] draws.
#[derive(Debug)]
pub struct HighlightScene<'a> {
    /// The mesh on the GPU.
    pub mesh: &'a GpuMesh,
    /// Its render indices (faces in the order of the set's topology).
    pub indices: &'a [u32],
    /// The highlight set, already updated for this frame.
    pub set: &'a HighlightSet,
    /// Object transform and base material.
    pub object: ObjectUniforms,
    /// Camera.
    pub camera: Camera,
    /// Light.
    pub light: Light,
    /// Base shading model.
    pub base: ShadingModel,
    /// Whether to draw the highlight pass (false gives the base alone).
    pub highlights: bool,
    /// Linear clear colour.
    pub clear: [f64; 4],
}

impl<'a> HighlightScene<'a> {
    /// The highlights alone, on the identity transform over a black base (no ambient,
    /// diffuse or k_s) and a black background: what the highlight tests measure.
    pub fn on_black(
        mesh: &'a GpuMesh,
        indices: &'a [u32],
        set: &'a HighlightSet,
        camera: Camera,
        light: Light,
    ) -> Self {
        Self {
            mesh,
            indices,
            set,
            object: ObjectUniforms::new(
                glam::Mat4::IDENTITY,
                glam::Vec3::ZERO,
                0.0,
                glam::Vec3::ZERO,
                1.0,
            ),
            camera,
            light: Light {
                ambient: glam::Vec3::ZERO,
                ..light
            },
            base: ShadingModel::Phong,
            highlights: true,
            clear: [0.0, 0.0, 0.0, 1.0],
        }
    }
}

/// Per-mesh buffers of [`Renderer::submit`]: the object uniforms and the highlight draw.
#[derive(Debug)]
pub struct FrameResources {
    object: npr_gpu::BaseObject,
    draw: crate::HighlightObject,
    /// The frame count of its last submission.
    pub(crate) frame: npr_gpu::FrameId,
    /// The receiver walk of the last [`Renderer::submit_frame_on_gpu`].
    walked: Option<npr_gpu::Prepared>,
}

impl FrameResources {
    /// The receiver walk of the last frame submitted with
    /// [`Renderer::submit_frame_on_gpu`] (for [`crate::gpu::ReceiverObject::read`] or
    /// [`crate::gpu::ReceiverObject::map_counts`] after it); `None` after a frame without one.
    pub fn walked(&self) -> Option<npr_gpu::Prepared> {
        self.walked
    }
}

/// Reusable GPU state for [`render`] (pipelines, buffers, target).
#[derive(Debug)]
pub struct Renderer {
    base: BaseShading,
    pass: HighlightPass,
    target: OffscreenTarget,
}

impl Renderer {
    /// Creates the pipelines and a `width × height` target.
    ///
    /// # Errors
    /// A bad size or texture set.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        width: u32,
        height: u32,
    ) -> Result<Self, SpecularError> {
        Ok(Self {
            base: BaseShading::new(device, queue, TargetFormats::default(), &Default::default()),
            pass: HighlightPass::new(device, queue, TargetFormats::default(), &Default::default())?,
            target: OffscreenTarget::new(device, width, height)?,
        })
    }

    /// Creates the pipelines with caller highlight textures (as
    /// [`HighlightPass::with_textures`]) and a `width × height` target.
    ///
    /// # Errors
    /// A bad size or texture set.
    pub fn with_textures(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        width: u32,
        height: u32,
        layers: &[image::RgbaImage],
        normal_map: &[bool],
    ) -> Result<Self, SpecularError> {
        Ok(Self {
            base: BaseShading::new(device, queue, TargetFormats::default(), &Default::default()),
            pass: HighlightPass::with_textures(
                device,
                queue,
                TargetFormats::default(),
                layers,
                normal_map,
            )?,
            target: OffscreenTarget::new(device, width, height)?,
        })
    }

    /// The highlight pass.
    pub fn pass(&self) -> &HighlightPass {
        &self.pass
    }

    /// The target.
    pub fn target(&self) -> &OffscreenTarget {
        &self.target
    }

    /// Per-mesh GPU state for [`Renderer::submit`]; create once per mesh and reuse.
    pub fn resources(&self, device: &wgpu::Device, mesh: &GpuMesh) -> FrameResources {
        FrameResources {
            object: self.base.create_object(device, mesh),
            draw: self.pass.create_object(device, mesh),
            frame: npr_gpu::FrameId::default(),
            walked: None,
        }
    }

    /// Records and submits one frame (base + highlights) without reading it back or
    /// waiting. `res` must come from [`Renderer::resources`] for `scene.mesh`.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for resources of another renderer.
    pub fn submit(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &HighlightScene<'_>,
        res: &mut FrameResources,
    ) -> Result<(), SpecularError> {
        self.submit_with(device, queue, scene, res, Walk::Cpu)
    }

    /// [`Renderer::submit`] with the frame's highlights made wholly on the GPU by
    /// `frame_gpu` for `light_eye` (search, regions, projectors, receivers, recorded in
    /// the frame's own submission), nothing read back; `scene.set` gives only the mesh,
    /// settings and controls.
    ///
    /// # Errors
    /// As [`Renderer::submit`], and the passes'.
    pub fn submit_frame_on_gpu(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &HighlightScene<'_>,
        res: &mut FrameResources,
        (frame_gpu, light_eye): (&mut crate::gpu::FrameOnGpu, npr_geometry::LightEye),
    ) -> Result<(), SpecularError> {
        self.submit_with(device, queue, scene, res, Walk::Frame(frame_gpu, light_eye))?;
        Ok(())
    }

    /// [`Renderer::submit`] with the frame's highlights set up by `setup` on its object's
    /// backend for `light_eye` and the scene's transform (`mesh`: the render mesh in its
    /// pose; `scene.set` is not read, the object holds its own), its stages recorded in
    /// the frame's own submission and [`crate::HighlightSetup::after_submit`] called after
    /// it: a frame as an embedder makes it.
    ///
    /// # Errors
    /// As [`Renderer::submit`], and the setup's.
    pub fn submit_setup(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &HighlightScene<'_>,
        res: &mut FrameResources,
        (setup, object, mesh, light_eye): (
            &crate::HighlightSetup,
            &mut crate::SetupObject,
            &npr_geometry::Mesh,
            npr_geometry::LightEye,
        ),
    ) -> Result<(), SpecularError> {
        let walk = Walk::Setup(setup, object, mesh, light_eye);
        self.submit_with(device, queue, scene, res, walk)
    }

    fn submit_with(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &HighlightScene<'_>,
        res: &mut FrameResources,
        mut walk: Walk<'_>,
    ) -> Result<(), SpecularError> {
        res.frame = res.frame.next();
        res.walked = None;
        let view = FrameUniforms::new(&scene.camera, &scene.light);
        let base_input = npr_gpu::BaseInput {
            frame: res.frame,
            view: &view,
            object: &scene.object,
            model: scene.base,
        };
        let base = self.base.prepare(queue, &mut res.object, &base_input)?;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr specular frame"),
        });
        let highlights = if scene.highlights {
            let world_from_object = glam::Mat4::from_cols_array_2d(&scene.object.world_from_object);
            let walked;
            let made = match &mut walk {
                Walk::Frame(frame_gpu, light_eye) => {
                    let frame = (*light_eye, world_from_object);
                    walked = frame_gpu.record(queue, &mut encoder, scene.set, frame, res.frame)?;
                    res.walked = Some(walked);
                    frame_gpu.highlight_frame(scene.set, &walked)?
                }
                Walk::Setup(setup, object, mesh, light_eye) => {
                    let input = crate::SetupInput {
                        frame: res.frame,
                        light_eye: *light_eye,
                        world_from_object,
                        mesh,
                        gpu: scene.mesh,
                    };
                    let prepared = setup.prepare(device, queue, object, &input)?;
                    setup.record(&mut encoder, object, &prepared)?
                }
                Walk::Cpu => crate::HighlightFrame::of_set(res.frame, scene.set, scene.indices),
            };
            let input = crate::HighlightInput {
                frame: res.frame,
                highlights: &made,
                view: &view,
                object: &scene.object,
            };
            Some(self.pass.prepare(queue, &mut res.draw, &input)?)
        } else {
            None
        };
        {
            let mut rpass = self.target.begin_clear_pass(&mut encoder, scene.clear);
            self.base.draw(&mut rpass, &res.object, &base)?;
            if let Some(prepared) = &highlights {
                self.pass.draw(&mut rpass, &res.draw, prepared)?;
            }
        }
        queue.submit(Some(encoder.finish()));
        if let Walk::Setup(setup, object, ..) = &mut walk {
            setup.after_submit(device, queue, object);
        }
        Ok(())
    }

    /// Renders one frame and reads it back.
    ///
    /// # Errors
    /// Readback failure.
    pub fn render(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &HighlightScene<'_>,
    ) -> Result<image::RgbaImage, SpecularError> {
        let mut res = self.resources(device, scene.mesh);
        self.submit(device, queue, scene, &mut res)?;
        Ok(readback_rgba(device, queue, &self.target.color)?)
    }
}

/// Renders `scene` at `width × height` with a fresh [`Renderer`].
///
/// # Errors
/// As [`Renderer::new`] and [`Renderer::render`].
pub fn render(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &HighlightScene<'_>,
    width: u32,
    height: u32,
) -> Result<image::RgbaImage, SpecularError> {
    Renderer::new(device, queue, width, height)?.render(device, queue, scene)
}

/// A light and a camera at the same direction `dir` from the origin (eye at distance
/// `distance`), as `LightEye` for the N = H search and as npr-gpu camera + light.
pub fn light_eye_along(
    dir: glam::Vec3,
    distance: f32,
    aspect: f32,
) -> (npr_geometry::LightEye, Camera, Light) {
    let d = dir.normalize_or(glam::Vec3::Z);
    let camera = Camera::look_at(d * distance, glam::Vec3::ZERO, aspect);
    let light = Light::directional(d);
    (
        npr_geometry::LightEye::Directions {
            to_light: d,
            to_eye: d,
        },
        camera,
        light,
    )
}

/// Where a frame's highlights come from: the set's update on the CPU, made wholly on the
/// GPU, or a setup on its backend.
enum Walk<'a> {
    Cpu,
    Frame(&'a mut crate::gpu::FrameOnGpu, npr_geometry::LightEye),
    Setup(
        &'a crate::HighlightSetup,
        &'a mut crate::SetupObject,
        &'a npr_geometry::Mesh,
        npr_geometry::LightEye,
    ),
}
