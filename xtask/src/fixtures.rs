//! `cargo xtask fixtures`: writes `fixtures/` from the code that defines each file. A test
//! in each owning crate checks that the committed files still match that code.

use crate::project_root;

/// Regenerates every fixture file.
pub fn run() -> anyhow::Result<()> {
    let dir = project_root().join("fixtures");
    std::fs::create_dir_all(&dir)?;
    let ramps = npr_gpu::fixtures::all()
        .into_iter()
        .map(|(n, i)| (n.to_string(), i));
    for (name, image) in ramps.chain(npr_specular::textures::fixtures()) {
        let path = dir.join(name);
        image.save(&path)?;
        println!("fixtures: wrote {}", path.display());
    }
    // The bad-input corpus of `npr_geometry::io` and its manifest.
    let bad = dir.join("bad");
    std::fs::create_dir_all(&bad)?;
    for (name, bytes, _kind) in npr_geometry::io::fixtures::bad() {
        std::fs::write(bad.join(name), bytes)?;
    }
    std::fs::write(
        bad.join("expected.txt"),
        npr_geometry::io::fixtures::expected_txt(),
    )?;
    println!("fixtures: wrote {}/ (bad-input corpus)", bad.display());
    Ok(())
}
