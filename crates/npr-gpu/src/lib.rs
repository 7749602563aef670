#![doc = include_str!("../README.md")]
//!
//! The GPU layer shared by every technique crate of the npr workspace.
//!
//! - [`GpuContext`]: a headless instance/adapter/device/queue, honouring `WGPU_BACKEND`,
//!   with a typed error that says what to install when no adapter exists.
//! - [`OffscreenTarget`] and [`readback_rgba`]: colour + depth targets and their readback
//!   (row padding handled in one helper, [`padded_bytes_per_row`]).
//! - [`GpuMesh`]: upload of an [`npr_geometry::Mesh`] (interleaved position, normal, uv;
//!   `u32` indices).
//! - [`FrameUniforms`] / [`ObjectUniforms`]: `#[repr(C)]` Pod uniform blocks mirrored in
//!   `shaders/common.wgsl`.
//! - [`projective`]: the projective-texture matrix `tex_from_world` shared by the specular
//!   and warping crates.
//! - [`BaseShading`]: Phong, Gouraud and cel shading passes over which techniques draw.
//! - [`render`]: the wgpu boilerplate written once: [`TargetFormats`], uniform buffers,
//!   attachments and passes, and [`PipelineBuilder`].
//! - [`outline`]: silhouette and crease lines from a normal + depth prepass, over any
//!   style.
//! - [`posing`]: a rig's morph targets and skinning as a compute pass that writes the
//!   posed mesh into its own vertex buffer, drawn by every pass.
//! - [`curvature`]: the per-vertex curvature tensor, principal curvatures and directions
//!   as compute passes over the mesh's own vertex buffer (a posed mesh is measured
//!   without a copy).
//!
//! Every pass takes `&wgpu::Device`, `&wgpu::Queue` and target views from the caller, so
//! it can be recorded into someone else's renderer; [`GpuContext`] is a convenience.

mod camera;
pub mod color;
pub mod compute;
mod context;
#[cfg(any(test, feature = "test-support"))]
pub mod cpu_twin;
pub mod curvature;
mod error;
#[cfg(any(test, feature = "test-support"))]
pub mod figures;
#[cfg(any(test, feature = "test-support"))]
pub mod fixtures;
pub mod layout;
mod mesh;
pub mod outline;
pub mod pass;
pub mod posing;
pub mod projective;
mod readback;
pub mod render;
pub mod shaders;
mod shading;
#[cfg(any(test, feature = "test-support"))]
pub mod snapshot;
mod targets;
#[cfg(any(test, feature = "test-support"))]
pub mod testing;
mod uniforms;

pub use camera::{Camera, Light};
pub use context::GpuContext;
pub use curvature::{CurvatureInput, CurvatureObject, CurvaturePass, POSE_REACH};
pub use error::GpuError;
pub use mesh::{GpuMesh, Vertex, check_mesh_limits};
pub use pass::{FrameId, Pass, PassError, Prepared};
pub use posing::{PoseInput, PosedObject, PosingPass};
pub use readback::{
    BufferReadback, TextureReadback, padded_bytes_per_row, readback_rgba, readback_texture,
};
pub use render::{PipelineBuilder, TargetFormats};
pub use shading::{
    BaseInput, BaseObject, BaseSettings, BaseShading, ShadingModel, default_ramp, toon_ramp,
    upload_ramp,
};
pub use targets::{
    COLOR_FORMAT, DEPTH_FORMAT, OffscreenTarget, begin_views_pass, check_size, texture_2d,
    texture_2d_descriptor,
};
pub use uniforms::{FrameUniforms, ObjectUniforms};

pub use wgpu;
