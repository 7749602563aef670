//! The hatching paper's Fig. 2: pen and pencil on single objects at 640×480, as in the
//! paper: `hatching-fig2-OBJECT-STYLE.png` and the sheet `hatching-fig2.png`; and Spot in
//! pen with ink outlines (ours), `hatching-outlines-spot-pen.png`.
//!
//! `cargo run --release -p npr-hatching --example fig2 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, Outlines, fixture, render, single};
use npr_geometry::generate;
use npr_gpu::GpuContext;
use npr_gpu::figures::{out_dir, save, sheet};
use npr_hatching::{HatchParams, TamParams, TamStyle, TonalArtMap};

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    let pen = TonalArtMap::generate(&TamParams::pen())?;
    let pencil = TonalArtMap::generate(&TamParams::pencil())?;
    let singles = vec![
        ("knot", npr_hatching::figures::knot()),
        ("sphere", generate::icosphere(4, 1.0)),
        ("torus", generate::torus(1.0, 0.4, 96, 48)),
        ("spot", fixture("spot")?),
        ("stanford-bunny", fixture("stanford-bunny")?),
    ];
    let mut tiles = Vec::new();
    for (name, mesh) in singles {
        let scene = single(mesh);
        for (tam, style) in [(&pen, TamStyle::Pen), (&pencil, TamStyle::Pencil)] {
            let pencil = style == TamStyle::Pencil;
            let params = [HatchParams {
                stroke_scale: if pencil { 1.25 } else { 1.0 },
                ink: if pencil { [0.04, 0.04, 0.05] } else { [0.0; 3] },
                ..Default::default()
            }];
            let size = (640, 480);
            let imgs = render(&ctx, &scene, tam, &params, false, Outlines::Paper, size)?;
            for img in imgs {
                save(
                    &img,
                    &dir.join(format!("hatching-fig2-{name}-{}.png", style.name())),
                )?;
                tiles.push(img);
            }
            // Spot in pen also with outlines: off (the paper's figure) against on (ours).
            if name == "spot" && style == TamStyle::Pen {
                let imgs = render(&ctx, &scene, tam, &params, false, Outlines::On, size)?;
                save(&imgs[0], &dir.join("hatching-outlines-spot-pen.png"))?;
            }
        }
    }
    save(&sheet(&tiles, 2), &dir.join("hatching-fig2.png"))?;
    Ok(())
}
