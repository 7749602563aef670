#![doc = include_str!("../README.md")]
//!
//! Post-rendering 3D warping with projective textures.
//!
//! Implements Huiwon Park (박희원) and Insung Ihm (임인성), "Post-Rendering 3D Warping using
//! Projective Texture" (투영 텍스처를 이용한 렌더링 후 3차원 와핑), Journal of KIISE
//! (정보과학회논문지), 2002 (received 2001-10-09, accepted 2002-06-18).
//!
//! Two reference images of the full-detail model, rendered at times t1 and t3
//! ([`reference`](mod@reference)), are projected onto a simplified proxy ([`proxy`], §3.2) posed at an
//! intermediate time t2 ([`pass`], §3.3.1), each from its own reference camera with the
//! projective texture matrix of `npr_gpu::projective` (§2.2). Proxy faces are binned by
//! normal so that whole bins are culled per reference and blended with per-bin opacity
//! ramps ([`bins`], §3.3.2–§3.3.3). A reference every k frames along a known path is the
//! [`sequence`] (§4). `metrics` (feature `test-support`) measures each warped frame
//! against the full render.
//!
//! The paper's path is [`Departures::PAPER`] (§3.3.2 representative-vector culling, the
//! §3.3.3 linear ramp, the uninflated proxy, references projected as they are). Ours,
//! [`Departures::OURS`], adds each of the [`Departure`]s, switchable alone: a reference
//! depth test (as a shadow map) removes texels hidden by other polygons in a reference,
//! which the paper's §3.4 leaves open; coverage-normalised lookups; conservative culling;
//! bins neither reference sees drawn from the nearer one; the proxy inflated by its
//! simplification error; a cosine-ratio ramp, sharpened to a band, with a time term that
//! makes the warp at a reference pose reproduce that reference.
//!
//! Antialiasing ([`msaa`], ours, default none): [`Antialiasing::Msaa4`] multisamples the
//! references, the warp and the full render 4×, the warp's sample mask following the
//! references' coverage; [`Antialiasing::Msaa4Blend`] multisamples references and full
//! render and blends a one-sample warp's rim by the references' coverage.
//!
//! Embedding: every pass draws into the caller's colour and depth formats and records into
//! the caller's `wgpu::CommandEncoder`; nothing here submits. What a reference shows is
//! the caller's [`BasePass`] ([`PhongBase`]: npr-gpu's Phong). An application keeps a
//! [`Warper`] and, per frame, either records a reference at the current camera or warps
//! the two newest references to it:
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, mesh: &npr_geometry::Mesh,
//! #     gpu_mesh: &npr_gpu::GpuMesh, target: &wgpu::Texture, depth: &wgpu::TextureView,
//! #     poses: &[npr_warp::ObjectView]) -> Result<(), npr_warp::WarpError> {
//! use npr_warp::{Departures, PhongBase, Proxy, Warper};
//! let (color_format, depth_format) =
//!     (wgpu::TextureFormat::Bgra8UnormSrgb, wgpu::TextureFormat::Depth32Float);
//! let proxy = Proxy::simplify(mesh, 0.02)?; // §3.2: 2 % of the triangles
//! let formats = npr_gpu::TargetFormats::new(color_format, depth_format);
//! let mut warper = Warper::new(device, queue, &proxy, Departures::OURS, 1.0, (512, 512),
//!     (formats, formats))?;
//! let light = npr_gpu::Light::directional(glam::Vec3::new(1.0, 1.5, 2.0));
//! let material = npr_gpu::ObjectUniforms::default_material(glam::Mat4::IDENTITY);
//! let mut base = PhongBase::new(gpu_mesh, light, material, formats);
//! let color = target.create_view(&Default::default());
//! for (i, pose) in poses.iter().enumerate() {
//!     let frame = npr_gpu::FrameId(i as u64); // one per submission
//!     let mut encoder = device.create_command_encoder(&Default::default());
//!     if i % 10 == 0 {
//!         // "Render a reference at camera C" (shown as is this frame: warp at s = 1).
//!         warper.record_reference(device, queue, &mut encoder, &mut base, frame, pose)?;
//!     }
//!     // "Warp the current references to camera C".
//!     let s = warper.position(pose);
//!     warper.record_warp(queue, &mut encoder, (&color, depth), frame, pose, s)?;
//!     queue.submit(Some(encoder.finish()));
//! }
//! # let _ = target;
//! # Ok(()) }
//! ```
//!
//! Data flow: `Mesh` → [`Proxy::simplify`] (once) → [`WarpPass::create_object`] (bins,
//! once) → per reference pose [`ReferenceFrame::record`] → per frame
//! [`WarpPass::prepare`] + [`WarpPass::draw`] into the caller's render pass. [`Warper`]
//! bundles this for one object; [`WarpSequence`] runs a known path (§4).
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used))]

pub mod bins;
pub mod deform;
pub mod departures;
mod error;
pub mod metrics;
pub mod msaa;
pub mod pass;
pub mod proxy;
pub mod reference;
#[cfg(any(test, feature = "test-support"))]
pub mod rig;
pub mod sequence;
pub mod shaders;
pub mod warper;

pub use bins::{BinPlan, Culling, DrawKind, Facing, NormalBins, PlanSettings, Ramp};
pub use departures::{Departure, Departures};
pub use error::WarpError;
#[cfg(any(test, feature = "test-support"))]
pub use metrics::flip_mean;
pub use metrics::{Quality, compare};
pub use msaa::{Antialiasing, MsaaTarget};
pub use pass::{
    ReferencePair, WarpInput, WarpMode, WarpObject, WarpPass, WarpPassSettings, WarpSettings,
};
pub use proxy::Proxy;
pub use reference::{
    BasePass, FullInput, FullRenderer, ObjectView, PhongBase, ReferenceDraw, ReferenceFrame,
};
pub use sequence::{
    FrameReport, FrameRole, SceneView, SequenceFrame, Turntable, WarpSchedule, WarpSequence,
};
pub use warper::Warper;
