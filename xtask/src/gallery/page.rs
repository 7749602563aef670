//! The gallery page itself: the HTML made from [`super::figures`] and
//! [`super::departures`], and the check that the demo wrote exactly the listed files.

use super::{Section, departures, figures, files};
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The file name of the page, in the demo directory.
pub const INDEX: &str = "index.html";

/// Escapes text for HTML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The page: one HTML file, images by relative path.
pub fn html() -> String {
    let mut p = String::new();
    p.push_str(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>npr: the papers' figures</title>\n<style>\n\
         body { font-family: sans-serif; max-width: 1400px; margin: 2em auto; padding: 0 1em; }\n\
         figure { margin: 1.5em 0; } img { max-width: 100%; border: 1px solid #ccc; }\n\
         figcaption { max-width: 60em; } .parts { font-size: 0.85em; color: #555; }\n\
         .pair { display: flex; gap: 1em; flex-wrap: wrap; } .pair figure { margin: 0; }\n\
         </style>\n</head>\n<body>\n<h1>npr: the papers' figures</h1>\n\
         <p>Written by <code>cargo xtask demo</code>. Each caption names the paper figure it \
         reproduces (or says it is ours) and its parameters. Departures from the papers are \
         shown as before/after pairs at the end.</p>\n",
    );
    let figures = figures();
    p.push_str("<ul>\n");
    for s in Section::ALL {
        let _ = writeln!(p, "<li><a href=\"#{s:?}\">{}</a></li>", esc(s.title()));
    }
    p.push_str("<li><a href=\"#departures\">Departures: before and after</a></li>\n</ul>\n");
    for s in Section::ALL {
        let _ = writeln!(p, "<h2 id=\"{s:?}\">{}</h2>", esc(s.title()));
        if !s.paper().is_empty() {
            let _ = writeln!(p, "<p><em>{}</em></p>", esc(s.paper()));
        }
        for f in figures.iter().filter(|f| f.section == s) {
            let label = match f.figure {
                Some(n) => format!("{} {n}", s.short()),
                None => "Ours".to_string(),
            };
            let _ = writeln!(
                p,
                "<figure>\n<img src=\"{}\" alt=\"{}\" loading=\"lazy\">\n\
                 <figcaption><strong>{}.</strong> {}",
                esc(&f.file),
                esc(&f.file),
                esc(&label),
                esc(&f.caption)
            );
            if !f.parts.is_empty() {
                p.push_str("<br><span class=\"parts\">Tiles alone:");
                for part in &f.parts {
                    let _ = write!(p, " <a href=\"{}\">{}</a>", esc(part), esc(part));
                }
                p.push_str("</span>");
            }
            p.push_str("</figcaption>\n</figure>\n");
        }
    }
    p.push_str("<h2 id=\"departures\">Departures: before and after</h2>\n");
    for d in departures() {
        let _ = writeln!(p, "<h3>{}</h3>\n<div class=\"pair\">", esc(d.title));
        for (file, label) in [(&d.before, d.before_label), (&d.after, d.after_label)] {
            let _ = writeln!(
                p,
                "<figure><img src=\"{}\" alt=\"{}\" loading=\"lazy\">\
                 <figcaption>{}</figcaption></figure>",
                esc(file),
                esc(label),
                esc(label)
            );
        }
        let _ = writeln!(p, "</div>\n<p>{}</p>", esc(&d.caption));
    }
    p.push_str("</body>\n</html>\n");
    p
}

/// Checks that the demo wrote exactly the listed files into `dir` (each listed file was
/// written this run and exists; nothing unlisted was written).
///
/// # Errors
/// Names the missing and the unlisted files.
pub fn check_written(dir: &Path, written: &[PathBuf]) -> anyhow::Result<()> {
    let listed = files();
    let names: BTreeSet<String> = written
        .iter()
        .filter_map(|p| {
            p.strip_prefix(dir)
                .ok()
                .map(|r| r.to_string_lossy().into_owned())
        })
        .collect();
    let missing: Vec<&String> = listed
        .iter()
        .filter(|f| !names.contains(*f) || !dir.join(f).is_file())
        .collect();
    let unlisted: Vec<&String> = names.iter().filter(|f| !listed.contains(*f)).collect();
    if !missing.is_empty() || !unlisted.is_empty() || names.len() != written.len() {
        anyhow::bail!(
            "the gallery (xtask/src/gallery.rs) and the demo disagree: listed but not written: \
             {missing:?}; written but not listed: {unlisted:?}"
        );
    }
    Ok(())
}

/// Writes the page into `dir`; returns its path.
///
/// # Errors
/// The write failing.
pub fn write(dir: &Path) -> anyhow::Result<PathBuf> {
    let path = dir.join(INDEX);
    std::fs::write(&path, html())
        .map_err(|e| anyhow::anyhow!("writing {}: {e}", path.display()))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every value of `attr="..."` in `html`.
    fn attribute_values(html: &str, attr: &str) -> Vec<String> {
        let key = format!("{attr}=\"");
        html.match_indices(&key)
            .filter_map(|(i, _)| {
                let rest = &html[i + key.len()..];
                rest.find('"').map(|end| rest[..end].to_string())
            })
            .collect()
    }

    #[test]
    fn every_image_the_page_names_is_written_by_the_demo() {
        let page = html();
        let listed = files();
        let srcs = attribute_values(&page, "src");
        assert!(srcs.len() >= figures().len(), "one img per figure at least");
        let links: Vec<String> = attribute_values(&page, "href")
            .into_iter()
            .filter(|h| !h.starts_with('#'))
            .collect();
        for name in srcs.iter().chain(&links) {
            assert!(
                listed.contains(name),
                "the page names {name}, which the demo does not write"
            );
            assert!(
                !name.contains("..") && !name.starts_with('/'),
                "{name} is not relative"
            );
        }
        // And the page shows or links every file the demo writes.
        let on_page: BTreeSet<&String> = srcs.iter().chain(&links).collect();
        for f in &listed {
            assert!(on_page.contains(f), "{f} is written but not on the page");
        }
    }

    #[test]
    fn every_figure_has_a_caption_and_each_missing_paper_figure_is_there() {
        for f in figures() {
            assert!(f.caption.len() > 20, "{} has no real caption", f.file);
        }
        let named = |section: Section, n: &str| {
            figures()
                .iter()
                .any(|f| f.section == section && f.figure == Some(n))
        };
        for n in ["Fig. 2", "Fig. 4", "Fig. 5", "Fig. 6", "Fig. 7", "Fig. 8"] {
            assert!(named(Section::Specular, n), "specular {n}");
        }
        for n in ["Fig. 1", "Fig. 2", "Fig. 3", "Fig. 4"] {
            assert!(named(Section::Hatching, n), "hatching {n}");
        }
        for n in ["Fig. 8", "Fig. 9", "Fig. 10"] {
            assert!(named(Section::Warp, n), "warp {n}");
        }
    }

    #[test]
    fn check_written_names_missing_and_unlisted_files() {
        let dir = std::env::temp_dir().join(format!("npr-gallery-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut written = Vec::new();
        for f in files() {
            let p = dir.join(&f);
            std::fs::write(&p, b"x").unwrap();
            written.push(p);
        }
        assert!(check_written(&dir, &written).is_ok());
        let extra = dir.join("not-listed.png");
        std::fs::write(&extra, b"x").unwrap();
        written.push(extra);
        let e = check_written(&dir, &written).unwrap_err().to_string();
        assert!(e.contains("not-listed.png"), "{e}");
        written.pop();
        let gone = written.remove(0);
        std::fs::remove_file(&gone).unwrap();
        let e = check_written(&dir, &written).unwrap_err().to_string();
        let name = gone.file_name().unwrap().to_string_lossy().into_owned();
        assert!(e.contains(&name), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
