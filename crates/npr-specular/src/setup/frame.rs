//! [`HighlightFrame`]: one frame's highlights as the highlight draw reads them, whatever
//! backend made them, ticketed by the frame they were made for.

use crate::{HighlightSet, SpecularError, gpu::ProjectorObject};
use npr_gpu::pass::{FrameId, PassError};

/// One frame's highlights for [`crate::HighlightPass::prepare`]: the projectors, the
/// receiver stream (render vertex, projector index) and, where the GPU made them, the
/// indirect draw's arguments. Made by [`crate::HighlightSetup::record`] (either backend),
/// or from a CPU set a caller updated itself ([`HighlightFrame::of_set`],
/// [`HighlightFrame::with_list`]). The draw refuses a frame made for another submission.
#[derive(Clone, Copy, Debug)]
pub struct HighlightFrame<'a> {
    frame: FrameId,
    pub(crate) source: Source<'a>,
}

/// Where a frame's records lie.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Source<'a> {
    /// The CPU's set after its update: its projectors and receivers are uploaded by the
    /// draw's prepare. `list`: a caller's stream in place of the §4.2 receivers.
    Set {
        set: &'a HighlightSet,
        indices: &'a [u32],
        list: Option<&'a [[u32; 2]]>,
    },
    /// Made by compute passes in this frame's encoder: the receivers' stream and its
    /// indirect arguments, and the projector records, drawn where they lie. `set` gives
    /// the render normals of a pose the CPU made.
    Gpu {
        set: &'a HighlightSet,
        stream: (&'a wgpu::Buffer, &'a wgpu::Buffer),
        projectors: &'a ProjectorObject,
    },
}

impl<'a> HighlightFrame<'a> {
    /// The highlights of `set`'s last [`HighlightSet::update`], drawn on their §4.2
    /// receivers (`indices`: the render mesh's triangles, faces in the set's order).
    pub fn of_set(frame: FrameId, set: &'a HighlightSet, indices: &'a [u32]) -> Self {
        Self {
            frame,
            source: Source::Set {
                set,
                indices,
                list: None,
            },
        }
    }

    /// The highlights of `set` drawn on a caller's stream instead of their receivers
    /// (entries (render vertex, index into `set.highlights()`), three per triangle; for
    /// figures such as [`crate::HighlightPass::draw_list_unrestricted`]).
    pub fn with_list(frame: FrameId, set: &'a HighlightSet, list: &'a [[u32; 2]]) -> Self {
        Self {
            frame,
            source: Source::Set {
                set,
                indices: &[],
                list: Some(list),
            },
        }
    }

    /// A frame the compute passes made.
    pub(crate) fn on_gpu(
        frame: FrameId,
        set: &'a HighlightSet,
        stream: (&'a wgpu::Buffer, &'a wgpu::Buffer),
        projectors: &'a ProjectorObject,
    ) -> Self {
        Self {
            frame,
            source: Source::Gpu {
                set,
                stream,
                projectors,
            },
        }
    }

    /// The submission the frame was made for.
    pub fn frame(&self) -> FrameId {
        self.frame
    }

    /// Whether the GPU made the frame (its records are not on the CPU).
    pub fn on_the_gpu(&self) -> bool {
        matches!(self.source, Source::Gpu { .. })
    }

    /// The set whose settings and render normals the frame uses.
    pub(crate) fn set(&self) -> &'a HighlightSet {
        match self.source {
            Source::Set { set, .. } | Source::Gpu { set, .. } => set,
        }
    }

    /// [`PassError::Stale`] unless the frame was made for `frame`.
    pub(crate) fn check(&self, frame: FrameId) -> Result<(), SpecularError> {
        if self.frame != frame {
            return Err(PassError::Stale {
                prepared: self.frame.0,
                current: frame.0,
            }
            .into());
        }
        Ok(())
    }
}
