//! Highlight sizing: the specular paper's Eq. (8) against ours (the footprint fitted to
//! the region N·H ≥ σ it stylizes, `HighlightSizing::Region`), on the scans,
//! `specular-sizing-SUBJECT-{paper,ours}.png`.
//!
//! `cargo run --release -p npr-specular --example sizing -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, disc, phong};
use npr_gpu::figures::{out_dir, save};
use npr_specular::HighlightSizing;

/// The subjects of the sizing comparison.
const SUBJECTS: [&str; 2] = ["spot", "stanford-bunny"];

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let (ctx, renderer) = common::setup()?;
    for mut s in common::subjects(&ctx, &SUBJECTS)? {
        for (label, how) in [
            ("paper", HighlightSizing::Paper),
            ("ours", HighlightSizing::Region),
        ] {
            s.set.tuning.sizing = how;
            s.set.reset();
            let img = phong(&ctx, &renderer, &mut s, disc())?;
            save(
                &img,
                &dir.join(format!("specular-sizing-{}-{label}.png", s.name)),
            )?;
        }
    }
    Ok(())
}
