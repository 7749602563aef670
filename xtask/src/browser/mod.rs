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
use npr_app::viewer::script;
use npr_app::viewer::state::{HighlightInfo, ViewerState};
use serde_json::{Value, json};
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod compute;
mod svg;

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
const EFFECTS: [&str; 5] = ["phong", "specular", "specular-gpu", "hatching-pen", "warp"];

/// The preset a case of [`EFFECTS`] renders: its effect, and for `specular-gpu` the
/// highlights made wholly on the GPU in the page (`[specular] backend = "gpu"`).
fn case_preset(case: &str) -> String {
    match case.strip_suffix("-gpu") {
        Some(effect) => format!("effect = \"{effect}\"\n[specular]\nbackend = \"gpu\"\n"),
        None => format!("effect = \"{case}\"\n"),
    }
}

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
    crate::gpu_setup::ensure_chromium()?;
    let driver = Driver::start()?;
    let session = driver.session()?;
    let result = check(&driver, &session, site, site_port);
    let _ = driver.call("DELETE", &format!("/session/{session}"), None);
    let rows = result?;
    check_no_webgpu(&driver, site_port)?;
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

/// The script the specular check runs on both sides (`npr view --script` format): pick
/// the largest highlight, then the three §3.4 edits — drag, turn, grow.
const EDIT_SCRIPT: &str = "\
@4 click-highlight
@5 drag-selected 40 0
@6 rotate-selected 30
@7 scroll-selected 1
";

fn check(driver: &Driver, session: &str, site: &Path, site_port: u16) -> anyhow::Result<Vec<Row>> {
    let ctx = npr_gpu::GpuContext::new()?;
    let model = Model::bunny()?;
    let mut rows = Vec::new();
    std::fs::write(site.join("check-edits.txt"), EDIT_SCRIPT)?;
    for effect in EFFECTS {
        let text = case_preset(effect);
        let name = format!("check-{effect}.toml");
        std::fs::write(site.join(&name), &text)?;
        let preset = Preset::from_toml(&text, Path::new(&name))?;
        let size = (preset.output.width, preset.output.height);
        let mut renderer = Renderer::new(&ctx, model.clone(), size)?;
        let view = View::new(&preset, &model.framing, size, 0.0);
        for scripted in [false, true] {
            if scripted && effect != "specular" {
                continue;
            }
            let mut url = format!("http://127.0.0.1:{site_port}/index.html?preset={name}");
            let mut label = effect.to_string();
            // The native frame: the engine `npr render` runs, on this machine's adapter,
            // after the same script through the same viewer state.
            let mut state = ViewerState::new(preset.clone());
            renderer.render(&ctx.device, &ctx.queue, &state.preset, &view)?;
            if scripted {
                url.push_str("&script=check-edits.txt");
                label.push_str("-edited");
                let mut last_frame = None;
                for event in script::parse(EDIT_SCRIPT, Path::new("check-edits.txt"))? {
                    if last_frame.is_some_and(|f| f != event.frame) {
                        renderer.render(&ctx.device, &ctx.queue, &state.preset, &view)?;
                    }
                    last_frame = Some(event.frame);
                    let highlights = renderer
                        .highlight_set()
                        .map(HighlightInfo::of_set)
                        .unwrap_or_default();
                    state.script(event.command, &view, size, &highlights)?;
                }
                renderer.render(&ctx.device, &ctx.queue, &state.preset, &view)?;
            }
            let native = object_frame(&ctx, &mut renderer, &state.preset, &view)?;
            let page = driver.load(session, &url)?;
            let error = driver.script(
                session,
                "return document.getElementById('error').textContent",
            )?;
            if error.as_str().is_some_and(|e| !e.is_empty()) {
                bail!("{label}: the page says: {error}");
            }
            if page.dimensions() != native.dimensions() {
                bail!(
                    "{label}: the canvas is {:?}, the native render {:?}",
                    page.dimensions(),
                    native.dimensions()
                );
            }
            if scripted {
                let stats = driver.script(session, "return window.nprViewer.stats_json()")?;
                let stats: Value = serde_json::from_str(stats.as_str().unwrap_or("{}"))?;
                if stats["selected"].as_u64() != state.selected || state.selected.is_none() {
                    bail!(
                        "the page selected highlight {}, the native side {:?}",
                        stats["selected"],
                        state.selected
                    );
                }
            }
            let row = compare(driver, session, site, &label, &native, &page)?;
            if scripted {
                // The edits must show: the page is nearer the edited native frame than the
                // unedited one (FLIP ≤ 0.05 alone would pass a page that ignored them).
                let unedited = image::open(site.join(format!("check-{effect}-native.png")))?;
                let mut masked = page.clone();
                for (p, n) in masked.pixels_mut().zip(native.pixels()) {
                    p[3] = n[3];
                }
                let (to_unedited, _) = npr_warp::metrics::flip_stats(&unedited.to_rgba8(), &masked)
                    .context("FLIP of an empty object")?;
                println!(
                    "xtask: the edited page is FLIP {:.4} from the edited native frame, {:.4} \
                     from the unedited one",
                    row.flip_mean, to_unedited
                );
                if to_unedited < 2.0 * row.flip_mean {
                    bail!(
                        "the page's edits do not show: FLIP {:.4} to the edited native frame, \
                         {to_unedited:.4} to the unedited one",
                        row.flip_mean
                    );
                }
            }
            rows.push(row);
        }
    }
    check_shaders(driver, session)?;
    compute::check(driver, session)?;
    check_bad_drop(driver, session, site, site_port, &ctx, &model)?;
    svg::check(driver, session, (site, site_port), &ctx, &model)?;
    check_clip(driver, session, site, site_port)?;
    Ok(rows)
}

/// Every shader the passes create, composed as they compose it, through Chromium's own
/// WGSL compiler (naga accepts some WGSL Chromium rejects, and the page then shows a black
/// canvas with no error). A shader Chromium must refuse is fed first, so a check that
/// cannot see errors fails.
fn check_shaders(driver: &Driver, session: &str) -> anyhow::Result<()> {
    let result = driver.script_async(
        session,
        "const done = arguments[arguments.length - 1];
         (async () => {
           const adapter = await navigator.gpu.requestAdapter();
           const device = await adapter.requestDevice();
           const known_bad = { crate: 'control', name: 'ends-in-discard.wgsl', source:
             '@fragment fn fs() -> @location(0) vec4<f32> { discard; }' };
           const shaders = [known_bad].concat(JSON.parse(window.nprViewer.shader_sources()));
           const out = [];
           for (const s of shaders) {
             const m = device.createShaderModule({ code: s.source, label: s.name });
             const info = await m.getCompilationInfo();
             out.push({ name: s.crate + '/' + s.name, errors: info.messages
               .filter((m) => m.type === 'error')
               .map((m) => m.lineNum + ':' + m.linePos + ' ' + m.message) });
           }
           device.destroy();
           done(out);
         })().catch((e) => done({ error: String(e) }));",
    )?;
    if let Some(e) = result.get("error") {
        bail!("compiling the shaders in the page: {e}");
    }
    let list = result.as_array().context("no shader list from the page")?;
    let (control, shaders) = list.split_first().context("no shaders compiled")?;
    if control["errors"].as_array().is_none_or(Vec::is_empty) {
        bail!("Chromium accepted a shader it must refuse: the shader check sees no errors");
    }
    let failed: Vec<String> = shaders
        .iter()
        .filter(|s| s["errors"].as_array().is_some_and(|e| !e.is_empty()))
        .map(|s| format!("{}: {}", s["name"], s["errors"]))
        .collect();
    if !failed.is_empty() {
        bail!("Chromium's WGSL compiler refuses: {}", failed.join("; "));
    }
    // The page must list what the crates list (`shaders::ALL` of each).
    let native: Vec<String> = [
        ("npr-gpu", npr_gpu::shaders::ALL),
        ("npr-specular", npr_specular::shaders::ALL),
        ("npr-hatching", npr_hatching::shaders::ALL),
        ("npr-warp", npr_warp::shaders::ALL),
    ]
    .iter()
    .flat_map(|(krate, files)| files.iter().map(move |f| format!("{krate}/{}", f.name)))
    .collect();
    let listed: Vec<&str> = shaders.iter().filter_map(|s| s["name"].as_str()).collect();
    if listed != native {
        bail!("the page compiled {listed:?}, the crates have {native:?}");
    }
    println!(
        "xtask: Chromium compiles all {} shaders as the passes compose them",
        shaders.len()
    );
    Ok(())
}

/// A broken model dropped on the canvas (a real `drop` event with the file): its
/// one-line message on the page, naming the file, and the bunny still drawn as before;
/// then a bad preset dropped the same way: its message, and the effect in use kept.
fn check_bad_drop(
    driver: &Driver,
    session: &str,
    site: &Path,
    site_port: u16,
    ctx: &npr_gpu::GpuContext,
    model: &Model,
) -> anyhow::Result<()> {
    let url = format!("http://127.0.0.1:{site_port}/index.html?preset=check-phong.toml");
    driver.load(session, &url)?;
    driver.script(
        session,
        "const dt = new DataTransfer();
         dt.items.add(new File([new Uint8Array([112, 108, 121, 10, 99])], 'broken.ply'));
         document.getElementById('view').dispatchEvent(
           new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
         return true;",
    )?;
    let said = page_error(driver, session, "a broken model was dropped")?;
    if !said.contains("broken.ply") {
        bail!("a broken model's message does not name the file: `{said}`");
    }
    let name = driver.script(session, "return window.nprViewer.model_name()")?;
    if name.as_str() != Some(model.name.as_str()) {
        bail!(
            "after a broken drop the model is {name}, not {}",
            model.name
        );
    }
    // A bad preset dropped the same way: its message, and the preset in use stays.
    driver.script(
        session,
        "document.getElementById('error').textContent = '';
         const dt = new DataTransfer();
         dt.items.add(new File(['effect = \"hatching-crayon\"\\n'], 'bad.toml'));
         document.getElementById('view').dispatchEvent(
           new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
         return true;",
    )?;
    let said_preset = page_error(driver, session, "a bad preset was dropped")?;
    let effect = driver.script(session, "return window.nprViewer.effect()")?;
    if !said_preset.contains("bad.toml") || effect.as_str() != Some("phong") {
        bail!("a bad preset: expected its message and phong kept, got `{said_preset}`, {effect}");
    }
    println!("xtask: a bad preset says `{said_preset}` and phong stays");
    std::thread::sleep(Duration::from_secs(2));
    let page = driver.canvas(session)?;
    let preset = Preset::from_toml("effect = \"phong\"\n", Path::new("check-phong.toml"))?;
    let size = (preset.output.width, preset.output.height);
    let mut renderer = Renderer::new(ctx, model.clone(), size)?;
    let view = View::new(&preset, &model.framing, size, 0.0);
    let native = object_frame(ctx, &mut renderer, &preset, &view)?;
    let row = compare(
        driver,
        session,
        site,
        "phong-after-bad-drop",
        &native,
        &page,
    )?;
    if row.flip_mean > MAX_FLIP {
        bail!(
            "after a broken drop the page no longer draws the bunny (FLIP {:.3})",
            row.flip_mean
        );
    }
    println!(
        "xtask: a broken drop says `{said}` and the bunny stays (FLIP {:.4})",
        row.flip_mean
    );
    Ok(())
}

/// The page plays a glTF clip: the Fox, loaded as a dropped file would be, lists its
/// clips and plays the first, its clip time advancing from frame to frame and the canvas
/// changing; pausing holds the time.
fn check_clip(driver: &Driver, session: &str, site: &Path, site_port: u16) -> anyhow::Result<()> {
    std::fs::copy(crate::fixture_mesh("Fox.glb"), site.join("Fox.glb"))?;
    let url = format!("http://127.0.0.1:{site_port}/index.html?preset=check-phong.toml");
    driver.load(session, &url)?;
    let names = driver.script_async(
        session,
        "const done = arguments[arguments.length - 1];
         fetch('Fox.glb').then((r) => r.arrayBuffer()).then((b) => {
           try { window.nprViewer.load_model('Fox.glb', new Uint8Array(b)); window.nprShowClips(); }
           catch (e) { done('error: ' + e); return; }
           setTimeout(() => done(window.nprViewer.clip_names()), 500);
         });",
    )?;
    let names = names.as_str().unwrap_or("");
    if !names.contains("Walk") {
        bail!("the page lists the Fox's clips as {names}");
    }
    let stats = |driver: &Driver| -> anyhow::Result<Value> {
        let s = driver.script(session, "return window.nprViewer.stats_json()")?;
        Ok(serde_json::from_str(s.as_str().unwrap_or("{}"))?)
    };
    let first = stats(driver)?;
    let before = driver.canvas(session)?;
    std::thread::sleep(Duration::from_secs(3));
    let later = stats(driver)?;
    let after = driver.canvas(session)?;
    let t = |v: &Value| v["clip_time"].as_f64().unwrap_or(f64::NAN);
    if first["clip"] != 0 || t(&later).partial_cmp(&t(&first)) != Some(std::cmp::Ordering::Greater)
    {
        bail!("the page does not play the Fox's first clip: {first} then {later}");
    }
    let moved = before
        .pixels()
        .zip(after.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 16))
        .count();
    if moved < 100 {
        bail!("the Fox does not move on the page ({moved} pixels changed in 3 s)");
    }
    driver.script(session, "return window.nprViewer.toggle_clip()")?;
    let paused = stats(driver)?;
    std::thread::sleep(Duration::from_secs(1));
    let still = stats(driver)?;
    if t(&paused) != t(&still) {
        bail!(
            "paused, the clip time still moves: {} then {}",
            t(&paused),
            t(&still)
        );
    }
    println!(
        "xtask: the page plays the Fox's clips {names}: clip time {:.2} -> {:.2} s, {moved} pixels moved; paused at {:.2} s",
        t(&first),
        t(&later),
        t(&still)
    );
    Ok(())
}

/// The page in a Chromium without WebGPU (headless, none of the flags that give it
/// SwiftShader's adapter): a one-line message and a title that says so, not a blank
/// canvas.
fn check_no_webgpu(driver: &Driver, site_port: u16) -> anyhow::Result<()> {
    let session = driver.session_with(&[
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-features=Vulkan,WebGPU",
    ])?;
    let outcome = (|| {
        let url = format!("http://127.0.0.1:{site_port}/index.html");
        match driver
            .open(&session, &url, Duration::from_secs(60))?
            .as_str()
        {
            "npr: no WebGPU" => {}
            "npr ready" => bail!("the page drew in a Chromium without WebGPU"),
            other => bail!("without WebGPU the page's title is `{other}`"),
        }
        let said = page_error(driver, &session, "the page found no WebGPU")?;
        if !said.contains("WebGPU") || said.contains("apt-get") {
            bail!("without WebGPU the page should say so in a browser's terms: `{said}`");
        }
        println!("xtask: without WebGPU the page says `{said}`");
        Ok(())
    })();
    let _ = driver.call("DELETE", &format!("/session/{session}"), None);
    outcome
}

/// The one-line message the page shows after `what`, waited for (up to 20 s).
fn page_error(driver: &Driver, session: &str, what: &str) -> anyhow::Result<String> {
    let started = Instant::now();
    loop {
        let said = driver.script(
            session,
            "return document.getElementById('error').textContent",
        )?;
        let said = said.as_str().unwrap_or("").to_string();
        if !said.is_empty() {
            return Ok(said);
        }
        if started.elapsed() > Duration::from_secs(20) {
            bail!("{what} and the page said nothing");
        }
        std::thread::sleep(Duration::from_millis(250));
    }
}

/// The native frame of `preset`, its alpha the object's coverage: the frame is drawn on
/// the preset's background and on black, and a pixel the background does not change is
/// the object's (partly, at edges). The comparisons then weigh the object, not the empty
/// background around it.
fn object_frame(
    ctx: &npr_gpu::GpuContext,
    renderer: &mut Renderer,
    preset: &Preset,
    view: &View,
) -> anyhow::Result<image::RgbaImage> {
    let mut on_black = preset.clone();
    on_black.base.background = [0.0, 0.0, 0.0];
    renderer.render(&ctx.device, &ctx.queue, &on_black, view)?;
    let black = renderer.read(&ctx.device, &ctx.queue)?;
    renderer.render(&ctx.device, &ctx.queue, preset, view)?;
    let mut frame = renderer.read(&ctx.device, &ctx.queue)?;
    for (p, b) in frame.pixels_mut().zip(black.pixels()) {
        let moved = (0..3).map(|c| p[c].abs_diff(b[c])).max().unwrap_or(0);
        p[3] = 255 - moved;
    }
    Ok(frame)
}

/// Saves both images into the site folder and measures the page against the native frame
/// over the object (the native frame's alpha, see [`object_frame`], masks both).
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
    let mut page = page.clone();
    for (p, n) in page.pixels_mut().zip(native.pixels()) {
        p[3] = n[3];
    }
    let (flip_mean, flip_max) =
        npr_warp::metrics::flip_stats(native, &page).context("FLIP of an empty object")?;
    let psnr_db = npr_warp::metrics::compare(native, &page).psnr_db;
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
        self.session_with(&CHROMIUM_FLAGS)
    }

    /// A new headless Chromium session with `args`; its id.
    fn session_with(&self, args: &[&str]) -> anyhow::Result<String> {
        let caps = json!({ "capabilities": { "alwaysMatch": {
            "goog:chromeOptions": { "binary": chromium_binary(), "args": args },
            // SwiftShader compiles and draws on the CPU: give scripts and loads time.
            "timeouts": { "script": 180_000, "pageLoad": 180_000 }
        }}});
        let v = self.call("POST", "/session", Some(&caps))?;
        v["sessionId"]
            .as_str()
            .map(str::to_string)
            .context("no session id from chromedriver")
    }

    /// Opens `url` and waits (up to `limit`) for the page's final title: `npr ready` once
    /// it has drawn (and run its script), or `npr: ...` when it cannot draw.
    fn open(&self, session: &str, url: &str, limit: Duration) -> anyhow::Result<String> {
        self.call(
            "POST",
            &format!("/session/{session}/url"),
            Some(&json!({ "url": url })),
        )?;
        let started = Instant::now();
        loop {
            let title = self.call("GET", &format!("/session/{session}/title"), None)?;
            let title = title.as_str().unwrap_or("");
            if title == "npr ready" || title.starts_with("npr:") {
                return Ok(title.to_string());
            }
            if started.elapsed() > limit {
                bail!("the page did not draw within {} s: {url}", limit.as_secs());
            }
            std::thread::sleep(Duration::from_millis(250));
        }
    }

    /// Opens `url`, waits for the page to say it has drawn, and returns the canvas.
    fn load(&self, session: &str, url: &str) -> anyhow::Result<image::RgbaImage> {
        let title = self.open(session, url, Duration::from_secs(120))?;
        if title != "npr ready" {
            bail!("the page says `{title}` at {url}");
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

    /// Runs `script` in the page as an asynchronous script: its value is what it passes to
    /// its last argument (the callback).
    fn script_async(&self, session: &str, script: &str) -> anyhow::Result<Value> {
        self.call(
            "POST",
            &format!("/session/{session}/execute/async"),
            Some(&json!({ "script": script, "args": [] })),
        )
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
