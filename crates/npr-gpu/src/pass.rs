//! The one contract every GPU pass of the workspace speaks (wgpu's "Encapsulating
//! Graphics Work" middleware pattern; glyphon's `new` / `prepare` / `render`; rerun
//! re_renderer's per-frame draw data):
//!
//! | verb | when | what it may do |
//! |---|---|---|
//! | `new(device, queue, formats, settings)` | once | build pipelines (keyed by the settings), upload constant data (ramps, textures, the TAM) |
//! | `create_object(device, &GpuMesh, ..)` | once per mesh | per-mesh buffers and bind groups; it keeps the caller's vertex buffer (no copy), so a mesh posed on the GPU is drawn by every pass |
//! | `prepare(&self, queue, &mut Object, &Input) -> Result<Prepared>` | per draw | the **only** queue writes; each call gets its own slot, so two views or two poses of one object in one submission stay distinct |
//! | `draw(&self, &mut RenderPass, &Object, &Prepared) -> Result` | per draw | record into the caller's render pass; refuse a [`Prepared`] of another pass, object or frame |
//! | `record(&self, &mut CommandEncoder, ..)` | per frame | where a pass has GPU work that is not drawing into the caller's pass (a prepass into its own target, compute) |
//!
//! The per-frame verbs are the [`Pass`] trait, so generic code (the `npr` app's engine,
//! a user's renderer) can hold any pass. Every input of a frame is an argument of
//! `prepare`: no setter writes per-frame state, and no clock advances inside a call.
//!
//! A frame is named by a [`FrameId`] that the caller advances once per submission. The
//! slots of an object are reused when its `prepare` sees a new [`FrameId`]; a
//! [`Prepared`] of an earlier frame is then stale and `draw` refuses it with
//! [`PassError::Stale`] rather than drawing whatever the slot now holds.

use std::sync::atomic::{AtomicU64, Ordering};

static NEXT_ID: AtomicU64 = AtomicU64::new(1);

fn next_id() -> u64 {
    NEXT_ID.fetch_add(1, Ordering::Relaxed)
}

/// The identity of one pass instance (each `new` makes a fresh one).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PassId(u64);

impl PassId {
    /// A new identity, never equal to any other.
    pub fn fresh() -> Self {
        Self(next_id())
    }
}

/// One submission of the caller's, in order. Advance it ([`FrameId::next`]) once per
/// submission; prepares with the same id share that submission.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FrameId(pub u64);

impl FrameId {
    /// The frame after this one.
    #[must_use]
    pub fn next(self) -> Self {
        Self(self.0.wrapping_add(1))
    }
}

/// What `prepare` hands back: a ticket for one slot of one object in one frame. Pass it to
/// `draw`, which checks that it belongs to that object, that pass and the object's
/// current frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Prepared {
    pass: PassId,
    object: u64,
    frame: FrameId,
    slot: u32,
}

impl Prepared {
    /// The frame it was prepared for.
    pub fn frame(&self) -> FrameId {
        self.frame
    }

    /// Its slot among the object's prepares of that frame (0 for the first).
    pub fn slot(&self) -> u32 {
        self.slot
    }
}

/// Why a pass refused an object or a [`Prepared`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PassError {
    /// The object was created by another pass instance. Fix: create the object with the
    /// pass that draws it.
    #[error("the object was created by another pass")]
    ForeignObject,
    /// The [`Prepared`] came from another pass or another object. Fix: draw each object with
    /// the ticket its own `prepare` returned.
    #[error("the prepared state belongs to another pass or object")]
    ForeignPrepared,
    /// The [`Prepared`] is of an earlier frame: the object has been prepared for a newer
    /// [`FrameId`] since, and its slot may hold other data. Fix: prepare again for this
    /// frame.
    #[error(
        "stale prepared state: prepared for frame {prepared}, the object is at frame {current}"
    )]
    Stale {
        /// The frame the ticket was prepared for.
        prepared: u64,
        /// The object's current frame.
        current: u64,
    },
    /// More prepares of one object in one frame than [`Slots::CAPACITY`]. Cause: the caller
    /// never advances its [`FrameId`]. Fix: pass a new `FrameId` for each submission.
    #[error(
        "more than {capacity} prepares of one object in frame {frame}: give each submission a new FrameId"
    )]
    SlotsExhausted {
        /// The slot limit per object and frame.
        capacity: usize,
        /// The frame that ran out.
        frame: u64,
    },
}

/// An object's per-frame slots: one `S` (its uniform buffers, storage, bind groups) per
/// `prepare` of the current frame, created on first use and reused in later frames.
#[derive(Debug)]
pub struct Slots<S> {
    pass: PassId,
    object: u64,
    frame: Option<FrameId>,
    used: usize,
    slots: Vec<S>,
}

impl<S> Slots<S> {
    /// The most prepares of one object in one frame.
    pub const CAPACITY: usize = 64;

    /// No slots yet, for an object of `pass`.
    pub fn new(pass: PassId) -> Self {
        Self {
            pass,
            object: next_id(),
            frame: None,
            used: 0,
            slots: Vec::new(),
        }
    }

    /// The pass that created the object.
    pub fn pass(&self) -> PassId {
        self.pass
    }

    /// [`PassError::ForeignObject`] unless the object belongs to `pass`.
    ///
    /// # Errors
    /// As above.
    pub fn check_pass(&self, pass: PassId) -> Result<(), PassError> {
        if self.pass == pass {
            Ok(())
        } else {
            Err(PassError::ForeignObject)
        }
    }

    /// Takes the next slot of `frame` (the first, when `frame` is new to this object),
    /// creating it with `make` when it does not exist yet.
    ///
    /// # Errors
    /// [`PassError::ForeignObject`] when `pass` did not create the object;
    /// [`PassError::SlotsExhausted`] past [`Slots::CAPACITY`] prepares in one frame.
    pub fn next(
        &mut self,
        pass: PassId,
        frame: FrameId,
        make: impl FnOnce() -> S,
    ) -> Result<(Prepared, &mut S), PassError> {
        self.check_pass(pass)?;
        if self.frame != Some(frame) {
            self.frame = Some(frame);
            self.used = 0;
        }
        if self.used >= Self::CAPACITY {
            return Err(PassError::SlotsExhausted {
                capacity: Self::CAPACITY,
                frame: frame.0,
            });
        }
        let slot = self.used;
        if slot == self.slots.len() {
            self.slots.push(make());
        }
        self.used += 1;
        let prepared = Prepared {
            pass,
            object: self.object,
            frame,
            slot: slot as u32,
        };
        Ok((prepared, &mut self.slots[slot]))
    }

    /// The slot `prepared` names, after checking it.
    ///
    /// # Errors
    /// [`PassError::ForeignObject`], [`PassError::ForeignPrepared`] or
    /// [`PassError::Stale`].
    pub fn get(&self, pass: PassId, prepared: &Prepared) -> Result<&S, PassError> {
        self.check_pass(pass)?;
        if prepared.pass != pass || prepared.object != self.object {
            return Err(PassError::ForeignPrepared);
        }
        if self.frame != Some(prepared.frame) {
            return Err(PassError::Stale {
                prepared: prepared.frame.0,
                current: self.frame.map_or(0, |f| f.0),
            });
        }
        self.slots
            .get(prepared.slot as usize)
            .filter(|_| (prepared.slot as usize) < self.used)
            .ok_or(PassError::ForeignPrepared)
    }

    /// Every slot created so far (for state that all slots share, such as a buffer that
    /// the object replaces).
    pub fn all_mut(&mut self) -> impl Iterator<Item = &mut S> {
        self.slots.iter_mut()
    }
}

/// The per-frame half of the contract: `prepare` and `draw`. `new` and `create_object`
/// are inherent functions of each pass, with the shapes in this module's table.
pub trait Pass {
    /// Per-mesh state from `create_object`.
    type Object;
    /// Everything one draw needs that changes per frame.
    type Input<'a>;
    /// The crate's error type.
    type Error: From<PassError>;

    /// Writes this draw's per-frame data into a fresh slot of `object`.
    ///
    /// # Errors
    /// A [`PassError`] for a foreign object or too many prepares in one frame; the
    /// pass's own errors for bad input.
    fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut Self::Object,
        input: &Self::Input<'_>,
    ) -> Result<Prepared, Self::Error>;

    /// Records the draw of `object` with the slot `prepared` into the caller's render
    /// pass.
    ///
    /// # Errors
    /// A [`PassError`] for a `prepared` of another pass, object or frame; nothing is
    /// recorded then.
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        object: &Self::Object,
        prepared: &Prepared,
    ) -> Result<(), Self::Error>;
}

/// Implements [`Pass`] for a pass whose inherent `prepare` and `draw` already have the
/// trait's shape, by forwarding to them:
/// `npr_gpu::impl_pass!(HighlightPass, HighlightObject, HighlightInput, SpecularError);`.
/// The input type takes one lifetime (`HighlightInput<'a>`).
#[macro_export]
macro_rules! impl_pass {
    ($pass:ty, $object:ty, $input:ident, $error:ty) => {
        impl $crate::Pass for $pass {
            type Object = $object;
            type Input<'a> = $input<'a>;
            type Error = $error;

            fn prepare(
                &self,
                queue: &$crate::wgpu::Queue,
                object: &mut $object,
                input: &$input<'_>,
            ) -> ::core::result::Result<$crate::Prepared, $error> {
                <$pass>::prepare(self, queue, object, input)
            }

            fn draw(
                &self,
                pass: &mut $crate::wgpu::RenderPass<'_>,
                object: &$object,
                prepared: &$crate::Prepared,
            ) -> ::core::result::Result<(), $error> {
                <$pass>::draw(self, pass, object, prepared)
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_are_reused_per_frame_and_stale_tickets_refused() {
        let pass = PassId::fresh();
        let mut slots: Slots<u32> = Slots::new(pass);
        let mut made = 0;
        let f0 = FrameId::default();
        let (a, _) = slots
            .next(pass, f0, || {
                made += 1;
                0
            })
            .expect("slot");
        let (b, _) = slots.next(pass, f0, || 1).expect("slot");
        assert_ne!(
            a.slot(),
            b.slot(),
            "two prepares in one frame get two slots"
        );
        assert!(slots.get(pass, &a).is_ok() && slots.get(pass, &b).is_ok());
        let (c, _) = slots.next(pass, f0.next(), || 2).expect("slot");
        assert_eq!(c.slot(), 0, "a new frame reuses the first slot");
        assert_eq!(made, 1);
        assert!(matches!(slots.get(pass, &a), Err(PassError::Stale { .. })));
        assert!(matches!(
            slots.get(PassId::fresh(), &c),
            Err(PassError::ForeignObject)
        ));
        let other: Slots<u32> = Slots::new(pass);
        assert_eq!(other.get(pass, &c), Err(PassError::ForeignPrepared));
    }

    #[test]
    fn a_frame_id_that_never_advances_runs_out_with_a_typed_error() {
        let pass = PassId::fresh();
        let mut slots: Slots<()> = Slots::new(pass);
        for _ in 0..Slots::<()>::CAPACITY {
            slots
                .next(pass, FrameId(7), || ())
                .expect("within capacity");
        }
        assert_eq!(
            slots.next(pass, FrameId(7), || ()).map(|(p, _)| p),
            Err(PassError::SlotsExhausted {
                capacity: Slots::<()>::CAPACITY,
                frame: 7
            })
        );
    }
}
