//! The WGSL that `npr-gpu` owns, embedded at compile time from the crate's own `shaders/`
//! directory, so that the runtime and the tests read the same text; and the shared
//! snippets that the technique crates compose into theirs.
//!
//! A technique crate keeps its WGSL in its own `shaders/` directory and lists each file as
//! a [`ShaderFile`] whose [`prelude`](ShaderFile::prelude) names the shared snippets it
//! needs ([`COMMON`], [`FULLSCREEN`]); [`ShaderFile::full_source`] is the text handed to
//! `wgpu::Device::create_shader_module`, and the text the naga validation and uniform-layout
//! tests read.

/// Shared uniform structs (`Frame`, `Object`) and Blinn-Phong; composed before the shaders
/// that use them.
pub const COMMON: &str = include_str!("../shaders/common.wgsl");
/// The full-screen vertex stage (`vs_fullscreen`, `FullscreenOut`): one triangle covering
/// the screen, drawn with `draw(0..3, 0..1)` and no vertex buffer; `vs_fullscreen_far`
/// draws it at the far plane, for a pass that skips the background by a depth test.
pub const FULLSCREEN: &str = include_str!("../shaders/fullscreen.wgsl");
/// Base shading passes: Phong, Gouraud, cel.
pub const BASE_SHADING: &str = include_str!("../shaders/base_shading.wgsl");
/// Outlines (silhouettes, creases) from a normal + depth prepass; shared by every style.
pub const OUTLINE: &str = include_str!("../shaders/outline.wgsl");
/// Posing: morph targets and linear blend skinning into the mesh's vertex buffer, and
/// the posed area-weighted normals (compute).
pub const POSING: &str = include_str!("../shaders/posing.wgsl");
/// Numeric helpers the compute shaders share (`finite`, `atan2_reduced`, `try_normalize`).
pub const NUMERIC: &str = include_str!("../shaders/numeric.wgsl");
/// Curvature: the per-vertex tensor of Lee & Choi Eq. (1) (corrected form), principal
/// curvatures and directions (compute).
pub const CURVATURE: &str = include_str!("../shaders/curvature.wgsl");

/// One WGSL file: its name, its text, and the shared snippets composed before it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShaderFile {
    /// File name inside the owning crate's `shaders/` directory.
    pub name: &'static str,
    /// The file's text.
    pub source: &'static str,
    /// Shared snippets ([`COMMON`], [`FULLSCREEN`]) placed before `source`, in order.
    pub prelude: &'static [&'static str],
}

impl ShaderFile {
    /// The complete shader: the prelude followed by the file's text.
    pub fn full_source(&self) -> String {
        let mut parts: Vec<&str> = self.prelude.to_vec();
        parts.push(self.source);
        compose(&parts)
    }

    /// The shader module of [`ShaderFile::full_source`], labelled with the file's name.
    pub fn module(&self, device: &wgpu::Device) -> wgpu::ShaderModule {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(self.name),
            source: wgpu::ShaderSource::Wgsl(self.full_source().into()),
        })
    }
}

/// Concatenates WGSL parts (shared snippets first, then the shader), one per line.
pub fn compose(parts: &[&str]) -> String {
    parts.join("\n")
}

/// `common.wgsl` itself (validated alone: it declares only structs and functions).
pub const COMMON_FILE: ShaderFile = ShaderFile {
    name: "common.wgsl",
    source: COMMON,
    prelude: &[],
};
/// `fullscreen.wgsl` itself (a valid module alone: a vertex entry point).
pub const FULLSCREEN_FILE: ShaderFile = ShaderFile {
    name: "fullscreen.wgsl",
    source: FULLSCREEN,
    prelude: &[],
};
/// `base_shading.wgsl` after `common.wgsl`.
pub const BASE_SHADING_FILE: ShaderFile = ShaderFile {
    name: "base_shading.wgsl",
    source: BASE_SHADING,
    prelude: &[COMMON],
};
/// `outline.wgsl` after `common.wgsl` and `fullscreen.wgsl`.
pub const OUTLINE_FILE: ShaderFile = ShaderFile {
    name: "outline.wgsl",
    source: OUTLINE,
    prelude: &[COMMON, FULLSCREEN],
};
/// `posing.wgsl` (compute; no shared snippet).
pub const POSING_FILE: ShaderFile = ShaderFile {
    name: "posing.wgsl",
    source: POSING,
    prelude: &[],
};

/// `numeric.wgsl` itself (validated alone: it declares only functions).
pub const NUMERIC_FILE: ShaderFile = ShaderFile {
    name: "numeric.wgsl",
    source: NUMERIC,
    prelude: &[],
};

/// `curvature.wgsl` (compute) after `numeric.wgsl`.
pub const CURVATURE_FILE: ShaderFile = ShaderFile {
    name: "curvature.wgsl",
    source: CURVATURE,
    prelude: &[NUMERIC],
};

/// Every shader file of this crate. A test checks that it names every `.wgsl` file in the
/// crate's `shaders/` directory and that each composed shader validates.
pub const ALL: &[ShaderFile] = &[
    COMMON_FILE,
    FULLSCREEN_FILE,
    BASE_SHADING_FILE,
    OUTLINE_FILE,
    POSING_FILE,
    NUMERIC_FILE,
    CURVATURE_FILE,
];
