//! The drawing as an SVG a pen plotter's tools read: a page in millimetres, the view
//! fitted and centred inside the margins, one Inkscape layer per pen (`1 hatching`,
//! `2 cross-hatching`, `3 outlines`, each a direct child of `<svg>`), strokes only. Before
//! writing, ends closer than the merge distance are joined, lines are simplified within
//! the same distance, and each layer's strokes are ordered to keep pen-up travel short.
//! The same drawing and page give the same bytes.

use super::streamlines::Polyline;
use super::{PenDrawing, order};
use crate::HatchError;

/// A page and pen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Page {
    /// Width × height in millimetres, portrait (the shorter side first); the page turns
    /// to landscape for a view wider than high.
    pub size_mm: (f32, f32),
    /// Margin on every side, mm.
    pub margin_mm: f32,
    /// Pen width, mm (the `stroke-width`).
    pub pen_mm: f32,
    /// Ends closer than this are joined, and lines simplified within it, mm.
    pub merge_mm: f32,
}

impl Default for Page {
    fn default() -> Self {
        Self {
            size_mm: (210.0, 297.0),
            margin_mm: 10.0,
            pen_mm: 0.3,
            merge_mm: 0.05,
        }
    }
}

impl Page {
    /// A named page (`a4`, `a3`, `letter`) or `WxHmm` (e.g. `200x150mm`), with the
    /// default margin and pen.
    ///
    /// # Errors
    /// [`HatchError::InvalidParams`] for another name.
    pub fn named(name: &str) -> Result<Self, HatchError> {
        let size_mm = match name.to_ascii_lowercase().as_str() {
            "a4" => (210.0, 297.0),
            "a3" => (297.0, 420.0),
            "letter" => (215.9, 279.4),
            other => parse_mm(other).ok_or_else(|| HatchError::InvalidParams {
                what: "page",
                reason: format!("\"{name}\" is not a4, a3, letter or WxHmm (e.g. 200x150mm)"),
            })?,
        };
        let (a, b) = size_mm;
        Ok(Self {
            size_mm: (a.min(b), a.max(b)),
            ..Self::default()
        })
    }

    /// Checks the page and pen: positive sizes, room inside the margins, a positive pen.
    ///
    /// # Errors
    /// [`HatchError::InvalidParams`] naming what is wrong.
    pub fn validate(&self) -> Result<(), HatchError> {
        let bad = |what, reason: String| Err(HatchError::InvalidParams { what, reason });
        let (w, h) = self.size_mm;
        if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
            return bad("page", format!("{w}×{h} mm is not a page size"));
        }
        if !(self.margin_mm.is_finite() && self.margin_mm >= 0.0) {
            return bad("margin", format!("{} mm is not a margin", self.margin_mm));
        }
        if 2.0 * self.margin_mm >= w.min(h) {
            return bad(
                "page",
                format!(
                    "{w}×{h} mm leaves no room inside {} mm margins",
                    self.margin_mm
                ),
            );
        }
        if !(self.pen_mm.is_finite() && self.pen_mm > 0.0) {
            return bad(
                "pen-mm",
                format!("{} mm: the pen width must be above 0", self.pen_mm),
            );
        }
        if !(self.merge_mm.is_finite() && self.merge_mm >= 0.0) {
            return bad("merge", format!("{} mm is not a distance", self.merge_mm));
        }
        Ok(())
    }

    /// The page's size turned for a view of `size` pixels (landscape when wider).
    pub fn oriented(&self, size: (u32, u32)) -> (f32, f32) {
        let (a, b) = (
            self.size_mm.0.min(self.size_mm.1),
            self.size_mm.0.max(self.size_mm.1),
        );
        if size.0 > size.1 { (b, a) } else { (a, b) }
    }

    /// Millimetres per view pixel, and the page position of pixel (0, 0), for a view of
    /// `size` fitted and centred inside the margins.
    pub fn fit(&self, size: (u32, u32)) -> (f32, [f32; 2]) {
        let (pw, ph) = self.oriented(size);
        let (vw, vh) = (size.0.max(1) as f32, size.1.max(1) as f32);
        let scale = ((pw - 2.0 * self.margin_mm) / vw).min((ph - 2.0 * self.margin_mm) / vh);
        (scale, [0.5 * (pw - scale * vw), 0.5 * (ph - scale * vh)])
    }

    /// The pen width in view pixels once the view is fitted to the page.
    pub fn pen_px(&self, size: (u32, u32)) -> f32 {
        self.pen_mm / self.fit(size).0
    }
}

fn parse_mm(s: &str) -> Option<(f32, f32)> {
    let (w, h) = s.strip_suffix("mm")?.split_once('x')?;
    let (w, h) = (w.trim().parse::<f32>().ok()?, h.trim().parse::<f32>().ok()?);
    (w.is_finite() && h.is_finite()).then_some((w, h))
}

/// What a plot of the SVG costs: lengths in mm, counts, and the time at the given speeds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlotStats {
    /// Strokes drawn, all layers.
    pub strokes: usize,
    /// Pen-down length, mm.
    pub draw_mm: f64,
    /// Pen-up travel between strokes of a layer, mm (each layer starts where its first
    /// stroke does).
    pub travel_mm: f64,
    /// Strokes shorter than 1 mm.
    pub short_strokes: usize,
}

impl PlotStats {
    /// The plot time in seconds at `draw_mm_s` pen down and `travel_mm_s` pen up.
    pub fn seconds(&self, draw_mm_s: f64, travel_mm_s: f64) -> f64 {
        self.draw_mm / draw_mm_s + self.travel_mm / travel_mm_s
    }
}

/// Outline pieces shorter than this after joining are left out, mm: to the pen they are
/// dots. They are what is left of a silhouette or crease that the depth test cuts into
/// specks, or of a crease on a noisy scan's triangulation, not a line a reader follows.
/// (The streamlines have their own minimum, [`crate::pen::PenSettings::min_length_px`].)
pub const MIN_OUTLINE_MM: f32 = 1.0;

/// The drawing's layers on the page: merged, simplified and ordered, in mm. Hatching ends
/// within [`Page::merge_mm`] are joined; outline ends within the pen's width too (the pen
/// draws them touching anyway), and outline pieces under [`MIN_OUTLINE_MM`] are left out.
pub fn page_layers(drawing: &PenDrawing, page: &Page) -> [Vec<Polyline>; 3] {
    let (scale, origin) = page.fit(drawing.size);
    let to_page = |l: &Polyline| -> Polyline {
        l.iter()
            .map(|p| [origin[0] + scale * p[0], origin[1] + scale * p[1]])
            .collect()
    };
    let layer = |lines: &[Polyline], join_mm: f32, min_mm: f32| {
        let lines: Vec<Polyline> = lines.iter().map(to_page).collect();
        let merged = order::merge_ends(lines, join_mm);
        let simple: Vec<Polyline> = merged
            .iter()
            .map(|l| order::simplify(l, page.merge_mm))
            .filter(|l| l.len() >= 2 && order::length(l) >= min_mm)
            .collect();
        order::order(simple)
    };
    [
        layer(&drawing.hatching, page.merge_mm, 0.0),
        layer(&drawing.cross_hatching, page.merge_mm, 0.0),
        layer(
            &drawing.outlines,
            page.merge_mm.max(page.pen_mm),
            MIN_OUTLINE_MM,
        ),
    ]
}

/// The plot statistics of page layers (see [`page_layers`]).
pub fn plot_stats(layers: &[Vec<Polyline>; 3]) -> PlotStats {
    let mut s = PlotStats::default();
    for lines in layers {
        let mut last: Option<[f32; 2]> = None;
        for l in lines {
            let len = order::length(l);
            s.strokes += 1;
            s.draw_mm += f64::from(len);
            if len < 1.0 {
                s.short_strokes += 1;
            }
            if let Some(p) = last {
                s.travel_mm += f64::from(order::dist(p, l[0]));
            }
            last = l.last().copied();
        }
    }
    s
}

/// The SVG of `drawing` on `page`.
///
/// # Errors
/// [`HatchError::InvalidParams`] for a page or pen that [`Page::validate`] refuses.
pub fn to_svg(drawing: &PenDrawing, page: &Page) -> Result<String, HatchError> {
    page.validate()?;
    let layers = page_layers(drawing, page);
    let (pw, ph) = page.oriented(drawing.size);
    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    out.push_str(&format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" \
         xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" \
         width=\"{}mm\" height=\"{}mm\" viewBox=\"0 0 {} {}\">\n",
        num(pw),
        num(ph),
        num(pw),
        num(ph)
    ));
    for (k, (name, lines)) in ["hatching", "cross-hatching", "outlines"]
        .iter()
        .zip(&layers)
        .enumerate()
    {
        out.push_str(&format!(
            "<g inkscape:groupmode=\"layer\" inkscape:label=\"{n} {name}\" id=\"layer{n}\" \
             fill=\"none\" stroke=\"black\" stroke-width=\"{}\" stroke-linecap=\"round\" \
             stroke-linejoin=\"round\">\n",
            num(page.pen_mm),
            n = k + 1
        ));
        for l in lines {
            out.push_str("<polyline points=\"");
            for (i, p) in l.iter().enumerate() {
                if i > 0 {
                    out.push(' ');
                }
                out.push_str(&num(p[0]));
                out.push(',');
                out.push_str(&num(p[1]));
            }
            out.push_str("\"/>\n");
        }
        out.push_str("</g>\n");
    }
    out.push_str("</svg>\n");
    Ok(out)
}

/// A number with at most three decimals, without trailing zeros.
fn num(v: f32) -> String {
    let s = format!("{:.3}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}
