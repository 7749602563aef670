//! The renderer behind `npr render` and `npr view`: one model, one offscreen target, and
//! the GPU state of every effect, built lazily from the public API of the technique
//! crates and rebuilt only when a preset change needs it (a new curvature smoothing, a
//! new highlight texture, shadows toggled, a new size).

use crate::AppError;
use crate::model::Model;
use crate::preset::{DirectionPreset, Effect, Preset};
use crate::view::View;
use glam::{Mat4, Vec2, Vec3};
use npr_geometry::{CurvatureOptions, CurvatureRadius};
use npr_gpu::{
    BaseInput, BaseObject, BaseSettings, BaseShading, FrameId, FrameUniforms, GpuMesh,
    ObjectUniforms, OffscreenTarget, ShadingModel, TargetFormats,
};
use npr_hatching::{HatchFrame, HatchObject, HatchParams, ShadowLight, TamParams, TonalArtMap};
use npr_specular::{
    HighlightControls, HighlightObject, HighlightPass, HighlightSet, HighlightShape,
    ProjectorControls,
};
use serde::Serialize;
use std::collections::HashMap;
// std's `Instant::now()` panics in the browser (wasm32-unknown-unknown has no clock).
#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

/// Statistics of one rendered frame (`npr render --json`, the viewer's heads-up line).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameStats {
    /// Frame index in its sequence.
    pub frame: usize,
    /// The effect drawn.
    pub effect: String,
    /// CPU setup the frame waited on (N = H search, matching, BFS; warp: none), µs.
    pub setup_us: f64,
    /// Highlights drawn (specular).
    pub highlights: usize,
    /// Receiver faces of all highlights (specular).
    pub receiver_faces: usize,
    /// Triangles drawn (the proxy's for a warped frame).
    pub triangles: usize,
    /// Whether the frame was warped from references rather than rendered in full.
    pub warped: bool,
    /// Warp: PSNR of this frame against a full render of the same view, dB.
    pub psnr_db: Option<f64>,
}

/// Highlight state: the set (per model and curvature smoothing) and its pass.
struct SpecularState {
    smoothing_edges: f32,
    abstraction: f32,
    shape: String,
    set: HighlightSet,
    pass: HighlightPass,
    draw: HighlightObject,
    /// Texture layer and normal-map flag of the preset's shape.
    layer: u32,
}

/// Hatching state for one size and shadow setting.
struct HatchState {
    size: (u32, u32),
    shadows: bool,
    pencil: bool,
    frame: HatchFrame,
    object: HatchObject,
    direction: DirectionPreset,
    /// This frame's parameters (passed to every prepare).
    params: HatchParams,
}

/// Outline state: the normal + depth prepass and the full-screen pass.
struct OutlineState {
    size: (u32, u32),
    target: npr_gpu::outline::NormalDepthTarget,
    prepass: npr_gpu::outline::NormalDepthPass,
    object: npr_gpu::outline::OutlineObject,
    pass: npr_gpu::outline::OutlinePass,
    source: npr_gpu::outline::OutlineSource,
}

/// The fewest proxy triangles warping uses (see [`Renderer::warp_reference`]).
pub const MIN_PROXY_TRIANGLES: usize = 256;

/// Warping state: the proxy's warper and the base pass drawing its references.
struct WarpState {
    key: (
        u32,
        crate::preset::WarpMode,
        bool,
        crate::preset::WarpAntialiasing,
        (u32, u32),
        ShadingModel,
        Vec<u8>,
    ),
    warper: npr_warp::Warper,
    base: npr_warp::PhongBase,
    proxy_triangles: usize,
}

/// The multisampled full render of the warp effect (its `[warp] antialiasing` when that
/// multisamples): the base shading built for the sample count and the multisampled
/// textures it draws into, resolved into the renderer's target.
struct FullMsaaState {
    size: (u32, u32),
    antialiasing: npr_warp::Antialiasing,
    base: BaseShading,
    object: BaseObject,
    cel_bands: Vec<u8>,
    target: npr_warp::MsaaTarget,
}

/// The antialiasing of a preset's frames rendered in full: the warp's when the effect is
/// warping (so full frames, references and warped frames share it, and a warped frame is
/// measured against the full render the user would otherwise see), one sample otherwise.
pub fn full_render_antialiasing(preset: &Preset) -> npr_warp::Antialiasing {
    if preset.effect == Effect::Warp {
        preset.warp.antialiasing.into()
    } else {
        npr_warp::Antialiasing::None
    }
}

/// One model's renderer (see the module docs).
pub struct Renderer {
    model: Model,
    gpu_mesh: GpuMesh,
    target: OffscreenTarget,
    base: BaseShading,
    object: BaseObject,
    cel_bands: Vec<u8>,
    /// The id of the last submission (each frame, reference or warp is one).
    submission: FrameId,
    specular: Option<SpecularState>,
    hatching: Option<HatchState>,
    outline: Option<OutlineState>,
    warp: Option<WarpState>,
    full_msaa: Option<FullMsaaState>,
    tams: HashMap<bool, TonalArtMap>,
    directions: HashMap<DirectionPreset, Vec<Vec3>>,
    curvature: Option<Vec<f32>>,
    frame_index: usize,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("model", &self.model.name)
            .field("size", &(self.target.width, self.target.height))
            .finish_non_exhaustive()
    }
}

/// The base material of a preset for `effect`.
pub fn object_uniforms(preset: &Preset, world_from_object: Mat4) -> ObjectUniforms {
    let ks = if preset.effect == Effect::Specular {
        preset.specular.base_ks
    } else {
        preset.base.ks
    };
    ObjectUniforms::new(
        world_from_object,
        Vec3::from(preset.base.diffuse),
        ks,
        Vec3::ONE,
        preset.base.shininess,
    )
}

/// The base shading model drawn for a preset.
pub fn shading_model(preset: &Preset) -> ShadingModel {
    match preset.effect {
        Effect::Phong => ShadingModel::Phong,
        Effect::Gouraud => ShadingModel::Gouraud,
        Effect::Cel => ShadingModel::Cel,
        _ => preset.base.model.into(),
    }
}

/// The clear colour of a preset (linear RGBA).
pub fn clear_color(preset: &Preset) -> [f64; 4] {
    let [r, g, b] = preset.base.background;
    [f64::from(r), f64::from(g), f64::from(b), 1.0]
}

/// The highlight texture layer of a built-in shape name, if it is one.
pub fn builtin_shape(name: &str) -> Option<HighlightShape> {
    HighlightShape::ALL.into_iter().find(|s| s.name() == name)
}

/// The global projector controls of a preset (Lee & Choi §3.4).
pub fn global_controls(preset: &Preset, layer: u32) -> ProjectorControls {
    ProjectorControls {
        sigma: preset.specular.sigma,
        texture_layer: layer,
        up: preset.specular.up.into(),
        ..ProjectorControls::default()
    }
}

/// How far (object units) an edit's anchor may be from a highlight's found centre to
/// apply to it: 15 % of the model's bounding radius.
pub fn anchor_reach(framing: &crate::view::Framing) -> f32 {
    0.15 * framing.radius
}

/// The id each of the preset's edits applies to: an edit with an anchor goes to the
/// highlight whose found centre (object space) is nearest the anchor, within `reach`
/// (see [`anchor_reach`]); otherwise (or when none is that near) to its own id.
pub fn resolve_edit_ids(set: &HighlightSet, preset: &Preset, reach: f32) -> Vec<u64> {
    preset
        .specular
        .edits
        .iter()
        .map(|e| {
            let Some(anchor) = e.anchor.map(Vec3::from) else {
                return e.id;
            };
            set.highlights()
                .iter()
                .map(|h| (h.id, h.centre.position_object.distance(anchor)))
                .filter(|(_, d)| *d <= reach)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map_or(e.id, |(id, _)| id)
        })
        .collect()
}

/// Applies the preset's global controls and per-highlight edits to a set (edits with an
/// anchor go to the highlight nearest it among the set's current highlights, within
/// `reach`, see [`resolve_edit_ids`]).
pub fn apply_controls(set: &mut HighlightSet, preset: &Preset, layer: u32, reach: f32) {
    set.global = global_controls(preset, layer);
    set.boundary = preset.specular.boundary.into();
    let ids = resolve_edit_ids(set, preset, reach);
    for (e, id) in preset.specular.edits.iter().zip(ids) {
        *set.controls_mut(id) = HighlightControls {
            translate: Vec2::from(e.translate),
            rotate_rad: e.rotate_deg.to_radians(),
            scale: Vec2::from(e.scale),
            ..HighlightControls::default()
        };
    }
}

impl Renderer {
    /// Uploads `model` and creates a `width × height` target.
    ///
    /// # Errors
    /// [`AppError::Gpu`] for a size or mesh past the device's limits.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        model: Model,
        size: (u32, u32),
    ) -> Result<Self, AppError> {
        let gpu_mesh = GpuMesh::upload(device, &model.mesh)?;
        let target = OffscreenTarget::new(device, size.0, size.1)?;
        let base = BaseShading::new(device, queue, TargetFormats::default(), &ramp_settings(&[]));
        let object = base.create_object(device, &gpu_mesh);
        Ok(Self {
            model,
            gpu_mesh,
            target,
            base,
            object,
            cel_bands: Vec::new(),
            submission: FrameId::default(),
            specular: None,
            hatching: None,
            outline: None,
            warp: None,
            full_msaa: None,
            tams: HashMap::new(),
            directions: HashMap::new(),
            curvature: None,
            frame_index: 0,
        })
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The model on the GPU.
    pub fn gpu_mesh(&self) -> &GpuMesh {
        &self.gpu_mesh
    }

    /// The target the last frame was drawn into.
    pub fn target(&self) -> &OffscreenTarget {
        &self.target
    }

    /// Target size.
    pub fn size(&self) -> (u32, u32) {
        (self.target.width, self.target.height)
    }

    /// Replaces the model; the current one stays if the upload fails.
    ///
    /// # Errors
    /// As [`GpuMesh::upload`].
    pub fn set_model(&mut self, device: &wgpu::Device, model: Model) -> Result<(), AppError> {
        let gpu_mesh = GpuMesh::upload(device, &model.mesh)?;
        self.model = model;
        self.object = self.base.create_object(device, &gpu_mesh);
        self.gpu_mesh = gpu_mesh;
        self.specular = None;
        self.hatching = None;
        self.outline = None;
        self.warp = None;
        self.full_msaa = None;
        self.directions.clear();
        self.curvature = None;
        self.frame_index = 0;
        Ok(())
    }

    /// Resizes the target (a zero side is refused with a typed error; the old target
    /// stays).
    ///
    /// # Errors
    /// [`AppError::Gpu`] for an invalid size.
    pub fn resize(&mut self, device: &wgpu::Device, size: (u32, u32)) -> Result<(), AppError> {
        if size != self.size() {
            self.target = OffscreenTarget::new(device, size.0, size.1)?;
        }
        Ok(())
    }

    /// The highlight set, once a specular frame has been drawn.
    pub fn highlight_set(&self) -> Option<&HighlightSet> {
        self.specular.as_ref().map(|s| &s.set)
    }

    /// Forgets highlight tracking (the next frame starts a new sequence).
    pub fn reset_sequence(&mut self) {
        if let Some(s) = &mut self.specular {
            s.set.reset();
        }
        self.frame_index = 0;
    }

    fn ensure_specular(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
    ) -> Result<(), AppError> {
        let sp = &preset.specular;
        let rebuild_set = self.specular.as_ref().is_none_or(|s| {
            s.smoothing_edges != sp.smoothing_edges || s.abstraction != sp.abstraction
        });
        let rebuild_pass = self.specular.as_ref().is_none_or(|s| s.shape != sp.shape);
        if !rebuild_set && !rebuild_pass {
            return Ok(());
        }
        let (pass, layer) = if let Some(shape) = builtin_shape(&sp.shape) {
            (
                HighlightPass::new(device, queue, TargetFormats::default(), &Default::default())?,
                shape.layer(),
            )
        } else {
            let size = 128;
            let mut layers = npr_specular::textures::builtin_set(size);
            let mut normal: Vec<bool> = HighlightShape::ALL
                .iter()
                .map(|s| s.is_normal_map())
                .collect();
            layers.push(npr_specular::textures::load_png(
                std::path::Path::new(&sp.shape),
                size,
            )?);
            normal.push(false);
            let layer = (layers.len() - 1) as u32;
            (
                HighlightPass::with_textures(
                    device,
                    queue,
                    TargetFormats::default(),
                    &layers,
                    &normal,
                )?,
                layer,
            )
        };
        let set = match self.specular.take() {
            Some(s) if !rebuild_set => s.set,
            _ => HighlightSet::with_abstraction(
                &self.model.mesh,
                &CurvatureOptions {
                    radius: CurvatureRadius::EdgeLengths(sp.smoothing_edges),
                    ..CurvatureOptions::default()
                },
                sp.abstraction,
            )?,
        };
        let draw = pass.create_object(device, &self.gpu_mesh);
        self.specular = Some(SpecularState {
            smoothing_edges: sp.smoothing_edges,
            abstraction: sp.abstraction,
            shape: sp.shape.clone(),
            set,
            pass,
            draw,
            layer,
        });
        Ok(())
    }

    /// Signed mean curvature `(κ_max + κ_min) / 2` per render vertex, times the bounding
    /// radius (so a sphere reads 1 at any scale); 0 where undefined. Computed once per
    /// model.
    pub fn mean_curvature(&mut self) -> &[f32] {
        let (mesh, r) = (&self.model.mesh, self.model.framing.radius);
        self.curvature.get_or_insert_with(|| {
            let (welded, _, field) =
                npr_geometry::CurvatureField::for_mesh(mesh, &CurvatureOptions::default());
            let field = field.to_render(&welded.render_to_welded);
            (0..mesh.vertex_count())
                .map(|v| {
                    if field.valid.get(v).copied().unwrap_or(false) {
                        0.5 * (field.kappa_max[v] + field.kappa_min[v]) * r
                    } else {
                        0.0
                    }
                })
                .collect()
        })
    }

    /// The mean curvature of [`Renderer::mean_curvature`], if computed already.
    pub fn cached_mean_curvature(&self) -> Option<&[f32]> {
        self.curvature.as_deref()
    }

    /// The hatching G-buffer of the last hatched frame (tone and stroke angle per pixel),
    /// read back (submits and waits).
    ///
    /// # Errors
    /// [`AppError::Hatching`] when readback fails.
    pub fn hatch_inputs(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<npr_hatching::HatchInputs>, AppError> {
        match &self.hatching {
            Some(h) => Ok(Some(h.frame.gbuffer.read(device, queue)?)),
            None => Ok(None),
        }
    }

    /// The per-vertex stroke directions of `which`, if computed already (see
    /// [`Renderer::directions`]).
    pub fn cached_directions(&self, which: DirectionPreset) -> Option<&[Vec3]> {
        self.directions.get(&which).map(Vec::as_slice)
    }

    /// The per-vertex stroke directions of `which` (computed once per model).
    pub fn directions(&mut self, which: DirectionPreset) -> &[Vec3] {
        let mesh = &self.model.mesh;
        self.directions.entry(which).or_insert_with(|| {
            let (source, dir) = match which {
                DirectionPreset::Smooth => (
                    npr_hatching::DirectionSource::default(),
                    npr_hatching::StrokeDirection::KappaMax,
                ),
                DirectionPreset::SmoothCurvatureOnly => (
                    npr_hatching::DirectionSource::Smooth(
                        npr_geometry::StrokeFieldOptions::curvature_only(),
                    ),
                    npr_hatching::StrokeDirection::KappaMax,
                ),
                DirectionPreset::KMax => (
                    npr_hatching::DirectionSource::Principal,
                    npr_hatching::StrokeDirection::KappaMax,
                ),
                DirectionPreset::KMin => (
                    npr_hatching::DirectionSource::Principal,
                    npr_hatching::StrokeDirection::KappaMin,
                ),
            };
            npr_hatching::stroke_directions(
                mesh,
                &source,
                dir,
                &CurvatureOptions::default(),
                Vec3::Y,
            )
        })
    }

    fn ensure_hatching(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
    ) -> Result<(), AppError> {
        let pencil = preset.effect == Effect::HatchingPencil;
        let h = &preset.hatching;
        let params = HatchParams {
            bins: h.bins,
            stroke_scale: h.stroke_scale,
            mode: h.blend.into(),
            ink: h.ink,
            paper: h.paper,
            space: h.space.into(),
            ..HatchParams::default()
        };
        if let std::collections::hash_map::Entry::Vacant(e) = self.tams.entry(pencil) {
            let p = if pencil {
                TamParams::pencil()
            } else {
                TamParams::pen()
            };
            e.insert(TonalArtMap::generate(&p)?);
        }
        let size = self.size();
        let rebuild = self
            .hatching
            .as_ref()
            .is_none_or(|s| s.size != size || s.shadows != h.shadows || s.direction != h.direction);
        let Some(tam) = self.tams.get(&pencil) else {
            return Ok(());
        };
        if rebuild {
            let settings = npr_hatching::HatchFrameSettings {
                tam: tam.clone(),
                scene: npr_hatching::SceneSettings {
                    vsm: npr_hatching::VsmSettings {
                        enabled: h.shadows,
                        ..Default::default()
                    },
                    ..Default::default()
                },
            };
            let formats = TargetFormats::default();
            let frame = HatchFrame::new(device, queue, formats, &settings, (size.0, size.1))?;
            let direction = h.direction;
            let dirs = self.directions(direction).to_vec();
            let object = frame.create_object(device, &self.gpu_mesh, &dirs)?;
            self.hatching = Some(HatchState {
                size,
                shadows: preset.hatching.shadows,
                pencil,
                frame,
                object,
                direction,
                params,
            });
            return Ok(());
        }
        if let Some(state) = &mut self.hatching {
            if state.pencil != pencil {
                state.frame.set_tam(device, queue, tam)?;
                state.pencil = pencil;
            }
            state.params = params;
        }
        Ok(())
    }

    /// Renders one frame of `preset` seen from `view` into the target and submits it. The
    /// warp effect's full render is multisampled as its `[warp] antialiasing` says (see
    /// [`full_render_antialiasing`]), resolved into the target.
    ///
    /// # Errors
    /// A technique's typed error (bad texture, bad parameters, ...).
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
        view: &View,
    ) -> Result<FrameStats, AppError> {
        let mut stats = FrameStats {
            frame: self.frame_index,
            effect: preset.effect.name().to_string(),
            triangles: self.model.mesh.triangle_count(),
            ..FrameStats::default()
        };
        let clock = self.frame_index as u64;
        self.frame_index += 1;
        let submission = self.next_submission();
        let object = object_uniforms(preset, view.world_from_object);
        let frame = FrameUniforms::new(&view.camera, &view.light);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr app frame"),
        });
        let base_input = BaseInput {
            frame: submission,
            view: &frame,
            object: &object,
            model: shading_model(preset),
        };
        match preset.effect {
            Effect::HatchingPen | Effect::HatchingPencil => {
                self.ensure_hatching(device, queue, preset)?;
                if let Some(h) = &mut self.hatching {
                    let light = ShadowLight::Directional {
                        towards_light: view.light.position_or_direction,
                        center: Vec3::ZERO,
                        radius: 1.05,
                    };
                    let hatch_view = npr_hatching::HatchView {
                        frame: submission,
                        clock,
                        camera: &view.camera,
                        light: &light,
                        params: &h.params,
                    };
                    let prepared =
                        h.frame
                            .prepare(queue, &hatch_view, &mut [(&mut h.object, &object)])?;
                    h.frame.record(
                        &mut encoder,
                        &self.target.color_view,
                        &[&h.object],
                        &prepared,
                    )?;
                }
            }
            Effect::Warp if full_render_antialiasing(preset).is_multisampled() => {
                self.ensure_full_msaa(device, queue, preset)?;
                if let Some(m) = &mut self.full_msaa {
                    let prepared = m.base.prepare(queue, &mut m.object, &base_input)?;
                    let mut pass = m.target.begin_pass(
                        &mut encoder,
                        &self.target.color_view,
                        Some(clear_color(preset)),
                    );
                    m.base.draw(&mut pass, &m.object, &prepared)?;
                }
            }
            effect => {
                self.set_ramp(device, queue, &preset.base.cel_bands);
                let base = self.base.prepare(queue, &mut self.object, &base_input)?;
                if effect == Effect::Specular {
                    self.ensure_specular(device, queue, preset)?;
                }
                let mut highlights = None;
                if let Some(s) = self
                    .specular
                    .as_mut()
                    .filter(|_| effect == Effect::Specular)
                {
                    let reach = anchor_reach(&self.model.framing);
                    let started = Instant::now();
                    if s.set.highlights().is_empty()
                        && preset.specular.edits.iter().any(|e| e.anchor.is_some())
                    {
                        // A fresh sequence: find the highlights once so that anchored
                        // edits can be matched to their ids. Updating again with the same
                        // light and eye matches every highlight to itself (same ids, full
                        // opacity), now with the edits applied.
                        s.set.update(view.light_eye(), view.world_from_object);
                    }
                    apply_controls(&mut s.set, preset, s.layer, reach);
                    s.set.update(view.light_eye(), view.world_from_object);
                    stats.setup_us = started.elapsed().as_secs_f64() * 1e6;
                    let st = s.set.stats();
                    stats.highlights = st.highlights;
                    stats.receiver_faces = st.receiver_faces;
                    let input = npr_specular::HighlightInput {
                        frame: submission,
                        indices: &self.model.mesh.indices,
                        set: &s.set,
                        view: &frame,
                        object: &object,
                        list: None,
                    };
                    highlights = Some(s.pass.prepare(queue, &mut s.draw, &input)?);
                }
                let mut pass = self
                    .target
                    .begin_clear_pass(&mut encoder, clear_color(preset));
                self.base.draw(&mut pass, &self.object, &base)?;
                if let (Some(s), Some(prepared)) = (&self.specular, &highlights) {
                    s.pass.draw(&mut pass, &s.draw, prepared)?;
                }
            }
        }
        if preset.outline.enabled {
            self.record_outline(device, queue, &mut encoder, preset, view, submission)?;
        }
        queue.submit(Some(encoder.finish()));
        Ok(stats)
    }

    /// The id of the next submission.
    fn next_submission(&mut self) -> FrameId {
        self.submission = self.submission.next();
        self.submission
    }

    /// Builds (or keeps) the multisampled full render of the warp effect for the target's
    /// size, the preset's antialiasing and its cel bands.
    fn ensure_full_msaa(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
    ) -> Result<(), AppError> {
        let antialiasing = full_render_antialiasing(preset);
        let size = self.size();
        let keep = self
            .full_msaa
            .as_ref()
            .is_some_and(|m| m.size == size && m.antialiasing == antialiasing);
        if !keep {
            let formats = antialiasing.references(TargetFormats::default());
            let target = npr_warp::MsaaTarget::new(device, size.0, size.1, formats)?;
            let base = BaseShading::new(device, queue, formats, &ramp_settings(&[]));
            let object = base.create_object(device, &self.gpu_mesh);
            self.full_msaa = Some(FullMsaaState {
                size,
                antialiasing,
                base,
                object,
                cel_bands: Vec::new(),
                target,
            });
        }
        if let Some(m) = &mut self.full_msaa {
            set_ramp(
                device,
                queue,
                (&mut m.base, &mut m.object),
                &mut m.cel_bands,
                &preset.base.cel_bands,
            );
        }
        Ok(())
    }

    fn ensure_warp(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
        view: &View,
    ) -> Result<(), AppError> {
        let w = &preset.warp;
        let model = preset.base.model.into();
        let key = (
            w.proxy_ratio.to_bits(),
            w.mode,
            w.depth_test,
            w.antialiasing,
            self.size(),
            model,
            preset.base.cel_bands.clone(),
        );
        if self.warp.as_ref().is_some_and(|s| s.key == key) {
            return Ok(());
        }
        // A proxy needs some triangles to carry the references: keep at least
        // MIN_PROXY_TRIANGLES (all of a smaller mesh) whatever the ratio.
        let tris = self.model.mesh.triangle_count().max(1);
        let ratio = w
            .proxy_ratio
            .max((MIN_PROXY_TRIANGLES as f32 / tris as f32).min(1.0));
        let proxy = npr_warp::Proxy::simplify(&self.model.mesh, ratio)?;
        let antialiasing = npr_warp::Antialiasing::from(w.antialiasing);
        let references = antialiasing.references(TargetFormats::default());
        let warper = npr_warp::Warper::new(
            device,
            queue,
            &proxy,
            w.departures(),
            1.0 / self.model.framing.radius,
            self.size(),
            (
                references,
                antialiasing.warp_target(TargetFormats::default()),
            ),
        )?;
        let shades: Vec<[u8; 4]> = preset
            .base
            .cel_bands
            .iter()
            .map(|&g| [g, g, g, 255])
            .collect();
        let base = npr_warp::PhongBase::new(
            &self.gpu_mesh,
            view.light,
            object_uniforms(preset, view.world_from_object),
            references,
        )
        .with_model(model, Some(npr_gpu::toon_ramp(256, &shades)));
        self.warp = Some(WarpState {
            key,
            warper,
            base,
            proxy_triangles: proxy.mesh.triangle_count(),
        });
        Ok(())
    }

    /// Warping (Park & Ihm): records a reference of the full model at `view` (its base shading
    /// per the preset) and submits it. From then on warps interpolate between the previous
    /// newest reference (s = 0) and this one (s = 1).
    ///
    /// # Errors
    /// [`AppError::Warp`] for a proxy or setting the warp cannot use.
    pub fn warp_reference(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
        view: &View,
    ) -> Result<(), AppError> {
        self.ensure_warp(device, queue, preset, view)?;
        let Some(w) = &mut self.warp else {
            return Ok(());
        };
        w.base
            .set_lighting(view.light, object_uniforms(preset, view.world_from_object));
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr app warp reference"),
        });
        let pose = warp_view(view);
        let frame = self.submission.next();
        self.submission = frame;
        w.warper
            .record_reference(device, queue, &mut encoder, &mut w.base, frame, &pose)?;
        queue.submit(Some(encoder.finish()));
        Ok(())
    }

    /// References recorded so far.
    pub fn warp_references(&self) -> u64 {
        self.warp
            .as_ref()
            .map_or(0, |w| w.warper.references_recorded())
    }

    /// Warping (Park & Ihm): draws the proxy textured by the two newest references at `view`,
    /// at position `s` between them (`None`: estimated from the eye, as for an unknown
    /// path), over the preset's background, into the target, and submits it.
    ///
    /// # Errors
    /// As [`Renderer::warp_reference`].
    pub fn warp_frame(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
        view: &View,
        s: Option<f32>,
    ) -> Result<FrameStats, AppError> {
        self.ensure_warp(device, queue, preset, view)?;
        let mut stats = FrameStats {
            frame: self.frame_index,
            effect: preset.effect.name().to_string(),
            warped: true,
            ..FrameStats::default()
        };
        self.frame_index += 1;
        let submission = self.next_submission();
        let Some(w) = &mut self.warp else {
            return Ok(stats);
        };
        stats.triangles = w.proxy_triangles;
        let pose = warp_view(view);
        let s = s.unwrap_or_else(|| w.warper.position(&pose));
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr app warp"),
        });
        if w.warper.antialiasing().warp_is_multisampled() {
            // The warper's own multisampled pass, resolved into the target.
            let (color, depth) = (&self.target.color_view, &self.target.depth_view);
            w.warper.clear = clear_color(preset);
            w.warper
                .record_warp(queue, &mut encoder, (color, depth), submission, &pose, s)?;
        } else {
            let prepared = w.warper.prepare(queue, submission, &pose, s)?;
            let mut pass = self
                .target
                .begin_clear_pass(&mut encoder, clear_color(preset));
            if let Some(prepared) = &prepared {
                w.warper.draw(&mut pass, prepared)?;
            }
        }
        if preset.outline.enabled {
            self.record_outline(device, queue, &mut encoder, preset, view, submission)?;
        }
        queue.submit(Some(encoder.finish()));
        Ok(stats)
    }

    /// Records the outline prepass and pass over the target (`npr_gpu::outline`).
    fn record_outline(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        preset: &Preset,
        view: &View,
        frame: FrameId,
    ) -> Result<(), AppError> {
        use npr_gpu::outline::{
            NormalDepthInput, NormalDepthPass, NormalDepthTarget, OutlineInput, OutlinePass,
        };
        let size = self.size();
        if self.outline.as_ref().is_none_or(|o| o.size != size) {
            let prepass = NormalDepthPass::new(device, queue);
            let object = prepass.create_object(device, &self.gpu_mesh);
            let target = NormalDepthTarget::new(device, size.0, size.1)?;
            let pass = OutlinePass::new(device, queue, TargetFormats::default());
            let source = pass.create_object(device, &target);
            self.outline = Some(OutlineState {
                size,
                target,
                object,
                prepass,
                pass,
                source,
            });
        }
        if let Some(o) = &mut self.outline {
            let input = NormalDepthInput {
                frame,
                camera: &view.camera,
                world_from_object: view.world_from_object,
            };
            let prepared = o.prepass.prepare(queue, &mut o.object, &input)?;
            let settings = preset.outline.settings();
            let input = OutlineInput {
                frame,
                settings: &settings,
            };
            let lines = o.pass.prepare(queue, &mut o.source, &input)?;
            o.prepass
                .record(encoder, &o.target, &[(&o.object, &prepared)])?;
            let mut pass = npr_gpu::render::begin_color_pass(
                encoder,
                "npr app outline",
                &self.target.color_view,
                wgpu::LoadOp::Load,
            );
            o.pass.draw(&mut pass, &o.source, &lines)?;
        }
        Ok(())
    }

    fn set_ramp(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bands: &[u8]) {
        set_ramp(
            device,
            queue,
            (&mut self.base, &mut self.object),
            &mut self.cel_bands,
            bands,
        );
    }

    /// Reads the target back as an sRGB image (waits for the GPU).
    ///
    /// # Errors
    /// [`AppError::Gpu`] when readback fails.
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<image::RgbaImage, AppError> {
        Ok(npr_gpu::readback_rgba(device, queue, &self.target.color)?)
    }
}

/// The base shading settings of a cel ramp of `bands` (grey levels, darkest first; none:
/// npr-gpu's default ramp).
fn ramp_settings(bands: &[u8]) -> BaseSettings {
    if bands.is_empty() {
        return BaseSettings::default();
    }
    let shades: Vec<[u8; 4]> = bands.iter().map(|&g| [g, g, g, 255]).collect();
    BaseSettings {
        ramp: npr_gpu::toon_ramp(256, &shades),
    }
}

/// Rebuilds `base` (and its object) for the cel ramp of `bands` unless `current` (the
/// bands it has) equals them: the ramp is a setting, uploaded once per pass.
fn set_ramp(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    (base, object): (&mut BaseShading, &mut BaseObject),
    current: &mut Vec<u8>,
    bands: &[u8],
) {
    if current.as_slice() == bands {
        return;
    }
    *base = BaseShading::new(device, queue, base.formats(), &ramp_settings(bands));
    *object = base.create_object(device, object.mesh());
    *current = bands.to_vec();
}

/// Renders `frames` turntable frames with warping (Park & Ihm): along the known path, a
/// reference every `k` frames (rendered one interval ahead), the frames between warped
/// from the two around them at the path's own fraction, and each warped frame compared
/// with a full render of the same view (PSNR in the stats). Reference frames are the full
/// render itself. Full renders use the warp's antialiasing (see
/// [`full_render_antialiasing`]), so with `msaa4` or `msaa4-blend` every frame of the
/// turntable is antialiased and the PSNR is against the multisampled full render.
///
/// # Errors
/// GPU or technique errors, or what `sink` returns.
// Batch only (a progress bar; PSNR from npr-warp's test-support metrics): native only.
#[cfg(not(target_arch = "wasm32"))]
pub fn render_warp_frames(
    ctx: &npr_gpu::GpuContext,
    model: Model,
    preset: &Preset,
    frames: u32,
    mut sink: impl FnMut(usize, image::RgbaImage, &FrameStats) -> Result<(), AppError>,
) -> Result<Vec<FrameStats>, AppError> {
    let size = (preset.output.width, preset.output.height);
    let framing = model.framing;
    let k = preset.warp.k.max(1) as usize;
    let view_at = |i: usize| {
        View::new(
            preset,
            &framing,
            size,
            360.0 * i as f32 / frames.max(1) as f32,
        )
    };
    let mut renderer = Renderer::new(&ctx.device, &ctx.queue, model, size)?;
    let bar = crate::progress::bar(u64::from(frames), "warp");
    let mut stats = Vec::new();
    for i in 0..frames as usize {
        let view = view_at(i);
        if i % k == 0 {
            if i == 0 {
                renderer.warp_reference(&ctx.device, &ctx.queue, preset, &view)?;
            }
            renderer.warp_reference(&ctx.device, &ctx.queue, preset, &view_at(i + k))?;
        }
        let full_stats = renderer.render(&ctx.device, &ctx.queue, preset, &view)?;
        let full = renderer.read(&ctx.device, &ctx.queue)?;
        if i % k == 0 {
            sink(i, full, &full_stats)?;
            stats.push(FrameStats {
                frame: i,
                ..full_stats
            });
        } else {
            let s = (i % k) as f32 / k as f32;
            let mut st = renderer.warp_frame(&ctx.device, &ctx.queue, preset, &view, Some(s))?;
            let warped = renderer.read(&ctx.device, &ctx.queue)?;
            st.frame = i;
            st.psnr_db = Some(npr_warp::metrics::compare(&full, &warped).psnr_db);
            sink(i, warped, &st)?;
            stats.push(st);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(stats)
}

/// The warp pose of a view.
pub fn warp_view(view: &View) -> npr_warp::ObjectView {
    npr_warp::ObjectView {
        camera: view.camera,
        world_from_object: view.world_from_object,
    }
}
