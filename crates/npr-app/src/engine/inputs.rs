//! What a preset means for each pass: the base material and shading model, the clear
//! colour, the highlight shape and controls (Lee & Choi §3.4) with the user's edits, and
//! the antialiasing of full renders.

use crate::preset::{Effect, Preset};
use glam::{Mat4, Vec2, Vec3};
use npr_gpu::{ObjectUniforms, ShadingModel};
use npr_specular::{HighlightControls, HighlightSet, HighlightShape};

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

/// The settings each frame reads of a preset (Lee & Choi §3.4's global controls, the
/// boundary), with the highlight pass's texture layer of its shape.
pub fn frame_tuning(preset: &Preset, layer: u32) -> npr_specular::HighlightTuning {
    let mut tuning = npr_specular::SpecularSettings::from(&preset.specular).tuning;
    tuning.controls.texture_layer = layer;
    tuning
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
    set.tuning = frame_tuning(preset, layer);
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
