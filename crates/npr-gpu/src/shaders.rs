//! Every WGSL source of the workspace, embedded at compile time so that the runtime and
//! the tests read the same text. Technique crates take their shader text from here.

/// Shared uniform structs and Blinn-Phong; prepended by [`compose`].
pub const COMMON: &str = include_str!("../../../shaders/common.wgsl");
/// Base shading passes: Phong, Gouraud, cel.
pub const BASE_SHADING: &str = include_str!("../../../shaders/base_shading.wgsl");
/// Post-rendering warping with projective textures (`npr-warp`); standalone.
pub const WARP: &str = include_str!("../../../shaders/warp.wgsl");

/// Outlines (silhouettes, creases) from a normal + depth prepass; shared by every style.
pub const OUTLINE: &str = include_str!("../../../shaders/outline.wgsl");

/// The specular highlight pass (npr-specular).
pub const SPECULAR_HIGHLIGHT: &str = include_str!("../../../shaders/specular_highlight.wgsl");
/// Image-space hatching pass (npr-hatching): Eq. (1)-(3), §3.1-§3.3.
pub const HATCHING: &str = include_str!("../../../shaders/hatching.wgsl");
/// Hatching inputs (npr-hatching): VSM shadow pass, tone + direction G-buffer, Phong + VSM.
pub const HATCHING_SCENE: &str = include_str!("../../../shaders/hatching_scene.wgsl");
/// Separable blur of variance-shadow-map moments (npr-hatching).
pub const VSM_BLUR: &str = include_str!("../../../shaders/vsm_blur.wgsl");

/// Every shader file: `(file name, source, needs common.wgsl prepended)`. A test checks
/// that this list names every `.wgsl` file in `shaders/` and that each validates.
pub const ALL: &[(&str, &str, bool)] = &[
    ("common.wgsl", COMMON, false),
    ("base_shading.wgsl", BASE_SHADING, true),
    ("outline.wgsl", OUTLINE, true),
    ("specular_highlight.wgsl", SPECULAR_HIGHLIGHT, true),
    ("hatching.wgsl", HATCHING, false),
    ("hatching_scene.wgsl", HATCHING_SCENE, true),
    ("vsm_blur.wgsl", VSM_BLUR, false),
    ("warp.wgsl", WARP, false),
];

/// `common.wgsl` followed by `source`: the text of a shader that uses the shared structs.
pub fn compose(source: &str) -> String {
    format!("{COMMON}\n{source}")
}

/// The full text of an entry of [`ALL`], composed if it needs `common.wgsl`.
pub fn full_source(entry: &(&str, &str, bool)) -> String {
    if entry.2 {
        compose(entry.1)
    } else {
        entry.1.to_string()
    }
}
