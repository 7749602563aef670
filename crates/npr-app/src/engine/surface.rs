//! Per-model surface fields the engine computes once and keeps: the stroke directions of
//! each direction preset and the mean curvature. A new model drops them.

use crate::preset::DirectionPreset;
use glam::Vec3;
use npr_geometry::{CurvatureOptions, Mesh};
use std::collections::HashMap;

/// The fields computed so far for one model (see the module docs).
#[derive(Default)]
pub(crate) struct SurfaceFields {
    directions: HashMap<DirectionPreset, Vec<Vec3>>,
    curvature: Option<Vec<f32>>,
}

impl SurfaceFields {
    /// The per-vertex stroke directions of `which`, computed on first use.
    pub(crate) fn directions(&mut self, mesh: &Mesh, which: DirectionPreset) -> &[Vec3] {
        self.directions
            .entry(which)
            .or_insert_with(|| stroke_directions(mesh, which))
    }

    /// Sets the directions of `which` (computed elsewhere: carried through a skinning).
    pub(crate) fn seed_directions(&mut self, which: DirectionPreset, directions: Vec<Vec3>) {
        self.directions.insert(which, directions);
    }

    /// The directions of `which`, if computed already.
    pub(crate) fn cached_directions(&self, which: DirectionPreset) -> Option<&[Vec3]> {
        self.directions.get(&which).map(Vec::as_slice)
    }

    /// Signed mean curvature per render vertex times `radius` (see
    /// [`super::Renderer::mean_curvature`]), computed on first use.
    pub(crate) fn mean_curvature(&mut self, mesh: &Mesh, radius: f32) -> &[f32] {
        self.curvature
            .get_or_insert_with(|| mean_curvature(mesh, radius))
    }

    /// The mean curvature, if computed already.
    pub(crate) fn cached_mean_curvature(&self) -> Option<&[f32]> {
        self.curvature.as_deref()
    }
}

/// `(κ_max + κ_min) / 2 · radius` per render vertex; 0 where undefined.
fn mean_curvature(mesh: &Mesh, radius: f32) -> Vec<f32> {
    let (welded, _, field) =
        npr_geometry::CurvatureField::for_mesh(mesh, &CurvatureOptions::default());
    let field = field.to_render(&welded.render_to_welded);
    (0..mesh.vertex_count())
        .map(|v| {
            if field.valid.get(v).copied().unwrap_or(false) {
                0.5 * (field.kappa_max[v] + field.kappa_min[v]) * radius
            } else {
                0.0
            }
        })
        .collect()
}

/// The stroke directions of a direction preset.
pub(crate) fn stroke_directions(mesh: &Mesh, which: DirectionPreset) -> Vec<Vec3> {
    use npr_hatching::{DirectionSource, StrokeDirection};
    let (source, dir) = match which {
        DirectionPreset::Smooth => (DirectionSource::default(), StrokeDirection::KappaMax),
        DirectionPreset::SmoothCurvatureOnly => (
            DirectionSource::Smooth(npr_geometry::StrokeFieldOptions::curvature_only()),
            StrokeDirection::KappaMax,
        ),
        DirectionPreset::KMax => (DirectionSource::Principal, StrokeDirection::KappaMax),
        DirectionPreset::KMin => (DirectionSource::Principal, StrokeDirection::KappaMin),
    };
    npr_hatching::stroke_directions(mesh, &source, dir, &CurvatureOptions::default(), Vec3::Y)
}
