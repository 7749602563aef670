//! Reference frames (§3.3, Fig. 4): the full-detail mesh rendered at a reference pose into
//! colour and depth textures, keeping the reference camera's `clip_from_world` and the
//! object's pose so the image can be projected back (§3.3.1).
//!
//! A reference can be rendered at once ([`ReferenceFrame::record`]) or in slices spread over
//! the intermediate frames ([`ReferenceFrame::record_slice`]), as the paper's §3.4 suggests
//! for hiding the reference cost behind a third off-screen buffer.

use crate::WarpError;
use glam::{Mat4, Vec3};
use npr_gpu::{
    BaseShading, COLOR_FORMAT, Camera, DEPTH_FORMAT, FrameUniforms, GpuMesh, Light, ObjectBinding,
    ObjectUniforms, OffscreenTarget, ShadingModel,
};

/// Where and how a reference (or a full frame) is rendered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// The camera.
    pub camera: Camera,
    /// Object → world of the (prototype) object.
    pub world_from_object: Mat4,
}

impl Pose {
    /// The camera's eye in the object's space.
    pub fn eye_object(&self) -> Vec3 {
        self.world_from_object
            .inverse()
            .transform_point3(self.camera.eye)
    }
}

/// A reference image: colour + depth of the full mesh at one pose (§3.3).
#[derive(Debug)]
pub struct ReferenceFrame {
    /// Colour ([`COLOR_FORMAT`]) and depth ([`DEPTH_FORMAT`]) textures, both sampleable.
    pub target: OffscreenTarget,
    /// The pose the reference shows (valid after a complete record).
    pub pose: Pose,
    /// `pose.camera.clip_from_world()`, kept for the projective texture matrix.
    pub clip_from_world: Mat4,
    shading: BaseShading,
    object: ObjectBinding,
}

impl ReferenceFrame {
    /// A reference slot of `width × height` with its own full-Phong shading state.
    ///
    /// # Errors
    /// [`WarpError::Gpu`] for a bad size.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        width: u32,
        height: u32,
    ) -> Result<Self, WarpError> {
        let target = OffscreenTarget::new(device, width, height)?;
        let shading = BaseShading::new(device, queue, COLOR_FORMAT, DEPTH_FORMAT);
        let object =
            shading.create_object(device, &ObjectUniforms::default_material(Mat4::IDENTITY));
        let camera = Camera::look_at(Vec3::Z * 3.0, Vec3::ZERO, target.aspect());
        Ok(Self {
            target,
            pose: Pose {
                camera,
                world_from_object: Mat4::IDENTITY,
            },
            clip_from_world: camera.clip_from_world(),
            shading,
            object,
        })
    }

    /// Writes the uniforms for rendering `pose` with `light` and `material` (whose
    /// `world_from_object` is replaced by the pose's). Call before the submit that carries
    /// [`ReferenceFrame::record`] or the first [`ReferenceFrame::record_slice`].
    pub fn set_pose(
        &mut self,
        queue: &wgpu::Queue,
        pose: &Pose,
        light: &Light,
        material: &ObjectUniforms,
    ) {
        self.pose = *pose;
        self.clip_from_world = pose.camera.clip_from_world();
        self.shading
            .set_frame(queue, &FrameUniforms::new(&pose.camera, light));
        let mut m = *material;
        let fresh = ObjectUniforms::new(pose.world_from_object, Vec3::ZERO, 0.0, Vec3::ZERO, 1.0);
        m.world_from_object = fresh.world_from_object;
        m.normal_from_object = fresh.normal_from_object;
        self.object.update(queue, &m);
    }

    /// Records the full render of `mesh` (full Phong) into the reference, clearing it to
    /// `clear` (use alpha 0 so the object's pixels are those with alpha 1).
    pub fn record(&self, encoder: &mut wgpu::CommandEncoder, mesh: &GpuMesh, clear: [f64; 4]) {
        self.record_slice(encoder, mesh, clear, 0, 1);
    }

    /// Records slice `slice` of `slices` of the full render: the triangles
    /// `[slice/slices, (slice+1)/slices)` of the index buffer. Slice 0 clears; later slices
    /// load what earlier ones drew, so after all slices the reference equals
    /// [`ReferenceFrame::record`] (§3.4: the next reference spread over the frames between).
    pub fn record_slice(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        mesh: &GpuMesh,
        clear: [f64; 4],
        slice: u32,
        slices: u32,
    ) {
        let slices = slices.max(1);
        let slice = slice.min(slices - 1);
        let triangles = u64::from(mesh.index_count / 3);
        let tri_at = |k: u32| (triangles * u64::from(k) / u64::from(slices)) as u32 * 3;
        let (start, end) = (tri_at(slice), tri_at(slice + 1));
        let mut pass = if slice == 0 {
            self.target.begin_clear_pass(encoder, clear)
        } else {
            self.target.begin_load_pass(encoder)
        };
        if slices == 1 {
            self.shading
                .draw(&mut pass, ShadingModel::Phong, &self.object, mesh);
            return;
        }
        // `BaseShading::draw` sets the pipeline and bind groups and draws the whole mesh;
        // give it an empty view of the mesh, then draw only this slice's range.
        let state_only = GpuMesh {
            vertex_buffer: mesh.vertex_buffer.clone(),
            index_buffer: mesh.index_buffer.clone(),
            index_count: 0,
            vertex_count: mesh.vertex_count,
        };
        self.shading
            .draw(&mut pass, ShadingModel::Phong, &self.object, &state_only);
        pass.draw_indexed(start..end, 0, 0..1);
    }
}

/// The full render of every object of a scene (full Phong): what each warped frame is
/// compared with and what a reference costs. Owns its own shading state.
#[derive(Debug)]
pub struct FullRenderer {
    shading: BaseShading,
    objects: Vec<ObjectBinding>,
    count: usize,
}

impl FullRenderer {
    /// A renderer for [`COLOR_FORMAT`] / [`DEPTH_FORMAT`] targets.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        Self {
            shading: BaseShading::new(device, queue, COLOR_FORMAT, DEPTH_FORMAT),
            objects: Vec::new(),
            count: 0,
        }
    }

    /// Writes the camera, light and one transform per object (`material`'s transform is
    /// replaced by each object's).
    pub fn set_scene(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        camera: &Camera,
        world_from_objects: &[Mat4],
        light: &Light,
        material: &ObjectUniforms,
    ) {
        self.shading
            .set_frame(queue, &FrameUniforms::new(camera, light));
        while self.objects.len() < world_from_objects.len() {
            self.objects
                .push(self.shading.create_object(device, material));
        }
        for (binding, m) in self.objects.iter().zip(world_from_objects) {
            let fresh = ObjectUniforms::new(*m, Vec3::ZERO, 0.0, Vec3::ZERO, 1.0);
            let mut u = *material;
            u.world_from_object = fresh.world_from_object;
            u.normal_from_object = fresh.normal_from_object;
            binding.update(queue, &u);
        }
        self.count = world_from_objects.len();
    }

    /// Records the full render of `mesh` at every object transform into `target`.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &OffscreenTarget,
        mesh: &GpuMesh,
        clear: [f64; 4],
    ) {
        let mut pass = target.begin_clear_pass(encoder, clear);
        for object in self.objects.iter().take(self.count) {
            self.shading
                .draw(&mut pass, ShadingModel::Phong, object, mesh);
        }
    }
}
