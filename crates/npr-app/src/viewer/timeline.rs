//! A model's glTF clip in a live view, for the window and the browser page alike: the
//! clip the preset names (`[animation] clip`), posed at the viewer's clip time
//! ([`ViewerState::clip_time`], advanced while [`ViewerState::clip_playing`]) into the
//! renderer in place ([`Renderer::set_pose`]), so picking and editing a highlight work on
//! the moving model and its edits follow it. A clip that cannot be played leaves the bind
//! pose drawn, and [`Timeline::note`] says why in one line.

use super::state::ViewerState;
use crate::AppError;
use crate::animation::{Animated, ClipChoice, Playback, resolve_clip};
use crate::engine::Renderer;
use crate::model::Model;

/// See the module docs.
#[derive(Clone, Debug, Default)]
pub struct Timeline {
    /// The loaded, rigged model (`None` for a model without clips or morphs).
    source: Option<Model>,
    animated: Option<Animated>,
    /// The `[animation]` settings `animated` was built for.
    built_for: Option<(String, bool)>,
    /// The clip time last posed.
    posed_at: Option<f32>,
    /// The rest pose's stroke directions, for the direction preset they are of (the
    /// carried geometry, [`crate::preset::PoseGeometry::Carried`]).
    rest: Option<(crate::preset::DirectionPreset, Vec<glam::Vec3>)>,
    note: Option<String>,
}

impl Timeline {
    /// The timeline of a loaded model (inert for a model without a rig).
    pub fn new(model: &Model) -> Self {
        Self {
            source: model.rig.is_some().then(|| model.clone()),
            ..Self::default()
        }
    }

    /// Whether the model has a clip to play.
    pub fn has_clips(&self) -> bool {
        self.source
            .as_ref()
            .and_then(|m| m.rig.as_ref())
            .is_some_and(|r| !r.clips().is_empty())
    }

    /// The model's clip names.
    pub fn clip_names(&self) -> Vec<String> {
        self.animated
            .as_ref()
            .map_or_else(Vec::new, Animated::clip_names)
    }

    /// The clip playing (its index), if any.
    pub fn clip(&self) -> Option<usize> {
        self.animated.as_ref().and_then(Animated::clip)
    }

    /// The length of the clip playing, seconds.
    pub fn duration(&self) -> f32 {
        self.animated.as_ref().map_or(0.0, Animated::duration)
    }

    /// Why the clip asked for does not play, one line.
    pub fn note(&self) -> Option<&str> {
        self.note.as_deref()
    }

    /// Before a frame: (re)chooses the clip when the preset's changed, and poses the
    /// renderer at the state's clip time when that moved.
    ///
    /// # Errors
    /// [`AppError::Gpu`] when the pose cannot be written (the renderer keeps its model).
    pub fn update(
        &mut self,
        renderer: &mut Renderer,
        gpu: (&wgpu::Device, &wgpu::Queue),
        state: &ViewerState,
    ) -> Result<(), AppError> {
        let Some(source) = &self.source else {
            return Ok(());
        };
        let a = &state.preset.animation;
        let wanted = (a.clip.clone(), a.looped);
        if self.built_for.as_ref() != Some(&wanted) {
            let choice = ClipChoice::parse(Some(&a.clip));
            let (clip, note) = match resolve_clip(source, &choice) {
                Ok(c) => (c, None),
                Err(e) => (None, Some(format!("{e}; the bind pose is drawn"))),
            };
            let playback = Playback {
                looped: a.looped,
                ..Playback::default()
            };
            self.animated = Some(Animated::new(source.clone(), clip, playback)?);
            self.note = note;
            self.built_for = Some(wanted);
            self.posed_at = None;
            self.rest = None;
        }
        let Some(animated) = &self.animated else {
            return Ok(());
        };
        let t = if animated.plays() {
            state.clip_time
        } else {
            0.0
        };
        if self.posed_at != Some(t) {
            let which = state.preset.hatching.direction;
            let carry = state.preset.effect.is_hatching()
                && a.geometry == crate::preset::PoseGeometry::Carried;
            if carry && self.rest.as_ref().is_none_or(|(w, _)| *w != which) {
                self.rest = Some((which, animated.rest_directions(which)));
            }
            let rest = carry
                .then(|| self.rest.as_ref().map(|(_, r)| r.as_slice()))
                .flatten();
            crate::animation::set_pose_at(renderer, gpu, animated, t, &state.preset, rest)?;
            self.posed_at = Some(t);
        }
        Ok(())
    }
}
