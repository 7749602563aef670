//! The committed highlight-texture fixtures equal what the code generates (regenerate
//! with `cargo xtask fixtures`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[test]
fn committed_highlight_textures_match_the_code() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let mut problems = Vec::new();
    for (name, want) in npr_specular::textures::fixtures() {
        match image::open(dir.join(&name)) {
            Ok(img) if img.to_rgba8() == want => {}
            Ok(_) => problems.push(format!("{name}: differs from the code")),
            Err(e) => problems.push(format!("{name}: {e}")),
        }
    }
    assert!(
        problems.is_empty(),
        "run `cargo xtask fixtures`:\n{}",
        problems.join("\n")
    );
}
