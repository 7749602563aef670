//! `cargo xtask web --check`: the page in headless Chromium (WebGPU on its SwiftShader
//! adapter), each effect's canvas read back and compared with the native render of the
//! same preset (what `npr render` draws), by FLIP over the object's pixels and PSNR.
//!
//! Chromium is driven through chromedriver with the W3C WebDriver protocol (JSON over
//! HTTP, spoken here with std's `TcpStream`): `--dump-dom` and `--screenshot` return
//! before the page's asynchronous WebGPU work ends. The flags are the ones that work
//! without a GPU; drop any of the last four and `requestAdapter()` returns null or the
//! canvas loses its device.

use anyhow::{Context, bail};
use npr_app::engine::Renderer;
use npr_app::model::Model;
use npr_app::preset::Preset;
use npr_app::view::View;
use npr_app::viewer::state::{Button, HighlightInfo, Input, ViewerState};
use serde_json::{Value, json};
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Chromium's flags for WebGPU with no GPU.
const CHROMIUM_FLAGS: [&str; 7] = [
    "--headless=new",
    "--no-sandbox",
    "--enable-unsafe-webgpu",
    "--use-angle=swiftshader",
    "--enable-features=Vulkan",
    "--use-vulkan=swiftshader",
    "--window-size=1000,900",
];

/// The effects compared with the native render.
const EFFECTS: [&str; 4] = ["phong", "specular", "hatching-pen", "warp"];

/// The largest mean FLIP accepted per effect.
const MAX_FLIP: f64 = 0.05;

/// WebDriver's key for an element reference.
const ELEMENT_KEY: &str = "element-6066-11e4-a52e-4f735466cecf";

/// One effect's comparison.
struct Row {
    effect: String,
    flip_mean: f64,
    flip_max: f64,
    psnr_db: f64,
    page_frame_ms: String,
}

/// Runs the check on the site in `site` (already built), served on `site_port`.
pub fn run(site: &Path, site_port: u16) -> anyhow::Result<()> {
    for tool in ["chromium", "chromedriver"] {
        if Command::new(tool).arg("--version").output().is_err() {
            bail!(
                "{tool} is missing; on Debian/Ubuntu: apt-get install -y chromium chromium-driver"
            );
        }
    }
    let driver = Driver::start()?;
    let session = driver.session()?;
    let result = check(&driver, &session, site, site_port);
    let _ = driver.call("DELETE", &format!("/session/{session}"), None);
    let rows = result?;
    println!("| effect | FLIP mean | FLIP max | PSNR (dB) | page frame (ms) |");
    println!("|---|---|---|---|---|");
    for r in &rows {
        println!(
            "| {} | {:.4} | {:.3} | {:.1} | {} |",
            r.effect, r.flip_mean, r.flip_max, r.psnr_db, r.page_frame_ms
        );
    }
    let failed: Vec<&str> = rows
        .iter()
        .filter(|r| r.flip_mean > MAX_FLIP)
        .map(|r| r.effect.as_str())
        .collect();
    if !failed.is_empty() {
        bail!("the page differs from the native render (FLIP > {MAX_FLIP}): {failed:?}");
    }
    println!("xtask: the page matches the native render for {EFFECTS:?}");
    Ok(())
}

fn check(driver: &Driver, session: &str, site: &Path, site_port: u16) -> anyhow::Result<Vec<Row>> {
    let ctx = npr_gpu::GpuContext::new()?;
    let model = Model::bunny()?;
    let mut rows = Vec::new();
    for effect in EFFECTS {
        let text = format!("effect = \"{effect}\"\n");
        let name = format!("check-{effect}.toml");
        std::fs::write(site.join(&name), &text)?;
        let url = format!("http://127.0.0.1:{site_port}/index.html?preset={name}");
        let page = driver.load(session, &url)?;
        let error = driver.script(
            session,
            "return document.getElementById('error').textContent",
        )?;
        if error.as_str().is_some_and(|e| !e.is_empty()) {
            bail!("{effect}: the page says: {error}");
        }
        // The native frame: the engine `npr render` runs, on this machine's adapter.
        let preset = Preset::from_toml(&text, Path::new(&name))?;
        let size = (preset.output.width, preset.output.height);
        let mut renderer = Renderer::new(&ctx.device, &ctx.queue, model.clone(), size)?;
        let view = View::new(&preset, &model.framing, size, 0.0);
        renderer.render(&ctx.device, &ctx.queue, &preset, &view)?;
        let native = renderer.read(&ctx.device, &ctx.queue)?;
        if page.dimensions() != native.dimensions() {
            bail!(
                "{effect}: the canvas is {:?}, the native render {:?}",
                page.dimensions(),
                native.dimensions()
            );
        }
        rows.push(compare(driver, session, site, effect, &native, &page)?);
        if effect == "specular" {
            // §3.4: pick the first highlight on screen and drag it 40 px to the right,
            // through the shared viewer state on both sides.
            let mut state = ViewerState::new(preset.clone());
            let highlights = renderer
                .highlight_set()
                .map(HighlightInfo::of_set)
                .unwrap_or_default();
            let (id, from) = highlights
                .iter()
                .find_map(|h| view.to_pixel(h.centre_world, size).map(|p| (h.id, p)))
                .context("no highlight on screen to pick")?;
            let to = from + glam::Vec2::new(40.0, 0.0);
            state.input(
                Input::Press {
                    at: from,
                    button: Button::Left,
                },
                &view,
                size,
                &highlights,
            );
            for i in 1..=8 {
                let at = from + (to - from) * (i as f32 / 8.0);
                state.input(Input::Move { at }, &view, size, &highlights);
            }
            state.input(Input::Release { at: to }, &view, size, &highlights);
            renderer.render(&ctx.device, &ctx.queue, &state.preset, &view)?;
            let native = renderer.read(&ctx.device, &ctx.queue)?;
            let picked = driver.script(
                session,
                "const v = window.nprViewer; \
                 const h = JSON.parse(v.highlights_json()).find((h) => h.pixel); \
                 const [x, y] = h.pixel; v.pointer_down(x, y, 0, false, false); \
                 for (let i = 1; i <= 8; i++) v.pointer_move(x + 5 * i, y); \
                 v.pointer_up(x + 40, y); return h.id;",
            )?;
            if picked.as_u64() != Some(id) {
                bail!("the page picked highlight {picked}, the native side {id}");
            }
            std::thread::sleep(Duration::from_secs(3));
            let page = driver.canvas(session)?;
            rows.push(compare(
                driver,
                session,
                site,
                "specular-dragged",
                &native,
                &page,
            )?);
        }
    }
    // A bad model file: its message on the page, and the bunny still there.
    let said = driver.script(
        session,
        "try { window.nprViewer.load_model('broken.ply', new Uint8Array([112, 108, 121, 10, 99])); \
         return 'accepted'; } catch (e) { return String(e) + ' | ' + window.nprViewer.model_name(); }",
    )?;
    let said = said.as_str().unwrap_or("");
    if !said.contains(".ply") || !said.ends_with("| stanford-bunny.obj") {
        bail!("a broken model file: expected its error and the bunny kept, got `{said}`");
    }
    Ok(rows)
}

/// Saves both images into the site folder and measures the page against the native frame.
fn compare(
    driver: &Driver,
    session: &str,
    site: &Path,
    effect: &str,
    native: &image::RgbaImage,
    page: &image::RgbaImage,
) -> anyhow::Result<Row> {
    page.save(site.join(format!("check-{effect}.png")))?;
    native.save(site.join(format!("check-{effect}-native.png")))?;
    let (flip_mean, flip_max) =
        npr_warp::metrics::flip_stats(native, page).context("FLIP of an empty object")?;
    let psnr_db = npr_warp::metrics::compare(native, page).psnr_db;
    let frame_ms = driver.script(
        session,
        "return document.getElementById('stats').dataset.frameMs || ''",
    )?;
    let frame_ms: f64 = frame_ms
        .as_str()
        .and_then(|t| t.parse().ok())
        .unwrap_or(f64::NAN);
    Ok(Row {
        effect: effect.to_string(),
        flip_mean,
        flip_max,
        psnr_db,
        page_frame_ms: format!("{frame_ms:.0}"),
    })
}

/// A chromedriver process on a free port, killed on drop.
struct Driver {
    child: Child,
    port: u16,
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Driver {
    fn start() -> anyhow::Result<Self> {
        let port = TcpListener::bind(("127.0.0.1", 0))?.local_addr()?.port();
        let child = Command::new("chromedriver")
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .context("starting chromedriver")?;
        let driver = Self { child, port };
        let started = Instant::now();
        while driver.call("GET", "/status", None).is_err() {
            if started.elapsed() > Duration::from_secs(20) {
                bail!("chromedriver did not answer on port {port}");
            }
            std::thread::sleep(Duration::from_millis(200));
        }
        Ok(driver)
    }

    /// A new headless Chromium session; its id.
    fn session(&self) -> anyhow::Result<String> {
        let caps = json!({ "capabilities": { "alwaysMatch": {
            "goog:chromeOptions": { "binary": chromium_binary(), "args": CHROMIUM_FLAGS }
        }}});
        let v = self.call("POST", "/session", Some(&caps))?;
        v["sessionId"]
            .as_str()
            .map(str::to_string)
            .context("no session id from chromedriver")
    }

    /// Opens `url`, waits for the page to say it has drawn, and returns the canvas.
    fn load(&self, session: &str, url: &str) -> anyhow::Result<image::RgbaImage> {
        self.call(
            "POST",
            &format!("/session/{session}/url"),
            Some(&json!({ "url": url })),
        )?;
        let started = Instant::now();
        loop {
            let title = self.call("GET", &format!("/session/{session}/title"), None)?;
            match title.as_str().unwrap_or("") {
                "npr ready" => break,
                t if t.starts_with("npr:") => bail!("the page says `{t}` at {url}"),
                _ if started.elapsed() > Duration::from_secs(120) => {
                    bail!("the page did not draw within 120 s: {url}")
                }
                _ => std::thread::sleep(Duration::from_millis(250)),
            }
        }
        // A few more frames: highlights fade in over their first frames.
        std::thread::sleep(Duration::from_secs(3));
        self.canvas(session)
    }

    /// The canvas as the page shows it (WebDriver's element screenshot).
    fn canvas(&self, session: &str) -> anyhow::Result<image::RgbaImage> {
        let canvas = self.call(
            "POST",
            &format!("/session/{session}/element"),
            Some(&json!({ "using": "css selector", "value": "#view" })),
        )?;
        let id = canvas[ELEMENT_KEY].as_str().context("no canvas element")?;
        let png = self.call(
            "GET",
            &format!("/session/{session}/element/{id}/screenshot"),
            None,
        )?;
        let bytes = base64_decode(png.as_str().context("no screenshot")?)?;
        Ok(image::load_from_memory(&bytes)?.to_rgba8())
    }

    /// Runs `script` in the page; its return value.
    fn script(&self, session: &str, script: &str) -> anyhow::Result<Value> {
        self.call(
            "POST",
            &format!("/session/{session}/execute/sync"),
            Some(&json!({ "script": script, "args": [] })),
        )
    }

    /// One WebDriver command: its `value`, or its error as an error.
    fn call(&self, method: &str, path: &str, body: Option<&Value>) -> anyhow::Result<Value> {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port))?;
        stream.set_read_timeout(Some(Duration::from_secs(180)))?;
        let body = body.map(Value::to_string).unwrap_or_default();
        write!(
            stream,
            "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            self.port,
            body.len()
        )?;
        // chromedriver keeps the connection open whatever the request says: read the
        // header, then exactly its Content-Length (or the chunks).
        let mut response = Vec::new();
        let mut buf = [0u8; 65536];
        let split = loop {
            if let Some(i) = response.windows(4).position(|w| w == b"\r\n\r\n") {
                break i;
            }
            let n = stream.read(&mut buf)?;
            if n == 0 {
                bail!("{method} {path}: chromedriver closed the connection");
            }
            response.extend_from_slice(&buf[..n]);
        };
        let head = String::from_utf8_lossy(&response[..split]).to_ascii_lowercase();
        let mut payload = response[split + 4..].to_vec();
        let length = head
            .lines()
            .find_map(|l| l.strip_prefix("content-length:"))
            .and_then(|v| v.trim().parse::<usize>().ok());
        let complete = |p: &[u8]| match length {
            Some(n) => p.len() >= n,
            None => p.ends_with(b"0\r\n\r\n"),
        };
        while !complete(&payload) {
            let n = stream.read(&mut buf)?;
            if n == 0 {
                break;
            }
            payload.extend_from_slice(&buf[..n]);
        }
        if length.is_none() && head.contains("transfer-encoding: chunked") {
            payload = dechunk(&payload)?;
        }
        let v: Value = serde_json::from_slice(&payload)
            .with_context(|| format!("{method} {path}: not JSON"))?;
        let value = v["value"].clone();
        if let Some(error) = value.get("error").and_then(Value::as_str) {
            bail!(
                "{method} {path}: {error}: {}",
                value["message"]
                    .as_str()
                    .unwrap_or("")
                    .lines()
                    .next()
                    .unwrap_or("")
            );
        }
        Ok(value)
    }
}

/// Debian names the binary `chromium`; it is what chromedriver is built against.
fn chromium_binary() -> String {
    ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .into_iter()
        .find(|p| Path::new(p).exists())
        .unwrap_or("chromium")
        .to_string()
}

/// The body of a chunked HTTP response.
fn dechunk(mut data: &[u8]) -> anyhow::Result<Vec<u8>> {
    let mut out = Vec::new();
    loop {
        let line_end = data
            .windows(2)
            .position(|w| w == b"\r\n")
            .context("bad chunk")?;
        let size = usize::from_str_radix(String::from_utf8_lossy(&data[..line_end]).trim(), 16)?;
        data = &data[line_end + 2..];
        if size == 0 {
            return Ok(out);
        }
        out.extend_from_slice(data.get(..size).context("short chunk")?);
        data = data.get(size + 2..).unwrap_or(&[]);
    }
}

/// Standard base64 (WebDriver's screenshots).
fn base64_decode(text: &str) -> anyhow::Result<Vec<u8>> {
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0u32);
    for c in text
        .bytes()
        .filter(|c| !c.is_ascii_whitespace() && *c != b'=')
    {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => bail!("not base64: {:?}", c as char),
        };
        acc = ((acc << 6) | u32::from(v)) & 0xFFFF;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_base64_and_chunks() -> anyhow::Result<()> {
        assert_eq!(base64_decode("aGVsbG8gd29ybGQ=")?, b"hello world");
        assert_eq!(base64_decode("TWFu")?, b"Man");
        assert_eq!(
            dechunk(b"5\r\nhello\r\n6\r\n world\r\n0\r\n\r\n")?,
            b"hello world"
        );
        Ok(())
    }
}
