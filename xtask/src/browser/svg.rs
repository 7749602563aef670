//! The page's "save SVG": the pen plotter's SVG traced in the browser, against the one
//! `npr render --svg` traces natively from the same preset and view.

use super::{Driver, page_error};
use anyhow::bail;
use npr_app::model::Model;
use npr_app::preset::Preset;
use std::path::Path;

/// The largest difference in each layer's drawn length, page against native (the two
/// rasterisers differ by a few pixels along edges, and streamlines seeded there move).
const MAX_LENGTH_DIFFERENCE: f64 = 0.10;

/// One layer of a pen plotter SVG: its label, its strokes and their length in mm.
#[derive(Debug, PartialEq)]
struct Layer {
    label: String,
    strokes: usize,
    length_mm: f64,
}

/// The layers of an SVG as `npr_hatching::pen::to_svg` writes it (one `<g>` per pen,
/// `<polyline>` strokes).
fn layers(svg: &str) -> Vec<Layer> {
    let mut out: Vec<Layer> = Vec::new();
    for line in svg.lines() {
        if let Some(rest) = line.split("inkscape:label=\"").nth(1) {
            out.push(Layer {
                label: rest.split('"').next().unwrap_or("").to_string(),
                strokes: 0,
                length_mm: 0.0,
            });
        } else if let (Some(points), Some(layer)) = (line.split("points=\"").nth(1), out.last_mut())
        {
            let p: Vec<[f64; 2]> = points
                .split('"')
                .next()
                .unwrap_or("")
                .split(' ')
                .filter_map(|xy| {
                    let (x, y) = xy.split_once(',')?;
                    Some([x.parse().ok()?, y.parse().ok()?])
                })
                .collect();
            layer.strokes += 1;
            layer.length_mm += p
                .windows(2)
                .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
                .sum::<f64>();
        }
    }
    out
}

/// Asks the page for the SVG of the hatching-pen preset `preset_file` (A4, 0.3 mm pen),
/// waits for its download, and compares its layers with the native trace. An effect other
/// than hatching must be refused with one line.
pub(super) fn check(
    driver: &Driver,
    session: &str,
    (site, site_port): (&Path, u16),
    ctx: &npr_gpu::GpuContext,
    model: &Model,
) -> anyhow::Result<()> {
    let url = format!("http://127.0.0.1:{site_port}/index.html?preset=check-phong.toml");
    driver.load(session, &url)?;
    driver.script(
        session,
        "try { window.nprViewer.save_svg('x.svg', 'a4', 0.3); } catch (e) {
           document.getElementById('error').textContent = String(e);
         }
         return true;",
    )?;
    let said = page_error(driver, session, "save SVG was asked of phong")?;
    if !said.contains("save SVG draws the hatching") {
        bail!("save SVG with phong: expected the hatching-only message, got `{said}`");
    }
    println!("xtask: save SVG with phong says `{said}`");

    let name = "check-hatching-pen.toml";
    let url = format!("http://127.0.0.1:{site_port}/index.html?preset={name}");
    driver.load(session, &url)?;
    let result = driver.script_async(
        session,
        "const done = arguments[arguments.length - 1];
         window.nprLastSvg = undefined;
         try { window.nprViewer.save_svg('check.svg', 'a4', 0.3); } catch (e) { done('error: ' + e); return; }
         const started = performance.now();
         const wait = () => {
           if (window.nprLastSvg) done(window.nprLastSvg);
           else if (document.getElementById('error').textContent) done('error: ' + document.getElementById('error').textContent);
           else if (performance.now() - started > 120000) done('error: no SVG after 120 s');
           else setTimeout(wait, 100);
         };
         wait();",
    )?;
    let page_svg = result.as_str().unwrap_or("").to_string();
    if let Some(e) = page_svg.strip_prefix("error: ") {
        bail!("save SVG on the page: {e}");
    }
    std::fs::write(site.join("check-pen.svg"), &page_svg)?;

    let preset = Preset::from_toml(&std::fs::read_to_string(site.join(name))?, Path::new(name))?;
    let native_svg = crate::bench::plotter::trace(ctx, model.clone(), preset)?.svg;
    std::fs::write(site.join("check-pen-native.svg"), &native_svg)?;

    let (on_page, native) = (layers(&page_svg), layers(&native_svg));
    let labels = |l: &[Layer]| l.iter().map(|l| l.label.clone()).collect::<Vec<_>>();
    if labels(&on_page) != labels(&native) || native.len() != 3 {
        bail!(
            "the page's SVG has layers {:?}, the native one {:?}",
            labels(&on_page),
            labels(&native)
        );
    }
    if native[0].strokes == 0 || native[2].strokes == 0 {
        bail!("the native SVG has no hatching or no outlines: {native:?}");
    }
    for (p, n) in on_page.iter().zip(&native) {
        println!(
            "xtask: save SVG, layer \"{}\": {} strokes, {:.0} mm on the page; {} strokes, {:.0} mm natively",
            n.label, p.strokes, p.length_mm, n.strokes, n.length_mm
        );
        // A layer with little ink (a light view's cross-hatching) is judged against 50 mm.
        let difference = (p.length_mm - n.length_mm).abs() / n.length_mm.max(50.0);
        if difference > MAX_LENGTH_DIFFERENCE {
            bail!(
                "layer \"{}\": {:.0} mm of strokes on the page, {:.0} mm natively ({:.0} % apart; at most {:.0} %)",
                n.label,
                p.length_mm,
                n.length_mm,
                100.0 * difference,
                100.0 * MAX_LENGTH_DIFFERENCE
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layers_are_counted_and_measured() {
        let svg = "<svg>\n<g inkscape:groupmode=\"layer\" inkscape:label=\"1 hatching\">\n\
                   <polyline points=\"0,0 3,4\"/>\n<polyline points=\"1,1 1,2 2,2\"/>\n</g>\n\
                   <g inkscape:label=\"2 cross-hatching\">\n</g>\n</svg>\n";
        assert_eq!(
            layers(svg),
            vec![
                Layer {
                    label: "1 hatching".into(),
                    strokes: 2,
                    length_mm: 7.0
                },
                Layer {
                    label: "2 cross-hatching".into(),
                    strokes: 0,
                    length_mm: 0.0
                }
            ]
        );
    }
}
