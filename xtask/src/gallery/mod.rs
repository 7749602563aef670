//! The demo's gallery: `target/demo/index.html`, one page with every image `cargo xtask
//! demo` writes, in sections per paper, each figure captioned with the paper figure it
//! reproduces and its parameters, and a "departures" section of before/after pairs (the
//! paper's way, then ours).
//!
//! [`figures`] and [`departures`] are the one list of what the demo writes: the page is
//! made from them, and the demo checks after its run that it wrote exactly these files
//! ([`check_written`]), so a figure cannot be added to the demo without a caption here,
//! nor captioned here without being written.

use npr_gpu::ShadingModel;
use npr_hatching::{BlendMode, DirectionSource, TamStyle};
use std::collections::BTreeSet;

mod page;
pub use page::{check_written, write};

/// The base-shading demo meshes (`demo::demo_meshes`), in order.
pub const BASE_MESHES: [&str; 7] = [
    "sphere",
    "torus",
    "ellipsoid",
    "cylinder",
    "knot",
    "spot",
    "stanford-bunny",
];

/// The specular figures' subjects, in order.
pub const SPECULAR_SUBJECTS: [&str; 4] = ["knot", "ellipsoid", "spot", "stanford-bunny"];

/// The specular subjects of the highlight-sizing before/after pairs.
pub const SIZING_SUBJECTS: [&str; 2] = ["spot", "stanford-bunny"];

/// The single objects of the hatching paper's Fig. 2, in order.
pub const HATCHING_SINGLES: [&str; 5] = ["knot", "sphere", "torus", "spot", "stanford-bunny"];

/// The models of the plotter section (`plotter-NAME.*`, fixtures' OBJ files).
pub const PLOTTER_SUBJECTS: [&str; 2] = ["stanford-bunny", "spot"];

/// The effects of the animated section (`animated-fox-EFFECT.gif`).
pub const ANIMATED_EFFECTS: [&str; 3] = ["hatching-pen", "specular", "warp"];

/// A section of the page: the base shadings, one paper, the pen plotter, or animated
/// models.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    /// Base shadings shared by the papers (`npr-gpu`).
    Base,
    /// Lee & Choi, stylized specular highlights (`npr-specular`).
    Specular,
    /// Kim & Lee, image-space hatching (`npr-hatching`).
    Hatching,
    /// Park & Ihm, post-rendering 3D warping (`npr-warp`).
    Warp,
    /// The hatching as pen strokes for a plotter (`npr_hatching::pen`), ours.
    Plotter,
    /// Skinned glTF playing its clips in the effects, ours.
    Animated,
}

impl Section {
    /// Every section, in page order.
    pub const ALL: [Section; 6] = [
        Self::Base,
        Self::Specular,
        Self::Hatching,
        Self::Warp,
        Self::Plotter,
        Self::Animated,
    ];

    fn title(self) -> &'static str {
        match self {
            Self::Base => "Base shading",
            Self::Specular => "Stylized specular highlights (npr-specular)",
            Self::Hatching => "Image-space hatching (npr-hatching)",
            Self::Warp => "Post-rendering 3D warping (npr-warp)",
            Self::Plotter => "Hatching for pen plotters (npr-hatching::pen)",
            Self::Animated => "Animated models (glTF skins and clips)",
        }
    }

    fn paper(self) -> &'static str {
        match self {
            Self::Base | Self::Plotter | Self::Animated => "",
            Self::Specular => {
                "Hwan-Jik Lee and Jung-Ju Choi, Stylized Specular Reflections Using \
                 Projective Textures based on Principal Curvature Analysis (Lee & Choi)"
            }
            Self::Hatching => {
                "Yongjin Kim and Seungyong Lee, Real-time Image-space Hatching (Kim & Lee)"
            }
            Self::Warp => {
                "Huiwon Park and Insung Ihm, Post-Rendering 3D Warping using Projective \
                 Texture (Park & Ihm)"
            }
        }
    }

    /// Short paper name for captions.
    fn short(self) -> &'static str {
        match self {
            Self::Base | Self::Plotter | Self::Animated => "",
            Self::Specular => "Lee & Choi",
            Self::Hatching => "Kim & Lee",
            Self::Warp => "Park & Ihm",
        }
    }
}

/// One figure on the page.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Its section.
    pub section: Section,
    /// The image shown (relative to the demo directory).
    pub file: String,
    /// The paper figure it reproduces (`"Fig. 4"` of the section's paper), or `None` for
    /// our own figures.
    pub figure: Option<&'static str>,
    /// What it shows and its parameters.
    pub caption: String,
    /// Files written beside it (its tiles, alone), linked under it.
    pub parts: Vec<String>,
}

/// The objects of the coherence GIFs (`hatching-coherence-NAME.gif`).
pub const COHERENCE_SUBJECTS: [&str; 2] = ["stanford-bunny", "knot"];

/// A before/after pair: the paper's way, then ours.
#[derive(Clone, Debug)]
pub struct Departure {
    /// What departs.
    pub title: &'static str,
    /// The paper's way.
    pub before: String,
    /// Label of `before`.
    pub before_label: &'static str,
    /// Ours.
    pub after: String,
    /// Label of `after`.
    pub after_label: &'static str,
    /// What to look for, and the parameters.
    pub caption: String,
}

fn fig(
    section: Section,
    file: impl Into<String>,
    figure: Option<&'static str>,
    caption: impl Into<String>,
) -> Figure {
    Figure {
        section,
        file: file.into(),
        figure,
        caption: caption.into(),
        parts: Vec::new(),
    }
}

/// Every figure the demo writes, in page order.
pub fn figures() -> Vec<Figure> {
    let mut out = Vec::new();
    base_figures(&mut out);
    specular_figures(&mut out);
    hatching_paper_figures(&mut out);
    hatching_own_figures(&mut out);
    warp_figures(&mut out);
    plotter_figures(&mut out);
    animated_figures(&mut out);
    out
}

/// Appends the animated section: the Fox walking in each of [`ANIMATED_EFFECTS`].
fn animated_figures(out: &mut Vec<Figure>) {
    for effect in ANIMATED_EFFECTS {
        let mut f = fig(
            Section::Animated,
            format!("animated-fox-{effect}.gif"),
            None,
            format!(
                "The Fox (a skinned glTF triangle soup, 24 joints) playing its Walk clip, \
                 {effect}, 24 frames at 30 fps with the camera still (`npr render \
                 fixtures/meshes/Fox.glb --effect {effect} --animation Walk --frames 24 \
                 --gif`). Each frame is posed on the CPU (linear blend skinning) and its \
                 curvature, highlights or stroke directions are computed on the posed \
                 surface; the warp poses its proxy with the Fox and projects each \
                 reference through the proxy's pose at the reference's moment. Below, every \
                 sixth frame."
            ),
        );
        f.parts = vec![format!("animated-fox-{effect}-strip.png")];
        out.push(f);
    }
}

/// Appends the plotter section: each subject's SVG beside the raster hatching.
fn plotter_figures(out: &mut Vec<Figure>) {
    for name in PLOTTER_SUBJECTS {
        let mut f = fig(
            Section::Plotter,
            format!("plotter-{name}.png"),
            None,
            format!(
                "The {name} as pen strokes for a plotter, A4 at 0.3 mm, traced from the \
                 640×480 view (`npr render --effect hatching-pen --svg`): (left) the SVG \
                 rasterised by resvg, one dot per view pixel; (right) the raster hatching of \
                 the same view. Evenly spaced streamlines along the stroke field, spaced by \
                 tone, cross-hatched past mid-tone, cut at visible silhouettes, with the \
                 visible outlines. `cargo xtask bench plotter` measures the tone of both."
            ),
        );
        f.parts = vec![
            format!("plotter-{name}.svg"),
            format!("plotter-{name}-svg.png"),
            format!("plotter-{name}-raster.png"),
        ];
        out.push(f);
    }
}

/// Appends the base-shading sheet and its tiles.
fn base_figures(out: &mut Vec<Figure>) {
    let base = Section::Base;
    let mut sheet = fig(
        base,
        "base-shading-sheet.png",
        None,
        "Phong, Gouraud and cel shading (a three-band 1-D ramp, as Lake 2000, with ink \
         outlines from npr_gpu::outline) of every demo mesh, one row each: sphere, torus, \
         ellipsoid, cylinder, the specular paper's knot, Spot, the bunny. 320×320 per tile, \
         directional light (1, 1.5, 2).",
    );
    for mesh in BASE_MESHES {
        for model in ShadingModel::ALL {
            sheet
                .parts
                .push(format!("base-{mesh}-{}.png", model.name()));
        }
    }
    out.push(sheet);
}

/// Appends the specular paper's figures (Lee & Choi Fig. 2, 4–8).
fn specular_figures(out: &mut Vec<Figure>) {
    let sp = Section::Specular;
    let common = "Phong base unless named, directional light towards (0.4, 0.7, 1.0), the \
                  object turned 0.4 rad about y, curvature ball 3 mean edge lengths, 360×360 \
                  per tile";
    for s in SPECULAR_SUBJECTS {
        out.push(fig(
            sp,
            format!("specular-fig2-{s}.png"),
            Some("Fig. 2"),
            format!(
                "{s}: (a) a directional texture (the streak, long along the texture's u), \
                 (b) projected with up = e_min (the paper's choice, Eq. (7)), (c) with up = \
                 e_max. σ = 0.9, scale 1.3. {common}."
            ),
        ));
        out.push(fig(
            sp,
            format!("specular-fig4-{s}.png"),
            Some("Fig. 4"),
            format!(
                "{s}: the §3.4 controls on the star texture (σ = 0.92): (a) original, (b) \
                 scaled (1.6, 0.8), (c) rotated 0.6 rad about N, (d) translated (0.02, 0.1) \
                 along (e_max, e_min). {common}."
            ),
        ));
        out.push(fig(
            sp,
            format!("specular-fig5-{s}.png"),
            Some("Fig. 5"),
            format!(
                "{s}: (a) the unrestricted projection: every face receives the projected \
                 star (HighlightPass::draw_list_unrestricted), so it lands on whatever the \
                 frustum reaches; (b) restricted to the §4.2 receivers (breadth-first from \
                 the centre's face, inside the frustum, N·N_max > 0). Star σ = 0.92 scaled \
                 2.5× (1.5× on Spot and the bunny) so the frustum reaches other parts of \
                 the surface. {common}."
            ),
        ));
        out.push(fig(
            sp,
            format!("specular-fig6-{s}.png"),
            Some("Fig. 6"),
            format!(
                "{s}: (a) Phong's own highlight (k_s = 0.8, n = 60), (b) the disc texture \
                 projected, (c) the normal-map texture shaded with Blinn's (N·H)^n, n = 8 \
                 (Eq. (2)–(3)). {common}."
            ),
        ));
        out.push(fig(
            sp,
            format!("specular-fig7-{s}.png"),
            Some("Fig. 7"),
            format!(
                "{s}: the highlight pass over other base shadings (§5): (a) Gouraud with the \
                 star, (b) cel (three-band ramp) with the disc. {common}."
            ),
        ));
    }
    out.push(fig(
        sp,
        "specular-fig8-knot-strip.png",
        Some("Fig. 8"),
        "The paper's knot (2,880 faces) turning about y in 5° steps (tilted 0.5 rad), cel \
         base with the star: every 9th frame (45° apart). Highlights are matched from frame \
         to frame and fade in and out over 6 frames (our frame-coherence additions).",
    ));
    out.push(fig(
        sp,
        "specular-fig8-knot.gif",
        Some("Fig. 8"),
        "The same, all 72 frames (a full turn) as a looping GIF, 60 ms per frame.",
    ));
}

/// Appends the tonal art maps and the hatching paper's figures (Kim & Lee Fig. 1–4).
fn hatching_paper_figures(out: &mut Vec<Figure>) {
    let h = Section::Hatching;
    for style in [TamStyle::Pen, TamStyle::Pencil] {
        out.push(fig(
            h,
            format!("hatching-tam-{}.png", style.name()),
            None,
            format!(
                "The {} tonal art map, light to dark: nested slices (every stroke of a \
                 lighter slice is in all darker ones), Praun et al. 2001's structure \
                 without mipmaps.",
                style.name()
            ),
        ));
    }
    let mut f1 = fig(
        h,
        "hatching-fig1.png",
        Some("Fig. 1"),
        "The three stages on the knot (a close-up, 480×360, pen, strokes 1.5 px per texel, \
         no outlines): (left) cut-and-paste, Eq. (1), 16 direction bins; (middle) blended \
         with the neighbouring bins, Eq. (2)–(3); (right) the offset partition mixed 50/50, \
         §3.3.",
    );
    for mode in BlendMode::ALL {
        f1.parts.push(format!("hatching-fig1-{}.png", mode.name()));
    }
    out.push(f1);
    let mut f2 = fig(
        h,
        "hatching-fig2.png",
        Some("Fig. 2"),
        "Single objects at 640×480 as in the paper, pen (left) and pencil (right, strokes \
         1.25×, ink 0.04): a (2, 3) knot, sphere, torus, Spot, the bunny. Stroke directions \
         from the smooth line field (our default), tone from Phong with a variance shadow \
         map; no outlines.",
    );
    for s in HATCHING_SINGLES {
        for style in [TamStyle::Pen, TamStyle::Pencil] {
            f2.parts
                .push(format!("hatching-fig2-{s}-{}.png", style.name()));
        }
    }
    out.push(f2);
    for (file, what) in [
        ("hatching-fig3-scene-pen.png", "pen"),
        ("hatching-fig3-scene-pencil.png", "pencil"),
    ] {
        out.push(fig(
            h,
            file,
            Some("Fig. 3"),
            format!(
                "A scene of six objects on a ground plane (the paper's is about 35,000 \
                 triangles), {what}, 960×600, directional light with cast shadows from the \
                 variance shadow map; no outlines."
            ),
        ));
    }
    out.push(fig(
        h,
        "hatching-fig3-scene-phong-vsm.png",
        None,
        "The Fig. 3 scene's baseline: Phong with the same variance shadow map (what `cargo \
         xtask bench hatching` times the hatching frame against).",
    ));
    out.push(fig(
        h,
        "hatching-fig4-scene-pen.png",
        Some("Fig. 4"),
        "A complex scene of several objects, about 1.1M triangles in all, at 1280×480 as in \
         the paper: a ground plane, a cylinder (33k), the bunny (69k), a torus (160k), a \
         (2, 3) knot (720k), Spot (23k) and a sphere (82k); pen, directional light with cast \
         shadows, smooth stroke fields; no outlines. The demo prints the exact count.",
    ));
}

/// Appends our hatching figures: the spot-lit scene, stroke directions, coherence and flow.
fn hatching_own_figures(out: &mut Vec<Figure>) {
    let h = Section::Hatching;
    out.push(fig(
        h,
        "hatching-fig3-scene-spot-pen.png",
        None,
        "Ours: the Fig. 3 scene under a spot light (cone 26°–38°, shadows from the variance \
         shadow map), pen, with ink outlines.",
    ));
    let mut dirs = fig(
        h,
        "hatching-directions-bunny.png",
        None,
        "Stroke directions on the bunny, pen with outlines: (left) the raw principal \
         directions, (right) the smooth line field fitted to them (Knöppel et al. 2013). \
         `cargo xtask bench hatching-directions` measures both.",
    );
    for source in [DirectionSource::Principal, DirectionSource::default()] {
        dirs.parts
            .push(format!("hatching-directions-bunny-{}.png", source.name()));
    }
    out.push(dirs);
    let mut cad = fig(
        h,
        "hatching-directions-cad.png",
        None,
        "Stroke directions on hard-edged CAD parts (procedural: a block with a \
         through-hole, a stepped shaft, a bent bracket), pen with outlines: (left) the \
         paper's rule, raw principal directions; (right) our default, the smooth field cut \
         at creases with one straight direction per flat face. `cargo xtask bench \
         hatching-directions` measures both (planar_spread_deg, jump30_smooth_edge_share).",
    );
    for source in [DirectionSource::Principal, DirectionSource::default()] {
        cad.parts
            .push(format!("hatching-directions-cad-{}.png", source.name()));
    }
    out.push(cad);
    for name in COHERENCE_SUBJECTS {
        let mut gif = fig(
            h,
            format!("hatching-coherence-{name}.gif"),
            None,
            format!(
                "Beyond §5's shower-door limit: the {name} turning 2° per frame while the \
                 camera dollies in by 2× and back, pen; (left) the paper's screen-space \
                 strokes stay on the screen while the surface slides beneath, (right) our \
                 surface-anchored strokes (StrokeSpace::Surface) move with it at constant \
                 density. `cargo xtask bench hatching-coherence` measures both."
            ),
        );
        gif.parts
            .push(format!("hatching-coherence-{name}-strip.png"));
        out.push(gif);
    }
    out.push(fig(
        h,
        "hatching-flow-gpu.png",
        None,
        "The paper's suggested further use (§5): 2-D flow visualisation, a stream past two \
         counter-rotating vortices, tone from speed; the GPU pass with the pen map, 640×480.",
    ));
    out.push(fig(
        h,
        "hatching-flow-cpu-pencil.png",
        None,
        "The same flow hatched by the CPU reference with the pencil map.",
    ));
}

/// Appends the warping paper's figures (Park & Ihm Fig. 6, 8–10) and our sequence plots.
fn warp_figures(out: &mut Vec<Figure>) {
    let w = Section::Warp;
    let ratios_caption = |model: &str, ratios: &str| {
        format!(
            "{model}: the full render, then for each proxy ratio ({ratios}) the proxy (light \
             grey, edges dark) and the warped frame (all our departures on), halfway between \
             two references 10° (10 frames) apart as the camera orbits the object; 320×320 \
             per tile, 16×16 normal bins. The demo prints each warp's PSNR and SSIM against \
             the full render."
        )
    };
    out.push(fig(
        w,
        "warp-ratios-bunny.png",
        Some("Fig. 8"),
        ratios_caption("The bunny (69,451 triangles)", "5 %, 2 %, 1 %"),
    ));
    out.push(fig(
        w,
        "warp-ratios-knot-870k.png",
        Some("Fig. 9"),
        ratios_caption(
            "A (3, 5) torus-knot tube of 870,000 triangles, standing in for the paper's \
             Dragon (871,414)",
            "1 %, 0.4 %, 0.09 %",
        ),
    ));
    out.push(fig(
        w,
        "warp-ratios-knot-1100k.png",
        Some("Fig. 10"),
        ratios_caption(
            "A (2, 3) torus-knot tube of 1,100,000 triangles, standing in for the paper's \
             Buddha (1,085,634)",
            "0.6 %, 0.2 %, 0.07 %",
        ),
    ));
    out.push(fig(
        w,
        "warp-sequence-bunny.png",
        None,
        "A warped sequence of the bunny (2 % proxy): a reference every 10 frames, drawn \
         spread over the frames between; frames 1, 5, 9, 13, 17, 21.",
    ));
    out.push(fig(
        w,
        "warp-sequence-psnr-bunny.png",
        None,
        "PSNR of each of the sequence's 41 frames against the full render (grid every 5 dB \
         from 15 to 50 dB, 30 dB in red; reference frames marked by blue lines).",
    ));
    out.push(fig(
        w,
        "warp-occlusion-knot.png",
        Some("§3.4, Fig. 6"),
        "Surfaces hidden by other polygons in a reference (§3.4's open problem). Top: a \
         self-occluding knot turning 20° between references, seen halfway: full render, the \
         paper's path, ours, and the differences from the full render (×4) of each. Bottom: \
         a red square hides part of the knot in reference 0 only (first tile); the paper's \
         pass projects it onto the knot, our reference depth test falls back to reference 1.",
    ));
}

/// The before/after pairs of our departures from the papers.
pub fn departures() -> Vec<Departure> {
    let smooth = DirectionSource::default();
    let mut out = vec![
        Departure {
            title: "Hatching stroke directions: raw principal directions vs the smooth field",
            before: format!(
                "hatching-directions-bunny-{}.png",
                DirectionSource::Principal.name()
            ),
            before_label: "the paper: raw principal directions",
            after: format!("hatching-directions-bunny-{}.png", smooth.name()),
            after_label: "ours: smooth line field (Knöppel et al. 2013)",
            caption: "The bunny, pen, 640×480, with outlines in both. The raw field turns by \
                      more than 30° across about 10 % of the edges, the smooth one across \
                      under 2 % (`cargo xtask bench hatching-directions`)."
                .into(),
        },
        Departure {
            title: "Outlines off vs on",
            before: "hatching-fig2-spot-pen.png".into(),
            before_label: "the paper: no outlines",
            after: "hatching-outlines-spot-pen.png".into(),
            after_label: "ours: silhouette and crease outlines (npr_gpu::outline)",
            caption: "Spot, pen, 640×480. The figures that reproduce the papers draw no \
                      outlines; our own figures and cel shading add them."
                .into(),
        },
        Departure {
            title: "Warping: the paper's path vs ours",
            before: "warp-occlusion-knot-paper.png".into(),
            before_label: "the paper's path (Departures::PAPER)",
            after: "warp-occlusion-knot-ours.png".into(),
            after_label: "ours (Departures::OURS)",
            caption: "A self-occluding knot (5 % proxy) turning 20° between references, seen \
                      halfway. Ours adds the reference depth test, coverage-normalised \
                      lookups, conservative culling, the inflated proxy and the cosine ramp \
                      with a time term; each is measured alone in `cargo xtask bench warp`."
                .into(),
        },
    ];
    for s in SIZING_SUBJECTS {
        out.push(Departure {
            title: "Highlight sizing: the paper's Eq. (8) vs the region N·H ≥ σ",
            before: format!("specular-sizing-{s}-paper.png"),
            before_label: "the paper: Eq. (8), s = min(2r, 2/|κ| · sqrt(1 − σ²)) (HighlightSizing::Paper)",
            after: format!("specular-sizing-{s}-ours.png"),
            after_label: "ours: fitted to the region N·H ≥ σ (HighlightSizing::Region)",
            caption: format!(
                "{s}, disc texture, σ = 0.9. On a scan, κ is noisy: Eq. (8) gives circles \
                 capped at 2r and streaks, ours an ellipse fitted to the region each \
                 highlight stylizes, with suppressed duplicates and normal-cone receivers \
                 (`cargo xtask bench specular-fidelity` measures both)."
            ),
        });
    }
    out
}

/// Every file the demo writes (figures, their parts, the pairs), without repeats.
pub fn files() -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for f in figures() {
        out.insert(f.file);
        out.extend(f.parts);
    }
    for d in departures() {
        out.insert(d.before);
        out.insert(d.after);
    }
    out
}
