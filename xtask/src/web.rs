//! `cargo xtask web [--build-only | --check] [--port N]`: builds the browser viewer
//! (`npr-web`) into `target/web/` as a static site (`index.html`, `npr_web.js`,
//! `npr_web_bg.wasm`) and serves it on 127.0.0.1 (WebGPU needs a secure context; localhost
//! is one). `--check` serves it on a free port to headless Chromium instead and compares
//! the page with the native render ([`crate::browser`]).
//!
//! The wasm-bindgen CLI must match the `wasm-bindgen` crate of the lockfile exactly; when
//! it is missing or another version it is installed with `cargo install` (3 min 36 s on
//! 2 cores). Not with `--locked`: the CLI's own lockfile asks for a `webpki-roots`
//! release some registries do not serve.

use crate::cargo::cargo;
use crate::project_root;
use anyhow::{Context, bail};
use std::collections::BTreeSet;
use std::io::{BufRead, BufReader, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The wasm target the page is built for.
const WASM_TARGET: &str = "wasm32-unknown-unknown";

/// Builds the site; then with `check` runs the browser check on it, else unless
/// `build_only` serves it on `127.0.0.1:port` until killed.
pub fn run(build_only: bool, check: bool, port: u16) -> anyhow::Result<()> {
    let root = project_root();
    let out = root.join("target/web");
    let web_lock = root.join("crates/npr-web/Cargo.lock");
    check_lockfiles(&root.join("Cargo.lock"), &web_lock)?;
    let version = lockfile_version(&web_lock, "wasm-bindgen")?;
    ensure_wasm_target();
    let bindgen = ensure_wasm_bindgen(&version)?;
    // npr-web is its own workspace (see its manifest); it builds into the main target
    // folder, so the library crates' wasm artifacts are shared with any other wasm build.
    let target = crate::cargo::target_dir();
    let target_arg = target.to_string_lossy();
    // The check serves the check's build of the page (npr-web plus the compute passes'
    // comparisons, `crates/npr-web/check`); the published site is npr-web alone.
    let package = if check { "npr-web-check" } else { "npr-web" };
    cargo(
        &[
            "build",
            "--release",
            "--locked",
            "--manifest-path",
            "crates/npr-web/Cargo.toml",
            "-p",
            package,
            "--target-dir",
            &target_arg,
            "--target",
            WASM_TARGET,
        ],
        &[],
    )?;
    let wasm = target.join(format!(
        "{WASM_TARGET}/release/{}.wasm",
        package.replace('-', "_")
    ));
    std::fs::create_dir_all(&out)?;
    let status = Command::new(&bindgen)
        .args([
            "--target",
            "web",
            "--no-typescript",
            "--out-name",
            "npr_web",
            "--out-dir",
        ])
        .arg(&out)
        .arg(&wasm)
        .status()
        .with_context(|| format!("running {}", bindgen.display()))?;
    if !status.success() {
        bail!("wasm-bindgen failed ({status}) on {}", wasm.display());
    }
    let page = root.join("crates/npr-web/web/index.html");
    std::fs::copy(&page, out.join("index.html"))
        .with_context(|| format!("copying {}", page.display()))?;
    println!("xtask: the site is in {}", out.display());
    if check {
        let listener = TcpListener::bind(("127.0.0.1", 0))?;
        let port = listener.local_addr()?.port();
        let site = out.clone();
        std::thread::spawn(move || serve_on(listener, &site));
        return crate::browser::run(&out, port);
    }
    if build_only {
        return Ok(());
    }
    serve(&out, port)
}

/// Every `(name, version)` a `Cargo.lock` lists.
fn lockfile_packages(lockfile: &Path) -> anyhow::Result<BTreeSet<(String, String)>> {
    let text = std::fs::read_to_string(lockfile)
        .with_context(|| format!("reading {}", lockfile.display()))?;
    let mut out = BTreeSet::new();
    let mut lines = text.lines().map(str::trim);
    while let Some(line) = lines.next() {
        if let Some(name) = line.strip_prefix("name = ")
            && let Some(version) = lines.next().and_then(|l| l.strip_prefix("version = "))
        {
            out.insert((
                name.trim_matches('"').into(),
                version.trim_matches('"').into(),
            ));
        }
    }
    Ok(out)
}

/// The browser build's lockfile must pin what the main one pins: for every package both
/// name, the same versions (the page then runs the code the native tests ran).
fn check_lockfiles(main: &Path, web: &Path) -> anyhow::Result<()> {
    let (main_set, web_set) = (lockfile_packages(main)?, lockfile_packages(web)?);
    let main_names: BTreeSet<&str> = main_set.iter().map(|(n, _)| n.as_str()).collect();
    let differ: Vec<String> = web_set
        .iter()
        .filter(|(n, v)| {
            main_names.contains(n.as_str()) && !main_set.contains(&(n.clone(), v.clone()))
        })
        .map(|(n, v)| format!("{n} {v}"))
        .collect();
    if !differ.is_empty() {
        bail!(
            "{} pins versions the main Cargo.lock does not ({}); copy Cargo.lock over it \
             and run `cargo xtask web --build-only` (cargo then drops what the page does not use)",
            web.display(),
            differ.join(", ")
        );
    }
    Ok(())
}

/// The version of `package` in a `Cargo.lock` (the first entry of that name).
fn lockfile_version(lockfile: &Path, package: &str) -> anyhow::Result<String> {
    let text = std::fs::read_to_string(lockfile)
        .with_context(|| format!("reading {}", lockfile.display()))?;
    let mut lines = text.lines();
    let wanted = format!("name = \"{package}\"");
    while let Some(line) = lines.next() {
        if line.trim() == wanted
            && let Some(v) = lines
                .next()
                .and_then(|l| l.trim().strip_prefix("version = "))
        {
            return Ok(v.trim_matches('"').to_string());
        }
    }
    bail!("{package} is not in {}", lockfile.display())
}

/// Adds the wasm target through rustup when rustup exists (idempotent; without rustup the
/// build says what is missing).
fn ensure_wasm_target() {
    let added = Command::new("rustup")
        .args(["target", "add", WASM_TARGET])
        .status();
    if !added.is_ok_and(|s| s.success()) {
        println!("xtask: could not run `rustup target add {WASM_TARGET}`; building anyway");
    }
}

/// The wasm-bindgen CLI at exactly `version`: the one on PATH (or in cargo's bin folder)
/// when it matches, else installed with `cargo install`.
fn ensure_wasm_bindgen(version: &str) -> anyhow::Result<PathBuf> {
    let cargo_bin = std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo")))
        .map(|h| h.join("bin/wasm-bindgen"));
    let candidates = [Some(PathBuf::from("wasm-bindgen")), cargo_bin];
    let matches = |exe: &Path| {
        Command::new(exe).arg("--version").output().is_ok_and(|o| {
            String::from_utf8_lossy(&o.stdout).split_whitespace().nth(1) == Some(version)
        })
    };
    if let Some(found) = candidates.iter().flatten().find(|c| matches(c)) {
        return Ok(found.clone());
    }
    println!("xtask: installing wasm-bindgen-cli {version} (the lockfile's wasm-bindgen; ~4 min)");
    cargo(
        &[
            "install",
            "wasm-bindgen-cli",
            "--version",
            &format!("={version}"),
            // The one binary the build runs, without the TLS stack its test runner's
            // downloads need (ring's C build).
            "--bin",
            "wasm-bindgen",
            "--no-default-features",
        ],
        &[],
    )?;
    candidates
        .iter()
        .flatten()
        .find(|c| matches(c))
        .cloned()
        .with_context(|| format!("wasm-bindgen {version} installed but not found on PATH"))
}

/// Serves `dir` on `127.0.0.1:port`: GET of its files only, one thread per connection.
fn serve(dir: &Path, port: u16) -> anyhow::Result<()> {
    let listener = TcpListener::bind(("127.0.0.1", port))
        .with_context(|| format!("binding 127.0.0.1:{port}"))?;
    println!(
        "xtask: serving {} on http://127.0.0.1:{port}/ (Ctrl-C stops)",
        dir.display()
    );
    serve_on(listener, dir);
    Ok(())
}

/// Answers `listener`'s connections from `dir`, one thread each, until the process ends.
fn serve_on(listener: TcpListener, dir: &Path) {
    for stream in listener.incoming().flatten() {
        let dir = dir.to_path_buf();
        std::thread::spawn(move || {
            if let Err(e) = respond(stream, &dir) {
                eprintln!("xtask: web: {e}");
            }
        });
    }
}

/// Answers one HTTP/1.0-style request (the connection is closed after it).
fn respond(stream: TcpStream, dir: &Path) -> anyhow::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut request = String::new();
    reader.read_line(&mut request)?;
    // Skip the headers.
    let mut line = String::new();
    while reader.read_line(&mut line)? > 2 {
        line.clear();
    }
    let mut parts = request.split_whitespace();
    let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or("/"));
    let path = target.split(['?', '#']).next().unwrap_or("/");
    let rel = if path.ends_with('/') {
        format!("{path}index.html")
    } else {
        path.to_string()
    };
    let file = dir.join(rel.trim_start_matches('/'));
    let safe = !rel.split('/').any(|c| c == "..");
    let (status, body, kind) = match std::fs::read(&file) {
        Ok(body) if safe && method == "GET" => ("200 OK", body, content_type(&file)),
        _ => ("404 Not Found", b"not found\n".to_vec(), "text/plain"),
    };
    let mut stream = stream;
    write!(
        stream,
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n",
        body.len()
    )?;
    stream.write_all(&body)?;
    Ok(())
}

/// The MIME type browsers need (`application/wasm` for streaming compilation).
fn content_type(file: &Path) -> &'static str {
    match file.extension().and_then(|e| e.to_str()).unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" => "text/javascript",
        "wasm" => "application/wasm",
        "png" => "image/png",
        "toml" | "txt" => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_version_from_a_lockfile() -> anyhow::Result<()> {
        let v = lockfile_version(&project_root().join("Cargo.lock"), "wasm-bindgen")?;
        assert!(v.starts_with("0.2."), "{v}");
        Ok(())
    }

    #[test]
    fn the_browser_lockfile_pins_what_the_main_one_pins() -> anyhow::Result<()> {
        let root = project_root();
        let web = root.join("crates/npr-web/Cargo.lock");
        check_lockfiles(&root.join("Cargo.lock"), &web)?;
        assert!(lockfile_packages(&web)?.iter().any(|(n, _)| n == "wgpu"));
        // A lockfile that pins another wgpu is refused.
        let dir = std::env::temp_dir().join(format!("npr-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir)?;
        let other = dir.join("Cargo.lock");
        std::fs::write(
            &other,
            "[[package]]\nname = \"wgpu\"\nversion = \"0.1.0\"\n",
        )?;
        let refused = check_lockfiles(&root.join("Cargo.lock"), &other);
        std::fs::remove_dir_all(&dir)?;
        assert!(refused.is_err_and(|e| e.to_string().contains("wgpu 0.1.0")));
        Ok(())
    }
}
