//! Real-time hatching (Kim & Lee) in the engine: the hatching frame (VSM, G-buffer and
//! composite) specialised by the target size, the shadow setting and the stroke
//! directions; the tonal art map of each style is generated once, kept, and swapped into
//! the frame when the style changes.

use super::specialized::Specialized;
use super::surface::SurfaceFields;
use crate::AppError;
use crate::model::Model;
use crate::preset::{DirectionPreset, Effect, Preset};
use crate::view::View;
use glam::Vec3;
use npr_gpu::{FrameId, GpuMesh, ObjectUniforms, TargetFormats};
use npr_hatching::{HatchFrame, HatchObject, HatchParams, ShadowLight, TamParams, TonalArtMap};
use std::collections::HashMap;

/// What a hatching frame is built for.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct HatchKey {
    size: (u32, u32),
    shadows: bool,
    direction: DirectionPreset,
}

/// A hatching frame, the model's object in it, and which map it draws with (a new style
/// swaps the map in the frame, `HatchFrame::set_tam`, rather than rebuilding the frame and
/// its shadow and G-buffer targets).
struct HatchState {
    frame: HatchFrame,
    object: HatchObject,
    pencil: bool,
    /// The pose its object's stroke directions were computed on.
    pose: u64,
}

/// The hatching effect (see the module docs).
#[derive(Default)]
pub(crate) struct HatchingEffect {
    tams: HashMap<bool, TonalArtMap>,
    frame: Specialized<HatchKey, HatchState>,
    /// Poses of the model so far ([`HatchingEffect::repose`]).
    pose: u64,
}

impl HatchingEffect {
    /// The model moved to a new pose (same triangles): the stroke directions are taken
    /// again on the next frame; the frame and its maps stay.
    pub(crate) fn repose(&mut self) {
        self.pose += 1;
    }

    /// Drops the frame (a new model); the generated maps stay.
    pub(crate) fn clear(&mut self) {
        self.frame.clear();
    }

    /// The G-buffer of the last hatched frame, read back (submits and waits).
    ///
    /// # Errors
    /// [`AppError::Hatching`] when readback fails.
    pub(crate) fn read_inputs(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<npr_hatching::HatchInputs>, AppError> {
        match self.frame.get() {
            Some(h) => Ok(Some(h.frame.gbuffer.read(device, queue)?)),
            None => Ok(None),
        }
    }

    /// Which pixels the last hatched frame covers, read back (submits and waits); `None`
    /// before a hatched frame.
    ///
    /// # Errors
    /// [`AppError::Hatching`] when readback fails.
    pub(crate) fn read_mask(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<Vec<bool>>, AppError> {
        match self.frame.get() {
            Some(h) => Ok(Some(h.frame.gbuffer.read_surface_mask(device, queue)?)),
            None => Ok(None),
        }
    }

    /// Starts reading back the last hatched frame's G-buffer for the pen plotter (tone
    /// and θ, which pixels the object covers, the depth buffer); `None` before a hatched
    /// frame.
    ///
    /// # Errors
    /// [`AppError::Hatching`] when a copy cannot be set up.
    pub(crate) fn start_pen_read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<npr_hatching::GBufferReadback>, AppError> {
        match self.frame.get() {
            Some(h) => Ok(Some(h.frame.gbuffer.start_read(device, queue)?)),
            None => Ok(None),
        }
    }

    /// Prepares and records one hatched frame of `preset` at `view` into `color`.
    ///
    /// # Errors
    /// A map that cannot be generated, parameters the pass refuses, or a stale ticket.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        (model, mesh, fields): (&Model, &GpuMesh, &mut SurfaceFields),
        preset: &Preset,
        view: &View,
        (frame, clock, object): (FrameId, u64, &ObjectUniforms),
        encoder: &mut wgpu::CommandEncoder,
        (color, size): (&wgpu::TextureView, (u32, u32)),
    ) -> Result<(), AppError> {
        let h = &preset.hatching;
        let key = HatchKey {
            size,
            shadows: h.shadows,
            direction: h.direction,
        };
        let pencil = preset.effect == Effect::HatchingPencil;
        let tam = match self.tams.entry(pencil) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => {
                let p = if pencil {
                    TamParams::pencil()
                } else {
                    TamParams::pen()
                };
                e.insert(TonalArtMap::generate(&p)?)
            }
        };
        let state = self
            .frame
            .get_or_build(&key, |key| -> Result<_, AppError> {
                let settings = npr_hatching::HatchFrameSettings {
                    tam: tam.clone(),
                    scene: npr_hatching::SceneSettings {
                        vsm: npr_hatching::VsmSettings {
                            enabled: key.shadows,
                            ..Default::default()
                        },
                        ..Default::default()
                    },
                };
                let formats = TargetFormats::default();
                let frame = HatchFrame::new(device, queue, formats, &settings, key.size)?;
                let dirs = fields.directions(&model.mesh, key.direction);
                let object = frame.create_object(device, mesh, dirs)?;
                Ok(HatchState {
                    frame,
                    object,
                    pencil,
                    pose: self.pose,
                })
            })?;
        if state.pose != self.pose {
            // A new pose of the same mesh: new directions, the anchors kept, so the
            // strokes follow the moving surface.
            let dirs = fields.directions(&model.mesh, key.direction);
            state.frame.write_directions(queue, &state.object, dirs)?;
            state.pose = self.pose;
        }
        if state.pencil != pencil {
            state.frame.set_tam(device, queue, tam)?;
            state.pencil = pencil;
        }
        let params = HatchParams {
            bins: h.bins,
            stroke_scale: h.stroke_scale,
            mode: h.blend.into(),
            ink: h.ink,
            paper: h.paper,
            space: h.space.into(),
            ..HatchParams::default()
        };
        let light = ShadowLight::Directional {
            towards_light: view.light.position_or_direction,
            center: Vec3::ZERO,
            radius: 1.05,
        };
        let hatch_view = npr_hatching::HatchView {
            frame,
            clock,
            camera: &view.camera,
            light: &light,
            params: &params,
        };
        let prepared =
            state
                .frame
                .prepare(queue, &hatch_view, &mut [(&mut state.object, object)])?;
        state
            .frame
            .record(encoder, color, &[&state.object], &prepared)?;
        Ok(())
    }
}
