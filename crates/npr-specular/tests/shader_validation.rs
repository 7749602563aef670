//! Every `.wgsl` file under this crate's `shaders/` is listed in `npr_specular::shaders::ALL`,
//! and every entry, composed with its shared npr-gpu snippets, parses and validates with
//! naga; every struct the shaders bind has a uniform-layout test. All failures are
//! reported at once; no GPU needed.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use npr_gpu::testing::wgsl_layout::{check_coverage, validate_dir};
use std::path::Path;

#[test]
fn every_shader_file_is_embedded_and_validates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let n = validate_dir(&dir, npr_specular::shaders::ALL).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(n, npr_specular::shaders::ALL.len());
}

/// The structs bound as `var<uniform>` or `var<storage>` and the unit tests that compare
/// each with its Rust twin (`npr_gpu::assert_wgsl_layout!`): a new block fails here until
/// it has one.
#[test]
fn every_bound_struct_has_a_layout_test() {
    // `Counter` is four `u32` at the head of `SearchFrame` and `Dispatch` four (an
    // indirect dispatch), read back as words (`search_pass` tests decode them); `Meta` is
    // the indirect draw's four words and a `vec4<u32>` per highlight
    // (`ReceiverObject::read` decodes it, `tests/gpu_receivers.rs` checks it). The
    // structs bound inside a frame buffer (`SearchParams`, `ReceiverParams`, `Query`)
    // have their fields' offsets checked beside their frame's layout test.
    let covered = [
        "Frame",
        "Object",
        "Projector",
        "SolveVertex",
        "FieldVertex",
        "CentreRecord",
        "ClusterRecord",
        "Dispatch",
        "Face",
        "Meta",
        "RegionFrameData",
        "RegionVertex",
        "RegionFace",
        "RegionFit",
        "TrackData",
        "PeakScratch",
        "SearchFrame",
        "ReceiverFrame",
        "ProjectData",
        "ProjectOutput",
    ];
    let uniforms =
        check_coverage(npr_specular::shaders::ALL, &covered).unwrap_or_else(|e| panic!("{e}"));
    assert!(uniforms >= 2, "{uniforms} uniform blocks");
}

/// npr-gpu's `Frame` and `Object` blocks, as composed into this crate's shaders, match
/// their Rust twins (npr-gpu checks its own shaders).
#[test]
fn shared_blocks_match_their_rust_twins_in_the_composed_shaders() {
    let (frames, objects) =
        npr_gpu::testing::wgsl_layout::shared_blocks(npr_specular::shaders::ALL);
    assert!(frames >= 1 && objects >= 1, "{frames} / {objects} blocks");
}
