//! The embeddable warp for an application: per frame, either record a reference at the
//! current camera or warp the two newest references to it (§3.3), into the caller's
//! encoder and targets. See the crate docs for an example.

use crate::bins::BinPlan;
use crate::departures::Departures;
use crate::msaa::{Antialiasing, DepthResolve, MsaaTarget};
use crate::pass::{
    ReferencePair, WarpInput, WarpMode, WarpObject, WarpPass, WarpPassSettings, WarpSettings,
};
use crate::reference::{BasePass, ObjectView, ReferenceDraw, ReferenceFrame};
use crate::{Proxy, WarpError};
use npr_gpu::{FrameId, Prepared, TargetFormats};

/// Bins per axis of a [`Warper`]'s proxy (§3.3.2; the benchmark's N).
pub const WARPER_BINS: u32 = 16;

/// Two reference slots, one proxy and the warp pass: the state an application keeps.
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Debug)]
pub struct Warper {
    /// The warp settings (§3.3.2–§3.3.3 plan, tolerances).
    pub settings: WarpSettings,
    /// The fragment shader (depth-tested, paper, ...).
    pub mode: WarpMode,
    /// Clear colour of the references and warped frames (alpha 0: the object's pixels are
    /// those with alpha).
    pub clear: [f64; 4],
    pass: WarpPass,
    object: WarpObject,
    refs: [ReferenceFrame; 2],
    /// Multisampled: the warped frame's own multisampled colour and depth.
    msaa: Option<MsaaTarget>,
    /// References recorded so far (the newest is in slot `(recorded - 1) % 2`).
    recorded: u64,
    pair: Option<ReferencePair>,
}

impl Warper {
    /// A warper for `proxy` (see [`Proxy::simplify`]) drawn with a transform that scales
    /// object units by `world_per_object`, with `departures` ([`Departures::OURS`] or
    /// [`Departures::PAPER`]) and references of `size` (width, height) in texels.
    ///
    /// The references are drawn into targets of `references` (the base pass given to
    /// [`Warper::record_reference`] must be built for them, e.g. [`crate::PhongBase::new`]
    /// with the same formats); the warped frames into the caller's targets of `target`.
    /// The two sample counts choose the antialiasing ([`Antialiasing::from_samples`]; 1
    /// and 1: none). With a multisampled warp (4 and 4, [`Antialiasing::Msaa4`]),
    /// [`Warper::record_warp`] draws into the warper's own multisampled textures and
    /// resolves into the caller's one-sample colour, and [`Warper::draw`] needs a pass
    /// with 4 samples per pixel.
    ///
    /// # Errors
    /// [`WarpError::InvalidSetting`] for formats or sample counts the warp cannot use or a
    /// non-finite `world_per_object`; [`WarpError::Gpu`] for a bad size or a failed upload.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        proxy: &Proxy,
        departures: Departures,
        world_per_object: f32,
        (width, height): (u32, u32),
        (references, target): (TargetFormats, TargetFormats),
    ) -> Result<Self, WarpError> {
        if !(world_per_object.is_finite() && world_per_object > 0.0) {
            return Err(WarpError::InvalidSetting(format!(
                "world_per_object {world_per_object} is not a positive scale"
            )));
        }
        let settings = departures.settings(proxy, world_per_object);
        settings.validate()?;
        let antialiasing = Antialiasing::from_samples(references.samples, target.samples)?;
        let pass = WarpPass::new(device, queue, target, &WarpPassSettings { antialiasing })?;
        let object = pass.create_object(
            device,
            proxy,
            WARPER_BINS,
            departures.inflation(proxy),
            false,
        )?;
        // One depth resolve (shader and pipeline) for both slots.
        let resolve = references
            .is_multisampled()
            .then(|| DepthResolve::new(device, references.depth));
        let slot =
            || ReferenceFrame::with_resolve(device, width, height, references, resolve.clone());
        let msaa = if target.is_multisampled() {
            Some(MsaaTarget::new(device, width, height, target)?)
        } else {
            None
        };
        Ok(Self {
            settings,
            mode: departures.mode(),
            clear: [0.0; 4],
            pass,
            object,
            refs: [slot()?, slot()?],
            msaa,
            recorded: 0,
            pair: None,
        })
    }

    /// Records a reference at `pose` drawn by `base` (base-pass slot 0 or 1, for the
    /// caller's submission `frame`) into
    /// `encoder`, replacing the older reference; from then on warps interpolate between
    /// the previous newest reference (s = 0) and this one (s = 1). Submit the encoder before
    /// (or with) the next warp that uses it.
    ///
    /// # Errors
    /// [`WarpError::SampleCountMismatch`], recording nothing and keeping the references,
    /// when `base` is not built for the warper's antialiasing ([`BasePass::sample_count`]).
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    pub fn record_reference(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        base: &mut dyn BasePass,
        frame: FrameId,
        pose: &ObjectView,
    ) -> Result<(), WarpError> {
        let slot = (self.recorded % 2) as usize;
        let draw = ReferenceDraw::whole(frame, pose, slot);
        self.refs[slot].record(device, queue, encoder, base, &draw, self.clear)?;
        // Always (one small copy): a rigid proxy's snapshot is its current vertices, and a
        // reference recorded before the model first moves keeps the pose it shows.
        self.refs[slot].keep_proxy_pose(device, encoder, &self.object);
        self.recorded += 1;
        let [older, newer] = self.ordered();
        // With one reference recorded, it pairs with itself.
        self.pair = Some(self.pass.bind_pair(device, [older, newer]));
        Ok(())
    }

    /// Poses the proxy for a deforming model (ours): `posed` is [`Proxy::posed`] of the
    /// proxy this warper was built for, at the pose the full mesh is drawn at now. A
    /// reference recorded after it keeps the proxy's vertices at its pose
    /// ([`crate::deform`]), and warps draw the proxy at the newest pose set. Submit the
    /// encoder of a reference, and draw the warps prepared for a pose, before setting the
    /// next pose: the pose is written with `queue.write_buffer`, which runs ahead of the
    /// next submission's commands (a warp prepared before it is refused at `draw`).
    ///
    /// # Errors
    /// As [`WarpObject::repose`]; the proxy keeps its last pose then.
    pub fn set_proxy_pose(&mut self, queue: &wgpu::Queue, posed: &Proxy) -> Result<(), WarpError> {
        self.object.repose(queue, posed)
    }

    /// The references in time order, older first (both the same before a second one).
    fn ordered(&self) -> [&ReferenceFrame; 2] {
        let newest = ((self.recorded + 1) % 2) as usize;
        if self.recorded < 2 {
            [&self.refs[newest], &self.refs[newest]]
        } else {
            [&self.refs[1 - newest], &self.refs[newest]]
        }
    }

    /// The antialiasing of references and warped frames.
    pub fn antialiasing(&self) -> Antialiasing {
        self.pass.antialiasing()
    }

    /// References recorded so far (a warp needs at least one; the paper's interpolation,
    /// two).
    pub fn references_recorded(&self) -> u64 {
        self.recorded
    }

    /// The two references in time order, older first.
    pub fn references(&self) -> [&ReferenceFrame; 2] {
        self.ordered()
    }

    /// Where `pose`'s eye lies between the two references' eyes in object space (the
    /// camera may move, the object may move, or both), `s ∈ [0, 1]`: its projection onto
    /// the segment from the older reference's eye to the newer's (0 when they coincide).
    /// For a known path pass the path's own fraction instead.
    pub fn position(&self, pose: &ObjectView) -> f32 {
        let [a, b] = self.ordered().map(|r| r.pose.eye_object());
        let ab = b - a;
        let len2 = ab.length_squared();
        if len2.is_nan() || len2 <= 0.0 {
            return 0.0;
        }
        let s = (pose.eye_object() - a).dot(ab) / len2;
        if s.is_finite() {
            s.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// Writes the warp of the current references to `pose` at position `s` between them
    /// (see [`Warper::position`]) into a fresh slot, for submission `frame`. `None` before
    /// the first reference. Two prepares in one frame (two views, two poses) stay
    /// distinct.
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    ///
    /// # Errors
    /// [`WarpError::Pass`] for more than 64 prepares in one frame.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        frame: FrameId,
        pose: &ObjectView,
        s: f32,
    ) -> Result<Option<Prepared>, WarpError> {
        let Some(pair) = self.pair.as_ref() else {
            return Ok(None);
        };
        let input = WarpInput {
            frame,
            pair,
            now: pose,
            s,
            settings: &self.settings,
            mode: self.mode,
        };
        Ok(Some(self.pass.prepare(queue, &mut self.object, &input)?))
    }

    /// The plan (draws and bin weights) that `prepared` decided.
    ///
    /// # Errors
    /// [`WarpError::Pass`] for a ticket of an earlier frame.
    pub fn plan(&self, prepared: &Prepared) -> Result<&BinPlan, WarpError> {
        self.object.plan(&self.pass, prepared)
    }

    /// Records the warp `prepared` into the caller's render pass (targets of the formats
    /// given to [`Warper::new`]).
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    ///
    /// # Errors
    /// [`WarpError::Pass`] for a `prepared` of an earlier frame or another warper.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        prepared: &Prepared,
    ) -> Result<(), WarpError> {
        self.pass.draw(pass, &self.object, prepared)
    }

    /// [`Warper::prepare`], then [`Warper::draw`] in a pass of its own over `color` /
    /// `depth` cleared to [`Warper::clear`]. Multisampled, the pass is over the warper's
    /// own multisampled textures, resolved into `color`; `depth` is not written. `color`
    /// and `depth` are one sample per pixel whatever the antialiasing. Returns the plan,
    /// `None` before the first reference.
    ///
    /// # Errors
    /// [`WarpError::SampleCountMismatch`] (recording nothing) for a multisampled `color`,
    /// or a multisampled `depth` when the warp draws into it.
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    pub fn record_warp(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (color, depth): (&wgpu::TextureView, &wgpu::TextureView),
        frame: FrameId,
        pose: &ObjectView,
        s: f32,
    ) -> Result<Option<BinPlan>, WarpError> {
        WarpError::check_samples("the colour target", color.texture().sample_count(), 1)?;
        if self.msaa.is_none() {
            WarpError::check_samples("the depth target", depth.texture().sample_count(), 1)?;
        }
        let prepared = self.prepare(queue, frame, pose, s)?;
        let mut pass = match &self.msaa {
            Some(msaa) => msaa.begin_pass(encoder, color, Some(self.clear)),
            None => crate::reference::begin_clear_pass(encoder, color, depth, self.clear),
        };
        let Some(prepared) = prepared else {
            return Ok(None);
        };
        self.draw(&mut pass, &prepared)?;
        Ok(Some(self.plan(&prepared)?.clone()))
    }
}
