//! vpype (the plotter community's command-line tool for SVG line art), as `bench plotter`
//! uses it: reading our SVG (`vpype read FILE stat`, which must list our three layers),
//! and the pen-up travel its own `linesort --two-opt` reaches on the same file, the
//! figure our ordering is held to.
//!
//! vpype is Python: `NPR_VPYPE` names its executable, else `vpype` on the PATH, else the
//! bench installs it (pinned) into a virtual environment under the target directory with
//! `python3 -m venv`. Where none of that works, the bench says so and leaves the columns
//! empty.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The vpype release installed when none is found.
const VERSION: &str = "1.15.0";

/// The layer labels vpype must read from our SVG.
const LAYERS: [&str; 3] = ["1 hatching", "2 cross-hatching", "3 outlines"];

/// vpype's totals over every layer of a file, in its units (CSS px).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Totals {
    /// Pen-down length.
    pub length: f64,
    /// Pen-up travel within layers.
    pub pen_up: f64,
}

/// The vpype executable: found, or installed; `None` (with a line saying why) when neither
/// works.
pub fn find_or_install() -> Option<PathBuf> {
    let runs = |p: &Path| {
        Command::new(p)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if let Some(p) = std::env::var_os("NPR_VPYPE").map(PathBuf::from) {
        if runs(&p) {
            return Some(p);
        }
        println!("bench plotter: NPR_VPYPE={} does not run", p.display());
        return None;
    }
    if runs(Path::new("vpype")) {
        return Some(PathBuf::from("vpype"));
    }
    let venv = crate::cargo::target_dir().join("tools/vpype");
    let exe = venv.join("bin/vpype");
    if runs(&exe) {
        return Some(exe);
    }
    println!(
        "bench plotter: installing vpype {VERSION} into {} (python3 -m venv, pip)",
        venv.display()
    );
    let installed = Command::new("python3")
        .args(["-m", "venv"])
        .arg(&venv)
        .status()
        .is_ok_and(|s| s.success())
        && Command::new(venv.join("bin/pip"))
            .args(["install", "--quiet", &format!("vpype=={VERSION}")])
            .status()
            .is_ok_and(|s| s.success());
    if installed && runs(&exe) {
        Some(exe)
    } else {
        println!(
            "bench plotter: vpype could not be installed (needs python3 with venv and \
             network access to PyPI); its columns stay empty. Set NPR_VPYPE to a vpype \
             executable to use one you have."
        );
        None
    }
}

/// `vpype read FILE [linesort --two-opt] stat`: checks that vpype sees our three layers and
/// returns its totals.
///
/// # Errors
/// vpype failing, or its report missing a layer or the totals.
pub fn stat(vpype: &Path, svg: &Path, two_opt: bool) -> anyhow::Result<Totals> {
    let mut cmd = Command::new(vpype);
    cmd.arg("read").arg(svg);
    if two_opt {
        cmd.args(["linesort", "--two-opt"]);
    }
    let out = cmd.arg("stat").output()?;
    anyhow::ensure!(
        out.status.success(),
        "vpype read {} failed: {}",
        svg.display(),
        String::from_utf8_lossy(&out.stderr).trim()
    );
    parse_stat(&String::from_utf8_lossy(&out.stdout))
        .map_err(|e| anyhow::anyhow!("vpype read {}: {e}", svg.display()))
}

/// Reads `vpype stat`'s report: every layer label must be there, and the totals are the
/// last `Length:` and `Pen-up length:` lines (the report's whole-document section).
fn parse_stat(report: &str) -> Result<Totals, String> {
    for label in LAYERS {
        if !report.contains(&format!("svg_inkscape_label: '{label}'")) {
            return Err(format!("vpype does not see the layer \"{label}\""));
        }
    }
    let last = |key: &str| {
        report
            .lines()
            .filter_map(|l| l.trim().strip_prefix(key))
            .filter_map(|v| v.trim().parse::<f64>().ok())
            .next_back()
            .ok_or_else(|| format!("no `{key}` in vpype's report"))
    };
    Ok(Totals {
        length: last("Length:")?,
        pen_up: last("Pen-up length:")?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const REPORT: &str = "========= Stats ========= \nLayer 1\n  Length: 10.0\n  Pen-up length: 2.0\n  \
        svg_inkscape_label: '1 hatching'\nLayer 2\n  Length: 5.0\n  Pen-up length: 1.0\n  \
        svg_inkscape_label: '2 cross-hatching'\nLayer 3\n  Length: 5.0\n  Pen-up length: 1.5\n  \
        svg_inkscape_label: '3 outlines'\nTotals\n  Length: 20.0\n  Pen-up length: 4.5\n";

    #[test]
    fn totals_are_the_last_lines_and_every_layer_is_required() {
        assert_eq!(
            parse_stat(REPORT),
            Ok(Totals {
                length: 20.0,
                pen_up: 4.5
            })
        );
        let missing = REPORT.replace("'3 outlines'", "'outlines'");
        assert!(parse_stat(&missing).unwrap_err().contains("3 outlines"));
        assert!(parse_stat("svg_inkscape_label: '1 hatching'").is_err());
    }
}
