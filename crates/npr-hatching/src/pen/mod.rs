//! Hatching for pen plotters: the raster hatching's per-pixel inputs (tone after shading
//! and shadows, the stroke direction θ, which pixels the object covers, and the depth
//! buffer, all read back from the G-buffer the passes already draw) traced into vector
//! strokes, written as SVG ([`to_svg`]).
//!
//! - Hatching strokes follow θ as evenly spaced streamlines (Jobard and Lefer 1997),
//!   spaced so that their ink matches the tone: a pen of width `w` at spacing `d` inks
//!   `w / d` of the paper, so the spacing is `w / (1 − tone)`. The hatching's tone levels
//!   become spacing levels ([`PenSettings::levels`]).
//! - Past [`PenSettings::cross_from`], a second layer crosses the first at θ + 90°; two
//!   layers of share `c` ink `1 − (1 − c)²`, which sets `c`.
//! - Strokes stop at the object's edge and at its visible silhouettes (where the depth
//!   jumps), and never cross them.
//! - Outlines, the silhouettes and creases of the mesh, are polylines with their hidden
//!   parts removed against the depth buffer.

mod field;
mod order;
mod outline;
mod streamlines;
mod svg;

pub use outline::OutlineView;
pub use streamlines::Polyline;
pub use svg::{MIN_OUTLINE_MM, Page, PlotStats, page_layers, plot_stats, to_svg};

use crate::{HatchError, HatchInputs};
use npr_geometry::Mesh;

/// How the strokes are traced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PenSettings {
    /// The pen's width in view pixels (see [`Page::pen_px`]).
    pub pen_px: f32,
    /// Tone levels: the darkness `1 − tone` is rounded to multiples of `1 / levels`, each
    /// a spacing level. 8 by default.
    pub levels: u32,
    /// Darkness past which the cross-hatching is drawn, 0.5 by default.
    pub cross_from: f32,
    /// A stroke stops when another comes closer than this share of the spacing
    /// (Jobard and Lefer's `d_test / d_sep`), 0.6 by default: at 0.75 strokes stop early
    /// and leave gaps, at 0.5 converging strokes over-ink (`docs/results.md`, "Pen plotter
    /// SVG").
    pub test_ratio: f32,
    /// Integration step along a stroke, view pixels (1 by default).
    pub step_px: f32,
    /// Strokes shorter than this are dropped, view pixels.
    pub min_length_px: f32,
}

impl PenSettings {
    /// The defaults for a pen `pen_px` wide, with strokes of at least 1 mm at
    /// `mm_per_px`.
    pub fn for_pen(pen_px: f32, mm_per_px: f32) -> Self {
        Self {
            pen_px,
            levels: 8,
            cross_from: 0.5,
            test_ratio: 0.6,
            step_px: 1.0,
            min_length_px: (1.0 / mm_per_px.max(1e-6)).max(2.0),
        }
    }

    fn validate(&self) -> Result<(), HatchError> {
        let bad = |what, reason: &str| {
            Err(HatchError::InvalidParams {
                what,
                reason: reason.into(),
            })
        };
        if !(self.pen_px.is_finite() && self.pen_px > 0.0) {
            return bad(
                "pen_px",
                "the pen width must be a positive number of pixels",
            );
        }
        if self.levels == 0 || self.levels > 64 {
            return bad("levels", "1..=64 tone levels");
        }
        if !(self.cross_from > 0.0 && self.cross_from <= 1.0) {
            return bad("cross_from", "a darkness in (0, 1]");
        }
        if !(self.test_ratio > 0.0 && self.test_ratio <= 1.0) {
            return bad("test_ratio", "a share in (0, 1]");
        }
        if !(self.step_px.is_finite() && self.step_px >= 0.1 && self.step_px <= 4.0) {
            return bad("step_px", "0.1..=4 pixels");
        }
        if !(self.min_length_px.is_finite() && self.min_length_px >= 0.0) {
            return bad("min_length_px", "a length of at least 0");
        }
        Ok(())
    }
}

/// A traced view: polylines in view pixels (y down), one list per pen.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PenDrawing {
    /// The view's size in pixels.
    pub size: (u32, u32),
    /// Strokes along θ.
    pub hatching: Vec<Polyline>,
    /// Strokes along θ + 90°, in the darker tones.
    pub cross_hatching: Vec<Polyline>,
    /// Silhouettes and creases, hidden parts removed: the silhouettes first.
    pub outlines: Vec<Polyline>,
    /// How many of `outlines` are silhouettes (the lines that cut the strokes).
    pub silhouettes: usize,
}

/// Traces `inputs` (tone and θ per pixel) over the pixels `mask` covers into pen strokes;
/// with `outline`, the mesh's visible silhouettes and creases in that view are drawn and
/// cut the strokes.
///
/// # Errors
/// [`HatchError::LengthMismatch`] for a mask or depth buffer of another size,
/// [`HatchError::InvalidParams`] for settings out of range.
pub fn trace(
    inputs: &HatchInputs,
    mask: &[bool],
    outline: Option<(&Mesh, &OutlineView<'_>)>,
    settings: &PenSettings,
) -> Result<PenDrawing, HatchError> {
    settings.validate()?;
    let size = (inputs.width(), inputs.height());
    let n = (size.0 as usize) * (size.1 as usize);
    let check = |what, len: usize| {
        if len == n {
            Ok(())
        } else {
            Err(HatchError::LengthMismatch {
                what,
                expected: n,
                actual: len,
            })
        }
    };
    check("mask", mask.len())?;
    let outlines = match outline {
        Some((mesh, view)) => {
            check("depth", view.depth.len())?;
            if view.size != size {
                return Err(HatchError::LengthMismatch {
                    what: "outline view size",
                    expected: n,
                    actual: (view.size.0 as usize) * (view.size.1 as usize),
                });
            }
            Some(outline::outlines(mesh, view))
        }
        None => None,
    };
    let no_cuts = Vec::new();
    let cuts = outlines.as_ref().map_or(&no_cuts, |o| &o.cuts);
    let field = field::Field::new(inputs, mask, cuts, settings.levels);
    let spacing = streamlines::Spacing {
        pen_px: settings.pen_px,
        cross_from: settings.cross_from,
        test_ratio: settings.test_ratio,
        step_px: settings.step_px,
        min_length_px: settings.min_length_px,
    };
    let layer = |turn, cross| streamlines::Layer { turn, cross };
    let hatching = streamlines::trace_layer(&field, &spacing, layer(0.0, false));
    let cross_hatching =
        streamlines::trace_layer(&field, &spacing, layer(std::f32::consts::FRAC_PI_2, true));
    let silhouettes = outlines.as_ref().map_or(0, |o| o.silhouettes.len());
    let outlines = outlines.map_or_else(Vec::new, |o| {
        o.silhouettes.into_iter().chain(o.creases).collect()
    });
    Ok(PenDrawing {
        size,
        hatching,
        cross_hatching,
        outlines,
        silhouettes,
    })
}
