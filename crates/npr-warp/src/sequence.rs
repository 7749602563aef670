//! The schedule (§1, §3.4, §4): a reference every k frames along a known path (the paper
//! measures k = 10, 20, 30, 40), warped frames between, and optionally the next reference
//! rendered in slices spread over the intermediate frames (§3.4, with a third off-screen
//! buffer as the paper suggests). Several objects may share one reference pair (Table 3).

use crate::WarpError;
use crate::bins::BinPlan;
use crate::pass::{ReferencePair, WarpInput, WarpMode, WarpObject, WarpPass, WarpSettings};
use crate::reference::{BasePass, ObjectView, ReferenceDraw, ReferenceFrame};
use glam::Mat4;
use npr_gpu::FrameId;
use npr_gpu::{Camera, TargetFormats};

/// Which references a frame interpolates and where it lies between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameRole {
    /// Segment j: the frame lies between references j and j + 1.
    pub segment: u32,
    /// Frame number of reference j (`j·k`); reference j + 1 is at `(j + 1)·k`.
    pub first_frame: u32,
    /// Position between the references, `(frame − j·k) / k ∈ [0, 1)`.
    pub s: f32,
    /// Position of the frame inside its segment, `0..k`.
    pub step: u32,
}

/// A reference every `k` frames (§4), pure arithmetic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WarpSchedule {
    /// Frames per reference, k ≥ 1.
    pub period: u32,
    /// Spread the rendering of the reference after next over the k frames of a segment
    /// (§3.4) instead of rendering it whole at the segment's start.
    pub spread: bool,
}

impl WarpSchedule {
    /// A schedule with a reference every `period` frames.
    ///
    /// # Errors
    /// [`WarpError::ZeroPeriod`] for `period == 0`.
    pub fn new(period: u32, spread: bool) -> Result<Self, WarpError> {
        if period == 0 {
            return Err(WarpError::ZeroPeriod);
        }
        Ok(Self { period, spread })
    }

    /// The role of `frame`.
    pub fn role(&self, frame: u32) -> FrameRole {
        let k = self.period.max(1);
        let segment = frame / k;
        let step = frame % k;
        FrameRole {
            segment,
            first_frame: segment * k,
            s: step as f32 / k as f32,
            step,
        }
    }

    /// Frame amortized cost of this schedule: the reference cost spread over k frames plus
    /// one warp per frame (`REF/k + WARP`, ms).
    pub fn amortized_ms(&self, reference_ms: f64, warp_ms: f64) -> f64 {
        reference_ms / f64::from(self.period.max(1)) + warp_ms
    }
}

/// The scene along a known path at one frame: a camera and the world transform of every
/// object (object 0 is the one the references show; every object shares them, Table 3).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneView {
    /// The camera.
    pub camera: Camera,
    /// Object → world per object (at least one).
    pub objects: Vec<Mat4>,
}

impl SceneView {
    /// The pose of object `i` (object 0 when `i` is out of range; identity without objects).
    pub fn object(&self, i: usize) -> ObjectView {
        let m = self
            .objects
            .get(i)
            .or(self.objects.first())
            .copied()
            .unwrap_or(Mat4::IDENTITY);
        ObjectView {
            camera: self.camera,
            world_from_object: m,
        }
    }
}

/// What one frame of a [`WarpSequence`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameReport {
    /// The frame's role.
    pub s: f32,
    /// Reference slices rendered in this frame (k per reference when spreading; 1 for a
    /// whole reference; more at start-up).
    pub reference_slices: u32,
    /// The bin plan of each object.
    pub plans: Vec<BinPlan>,
}

/// A warped animation over a known path: a reference every k frames, warped frames between
/// (§3.3, §4). Owns three reference slots (two in use, one being built, §3.4). Records into
/// the caller's encoder; submits nothing.
#[derive(Debug)]
pub struct WarpSequence {
    /// The schedule.
    pub schedule: WarpSchedule,
    /// The warp settings used for every object.
    pub settings: WarpSettings,
    /// Draw mode (depth-tested, paper or fill).
    pub mode: WarpMode,
    /// Clear colour of the references and frames (alpha 0 by default: the object's pixels
    /// are the ones with alpha).
    pub clear: [f64; 4],
    pass: WarpPass,
    slots: [ReferenceFrame; 3],
    /// Reference index held by each slot (`None`: empty), and slices done.
    held: [Option<(u32, u32)>; 3],
    pair: Option<(u32, ReferencePair)>,
}

impl WarpSequence {
    /// A sequence rendering references of `width × height` in the caller's `formats`
    /// (references and warped frames alike: a sequence is not antialiased).
    ///
    /// # Errors
    /// [`WarpError::Gpu`] for a bad size, [`WarpError::InvalidSetting`] for settings out
    /// of range or formats the warp cannot use; [`WarpError::SampleCountMismatch`] when
    /// `formats` has more than one sample per pixel.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        schedule: WarpSchedule,
        settings: WarpSettings,
        width: u32,
        height: u32,
        formats: TargetFormats,
    ) -> Result<Self, WarpError> {
        settings.validate()?;
        WarpError::check_samples("a warp sequence's targets", formats.samples, 1)?;
        let slot = || ReferenceFrame::new(device, width, height, formats);
        Ok(Self {
            schedule,
            settings,
            mode: WarpMode::DepthTested,
            clear: [0.0; 4],
            pass: WarpPass::new(device, queue, formats, &Default::default())?,
            slots: [slot()?, slot()?, slot()?],
            held: [None; 3],
            pair: None,
        })
    }

    /// The warp pipelines (to create objects with [`WarpPass::create_object`]).
    pub fn pass(&self) -> &WarpPass {
        &self.pass
    }

    /// The reference slot holding reference `index`, if rendered completely.
    pub fn reference(&self, index: u32) -> Option<&ReferenceFrame> {
        let slot = (index % 3) as usize;
        match self.held[slot] {
            Some((i, done)) if i == index && done >= self.slices() => Some(&self.slots[slot]),
            _ => None,
        }
    }

    fn slices(&self) -> u32 {
        if self.schedule.spread {
            self.schedule.period
        } else {
            1
        }
    }

    /// Records reference `index` slice by slice (or whole when not spreading) into its slot
    /// (base-pass slot `index % 3`), drawn by `input.base` at `input.path`'s pose: one
    /// slice, or with `complete` every remaining one. Returns the slices recorded, or the
    /// error of [`ReferenceFrame::record`].
    fn advance_reference(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        input: &mut SequenceFrame<'_>,
        index: u32,
        complete: bool,
    ) -> Result<u32, WarpError> {
        let slot = (index % 3) as usize;
        let slices = self.slices();
        let mut done = match self.held[slot] {
            Some((i, done)) if i == index => done,
            _ => 0,
        };
        let pose = (input.path)(index * self.schedule.period).object(0);
        let mut n = 0;
        while done < slices {
            let draw = ReferenceDraw {
                frame: FrameId(u64::from(input.frame)),
                pose: &pose,
                slot,
                slice: done,
                slices,
            };
            self.slots[slot].record(device, queue, encoder, input.base, &draw, self.clear)?;
            done += 1;
            n += 1;
            if !complete {
                break;
            }
        }
        self.held[slot] = Some((index, done));
        Ok(n)
    }

    /// Records frame `input.frame` into `encoder`: the references it needs (recorded now if
    /// missing, drawn by `input.base`; the one after next advanced by one slice when
    /// spreading), then a pass over `color` / `depth` (cleared to [`WarpSequence::clear`])
    /// with every object of `path(frame)` warped with `objects[i]` (`path(frame).objects`
    /// gives their poses). Submit the encoder before recording the next frame (uniforms are
    /// written per frame). Submits nothing and does not wait.
    ///
    /// # Errors
    /// [`WarpError::SampleCountMismatch`], recording nothing, when `base` or `color` /
    /// `depth` are not one sample per pixel (a sequence is not antialiased).
    pub fn record_frame(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        mut input: SequenceFrame<'_>,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> Result<FrameReport, WarpError> {
        let samples = self.slots[0].sample_count();
        WarpError::check_samples("the base pass", input.base.sample_count(), samples)?;
        WarpError::check_samples("the colour target", color.texture().sample_count(), 1)?;
        WarpError::check_samples("the depth target", depth.texture().sample_count(), 1)?;
        let frame = input.frame;
        let role = self.schedule.role(frame);
        let j = role.segment;
        let mut report = FrameReport {
            s: role.s,
            ..Default::default()
        };
        for index in [j, j + 1] {
            report.reference_slices +=
                self.advance_reference(device, queue, encoder, &mut input, index, true)?;
        }
        if self.pair.as_ref().map(|p| p.0) != Some(j) {
            let (a, b) = ((j % 3) as usize, ((j + 1) % 3) as usize);
            let pair = self
                .pass
                .bind_pair(device, [&self.slots[a], &self.slots[b]]);
            self.pair = Some((j, pair));
        }
        if self.schedule.spread {
            report.reference_slices +=
                self.advance_reference(device, queue, encoder, &mut input, j + 2, false)?;
        }
        let scene = (input.path)(frame);
        let objects = input.objects;
        if let Some((_, pair)) = &self.pair {
            let mut prepared = Vec::with_capacity(objects.len());
            for (i, object) in objects.iter_mut().enumerate() {
                let now = scene.object(i);
                let warp = WarpInput {
                    frame: FrameId(u64::from(frame)),
                    pair,
                    now: &now,
                    s: role.s,
                    settings: &self.settings,
                    mode: self.mode,
                };
                let p = self.pass.prepare(queue, object, &warp)?;
                report.plans.push(object.plan(&self.pass, &p)?.clone());
                prepared.push(p);
            }
            let mut rpass = crate::reference::begin_clear_pass(encoder, color, depth, self.clear);
            for (object, p) in objects.iter().zip(&prepared) {
                self.pass.draw(&mut rpass, object, p)?;
            }
        }
        Ok(report)
    }
}

/// One frame of a [`WarpSequence`] as the caller describes it to
/// [`WarpSequence::record_frame`].
pub struct SequenceFrame<'a> {
    /// The base pass that draws the references (one sample per pixel).
    pub base: &'a mut dyn BasePass,
    /// The warp objects, one per object of the path's scene.
    pub objects: &'a mut [WarpObject],
    /// The scene at each frame: the camera and every object's pose.
    pub path: &'a dyn Fn(u32) -> SceneView,
    /// The frame to record.
    pub frame: u32,
}

/// A known path (§1: "an object moving along a set path"): objects turning about the
/// world y axis at `deg_per_frame`, each at its own offset, before a fixed camera; or, with
/// `orbit_camera`, the camera orbiting the fixed objects at the same rate (the same
/// relative motion, but the world-fixed light then lights the object the same way in every
/// frame, so only view-dependent shading changes). Used by the tests, the demo and the
/// benchmark.
#[derive(Clone, Debug, PartialEq)]
pub struct Turntable {
    /// The fixed camera.
    pub camera: Camera,
    /// Object → turntable frame applied first (e.g. centring and scaling to a unit sphere).
    pub normalize: Mat4,
    /// Rotation per frame, degrees.
    pub deg_per_frame: f32,
    /// World offset of each object (one entry per object).
    pub offsets: Vec<glam::Vec3>,
    /// Move the camera around the objects instead of turning the objects.
    pub orbit_camera: bool,
}

impl Turntable {
    /// The scene at (possibly fractional) frame `t`.
    pub fn pose(&self, t: f32) -> SceneView {
        let angle = (self.deg_per_frame * t).to_radians();
        if self.orbit_camera {
            let orbit = Mat4::from_rotation_y(-angle);
            let mut camera = self.camera;
            camera.eye = orbit.transform_point3(camera.eye);
            camera.target = orbit.transform_point3(camera.target);
            return SceneView {
                camera,
                objects: self
                    .offsets
                    .iter()
                    .map(|o| Mat4::from_translation(*o) * self.normalize)
                    .collect(),
            };
        }
        let spin = Mat4::from_rotation_y(angle);
        SceneView {
            camera: self.camera,
            objects: self
                .offsets
                .iter()
                .map(|o| Mat4::from_translation(*o) * spin * self.normalize)
                .collect(),
        }
    }
}
