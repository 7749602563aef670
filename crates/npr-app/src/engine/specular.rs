//! The stylized highlights (Lee & Choi) in the engine: the highlight setup
//! (`npr_specular::HighlightSetup`: the set and its backend), specialised by its
//! curvature smoothing, abstraction and backend setting, and the highlight pass,
//! specialised by its texture shape. A new shape keeps the set (and its tracked
//! highlights); new smoothing keeps the pass.

use super::FrameStats;
use super::inputs::{anchor_reach, apply_controls, builtin_shape};
use super::specialized::Specialized;
use crate::AppError;
use crate::model::Model;
use crate::preset::{BackendPreset, Preset};
use crate::view::View;
use npr_gpu::{FrameId, FrameUniforms, GpuMesh, ObjectUniforms, Prepared, TargetFormats};
use npr_specular::{
    HighlightObject, HighlightPass, HighlightSet, HighlightSetup, HighlightShape, SetupInput,
    SetupObject, SetupSettings, SpecularSettings,
};

/// What the highlight set is built for: the curvature smoothing (edge lengths) and the
/// abstraction scale, as bit patterns so that the key hashes, and the backend setting.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct SetKey {
    smoothing_edges: u32,
    abstraction: u32,
    backend: BackendPreset,
}

impl SetKey {
    fn of(preset: &Preset) -> Self {
        Self {
            smoothing_edges: preset.specular.smoothing_edges.to_bits(),
            abstraction: preset.specular.abstraction.to_bits(),
            backend: preset.specular.backend,
        }
    }
}

/// The highlight pass of one texture shape (a built-in name or a PNG path), the model's
/// object in it and the shape's texture layer.
struct ShapePass {
    pass: HighlightPass,
    object: HighlightObject,
    layer: u32,
}

/// The highlight setup and pass (see the module docs).
#[derive(Default)]
pub(crate) struct SpecularEffect {
    /// The setup's pass and the model's object in it (its set and backend), built for
    /// the preset's smoothing and abstraction.
    setup: Specialized<SetKey, (HighlightSetup, SetupObject)>,
    shape: Specialized<String, ShapePass>,
    /// The adapter the backend is chosen for (the renderer's context's).
    adapter: Option<wgpu::AdapterInfo>,
}

impl SpecularEffect {
    /// The adapter frames are drawn on, for the backend's rule; a set built before keeps
    /// its backend until the next model.
    pub(crate) fn set_adapter(&mut self, adapter: wgpu::AdapterInfo) {
        self.adapter = Some(adapter);
    }

    /// The model moved to a new pose (same triangles): the next frame takes it
    /// ([`SetupObject::repose`]), keeping its highlights' ids, fades and edits.
    pub(crate) fn repose(&mut self) {
        if let Some((_, object)) = self.setup.get_mut() {
            object.repose();
        }
    }

    /// The highlight set, once a specular frame has been prepared.
    pub(crate) fn set(&self) -> Option<&HighlightSet> {
        self.setup.get().map(|(_, object)| object.set())
    }

    /// Forgets highlight tracking (the next frame starts a new sequence).
    pub(crate) fn reset(&mut self) {
        if let Some((_, object)) = self.setup.get_mut() {
            object.reset();
        }
    }

    /// Drops everything (a new model).
    pub(crate) fn clear(&mut self) {
        self.setup.clear();
        self.shape.clear();
    }

    /// The frame's highlights for `view` ([`HighlightSetup::prepare`] and `record`, the
    /// GPU backend's stages recorded into `encoder` ahead of the frame's render pass),
    /// prepared for the highlight draw; the setup's figures into `stats`.
    ///
    /// # Errors
    /// A highlight texture that cannot be loaded, or a mesh the set cannot use.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn prepare(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        (model, mesh): (&Model, &GpuMesh),
        preset: &Preset,
        view: &View,
        (frame, uniforms, object): (FrameId, &FrameUniforms, &ObjectUniforms),
        stats: &mut FrameStats,
    ) -> Result<Prepared, AppError> {
        let sp = &preset.specular;
        let shape = self.shape.get_or_build(&sp.shape, |shape| {
            ShapePass::new(device, queue, mesh, shape)
        })?;
        let unknown = npr_specular::setup::backend::unknown_adapter();
        let adapter = self.adapter.as_ref().unwrap_or(&unknown);
        let (setup, setup_object) = self.setup.get_or_build(&SetKey::of(preset), |_| {
            let pass_settings = SetupSettings {
                normal_maps: shape.pass.normal_map_layers().to_vec(),
            };
            let setup = HighlightSetup::new(device, queue, &pass_settings);
            let settings = SpecularSettings::from(sp);
            let object = setup.create_object(device, queue, &model.mesh, &settings, adapter)?;
            Ok::<_, AppError>((setup, object))
        })?;
        let frame_of = (view.light_eye(), view.world_from_object);
        let object_uniforms = object;
        let object = setup_object;
        if object.set().highlights().is_empty() && sp.edits.iter().any(|e| e.anchor.is_some()) {
            // A fresh sequence: find the highlights once so that anchored edits can be
            // matched to their ids. Updating again with the same light and eye matches
            // every highlight to itself (same ids, full opacity), now with the edits
            // applied.
            object.update_now(&model.mesh, frame_of)?;
        }
        apply_controls(
            object.set_mut(),
            preset,
            shape.layer,
            anchor_reach(&model.framing),
        );
        let input = SetupInput {
            frame,
            light_eye: frame_of.0,
            world_from_object: frame_of.1,
            mesh: &model.mesh,
            gpu: mesh,
        };
        let prepared = setup.prepare(device, queue, object, &input)?;
        let highlights = setup.record(encoder, object, &prepared)?;
        let drawn = shape.pass.prepare(
            queue,
            &mut shape.object,
            &npr_specular::HighlightInput {
                frame,
                highlights: &highlights,
                view: uniforms,
                object: object_uniforms,
            },
        )?;
        let st = object.stats();
        stats.setup_us = st.cpu_us;
        stats.highlights = st.highlights;
        stats.receiver_faces = st.receiver_faces;
        stats.pose_on_gpu = st.pose_on_gpu;
        stats.backend = Some(object.choice().to_string());
        Ok(drawn)
    }

    /// After the frame's submission: asks for the GPU frame's highlights (the panel and
    /// picking, one frame late).
    pub(crate) fn after_submit(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) {
        if let Some((setup, object)) = self.setup.get_mut() {
            setup.after_submit(device, queue, object);
        }
    }

    /// Draws the highlights prepared as `prepared`.
    ///
    /// # Errors
    /// A [`npr_gpu::PassError`] for a stale ticket.
    pub(crate) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        prepared: &Prepared,
    ) -> Result<(), AppError> {
        if let Some(shape) = self.shape.get() {
            shape.pass.draw(pass, &shape.object, prepared)?;
        }
        Ok(())
    }
}

impl ShapePass {
    /// The pass for a built-in shape name, or for a PNG (then an extra layer after the
    /// built-in ones, at 128 × 128).
    fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &GpuMesh,
        shape: &str,
    ) -> Result<Self, AppError> {
        let formats = TargetFormats::default();
        let (pass, layer) = if let Some(builtin) = builtin_shape(shape) {
            let pass = HighlightPass::new(device, queue, formats, &Default::default())?;
            (pass, builtin.layer())
        } else {
            let size = 128;
            let mut layers = npr_specular::textures::builtin_set(size);
            let mut normal: Vec<bool> = HighlightShape::ALL
                .iter()
                .map(|s| s.is_normal_map())
                .collect();
            layers.push(npr_specular::textures::load_png(
                std::path::Path::new(shape),
                size,
            )?);
            normal.push(false);
            let layer = (layers.len() - 1) as u32;
            let pass = HighlightPass::with_textures(device, queue, formats, &layers, &normal)?;
            (pass, layer)
        };
        let object = pass.create_object(device, mesh);
        Ok(Self {
            pass,
            object,
            layer,
        })
    }
}
