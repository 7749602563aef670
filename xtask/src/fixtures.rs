//! `cargo xtask fixtures`: writes `fixtures/` from the code that defines each file. A test
//! in each owning crate checks that the committed files still match that code.

use crate::project_root;

/// Regenerates every fixture file.
pub fn run() -> anyhow::Result<()> {
    let dir = project_root().join("fixtures");
    std::fs::create_dir_all(&dir)?;
    for (name, image) in npr_gpu::fixtures::all() {
        let path = dir.join(name);
        image.save(&path)?;
        println!("fixtures: wrote {}", path.display());
    }
    Ok(())
}
