//! Post-rendering 3D warping with projective textures.
//!
//! Implements Huiwon Park (박희원) and Insung Ihm (임인성), "Post-Rendering 3D Warping using
//! Projective Texture" (투영 텍스처를 이용한 렌더링 후 3차원 와핑), Journal of KIISE
//! (정보과학회논문지), 2002 (received 2001-10-09, accepted 2002-06-18). The full text is
//! `../shared/papers/post-rendering-warping-projective-texture.txt`.
//!
//! Two reference images of the full-detail model, rendered at times t1 and t3
//! ([`reference`](mod@reference)), are projected onto a simplified proxy ([`proxy`], §3.2) posed at an
//! intermediate time t2 ([`pass`], §3.3.1), each from its own reference camera with the
//! projective texture matrix of `npr_gpu::projective` (§2.2). Proxy faces are binned by
//! normal so that whole bins are culled per reference and blended with per-bin opacity
//! ramps ([`bins`], §3.3.2–§3.3.3). A reference every k frames along a known path is the
//! [`sequence`] (§4). [`metrics`] measures each warped frame against the full render.
//!
//! Beyond the paper: a reference depth test (as a shadow map) removes texels hidden by
//! other polygons in a reference, which the paper's §3.4 leaves open, falling back to the
//! other reference; the proxy may be inflated by its simplification error so that its
//! silhouette covers the full mesh's; a temporal term in the §3.3.3 ramp makes the warp at
//! a reference pose reproduce that reference.
//!
//! Data flow: `Mesh` → [`Proxy::simplify`] (once) → [`WarpPass::create_object`] (bins,
//! once) → per reference pose [`ReferenceFrame::record`] → per frame
//! [`WarpPass::prepare`] + [`WarpPass::draw`] into the caller's render pass.
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used))]

pub mod bins;
mod error;
pub mod metrics;
pub mod pass;
pub mod proxy;
pub mod reference;
pub mod sequence;

pub use bins::{BinPlan, DrawKind, Facing, NormalBins, PlanSettings};
pub use error::WarpError;
pub use metrics::{Quality, compare};
pub use pass::{ReferencePair, WarpMode, WarpObject, WarpPass, WarpSettings};
pub use proxy::Proxy;
pub use reference::{FullRenderer, Pose, ReferenceFrame};
pub use sequence::{FrameReport, FrameRole, ScenePose, Turntable, WarpSchedule, WarpSequence};
