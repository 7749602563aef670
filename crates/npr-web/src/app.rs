//! The viewer object the page holds (wasm32 only).

use glam::Vec2;
use npr_app::engine::{FrameStats, Renderer};
use npr_app::model::Model;
use npr_app::preset::{Effect, Preset};
use npr_app::viewer::live::WarpLive;
use npr_app::viewer::script::{self, Command, Event};
use npr_app::viewer::state::{Button, HighlightInfo, Input, Key, ViewerState};
use std::collections::VecDeque;
use std::path::Path;
use wasm_bindgen::prelude::*;
use web_time::Instant;

/// An error as the page shows it: one line.
fn js_error(e: impl std::fmt::Display) -> JsValue {
    JsValue::from_str(&e.to_string())
}

/// The live viewer on one canvas: a GPU context, the engine, the viewer's state.
#[wasm_bindgen]
pub struct Viewer {
    ctx: npr_gpu::GpuContext,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    renderer: Renderer,
    state: ViewerState,
    stats: FrameStats,
    /// When the last frames started (up to 31), for the frame time.
    frame_times: VecDeque<Instant>,
    frame_ms: f64,
    /// Frames drawn since the start (live warping's clock).
    frame: u64,
    warp: WarpLive,
    /// The loaded script, the frame it started at, and how far it has run.
    script: Vec<Event>,
    script_start: u64,
    script_pos: usize,
    /// What the script asked of the page (downloads), as JSON objects, until taken.
    actions: Vec<serde_json::Value>,
    /// A "save SVG" on its way: asked for, then read back over the next frames.
    svg: Option<SvgRequest>,
    /// A glTF model's clip, posed each frame (space plays or pauses it).
    timeline: npr_app::viewer::timeline::Timeline,
}

/// A "save SVG" ([`Viewer::save_svg`]): the file name and page asked for, and once the
/// next frame is drawn, the G-buffer readback with the view it was drawn from.
struct SvgRequest {
    file: String,
    page: npr_hatching::pen::Page,
    readback: Option<(npr_hatching::GBufferReadback, npr_app::view::View, Preset)>,
}

#[wasm_bindgen]
impl Viewer {
    /// Starts a viewer on `canvas` (its current size) with the built-in bunny and the
    /// default preset (phong). Fails with a one-line message when the browser has no
    /// WebGPU adapter.
    pub async fn start(canvas: web_sys::HtmlCanvasElement) -> Result<Viewer, JsValue> {
        std::panic::set_hook(Box::new(|info| {
            web_sys::console::error_1(&JsValue::from_str(&info.to_string()));
        }));
        let size = (canvas.width().max(1), canvas.height().max(1));
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
        descriptor.backends = wgpu::Backends::BROWSER_WEBGPU;
        let (ctx, surface) = npr_gpu::GpuContext::for_surface_async(descriptor, move |i| {
            i.create_surface(wgpu::SurfaceTarget::Canvas(canvas))
        })
        .await
        .map_err(|e| match e {
            // The native message's fix (install a Vulkan driver) means nothing in a page.
            npr_gpu::GpuError::NoAdapter { .. } => js_error(
                "This browser gives the page no WebGPU adapter (WebGPU is off, or the GPU is \
                 blocklisted): try a recent Chrome or Edge, or turn WebGPU on in the browser's flags.",
            ),
            other => js_error(other),
        })?;
        let config = wgpu::SurfaceConfiguration {
            // The frame is copied in from the engine's target, not drawn.
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_DST,
            // Copy-compatible with the target's Rgba8UnormSrgb (formats that differ only
            // in sRGB-ness): the canvas shows the sRGB-encoded bytes as they are.
            format: wgpu::TextureFormat::Rgba8Unorm,
            width: size.0,
            height: size.1,
            present_mode: wgpu::PresentMode::Fifo,
            desired_maximum_frame_latency: 2,
            alpha_mode: wgpu::CompositeAlphaMode::Opaque,
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        surface.configure(&ctx.device, &config);
        let model = Model::bunny().map_err(js_error)?;
        let timeline = npr_app::viewer::timeline::Timeline::new(&model);
        let renderer = Renderer::new(&ctx, model, size).map_err(js_error)?;
        let mut preset = Preset::default();
        preset.output.width = size.0;
        preset.output.height = size.1;
        Ok(Viewer {
            ctx,
            surface,
            config,
            renderer,
            state: ViewerState::new(preset),
            stats: FrameStats::default(),
            frame_times: VecDeque::new(),
            frame_ms: 0.0,
            frame: 0,
            warp: WarpLive::default(),
            script: Vec::new(),
            script_start: 0,
            script_pos: 0,
            actions: Vec::new(),
            svg: None,
            timeline,
        })
    }

    /// The adapter, one line (name, type, backend).
    pub fn adapter(&self) -> String {
        self.ctx.adapter_summary()
    }

    /// Renders one frame of the current preset and view onto the canvas.
    pub fn frame(&mut self) -> Result<(), JsValue> {
        // The frame time: the mean interval over the last 30 frames (one interval says
        // little when the browser runs callbacks back to back while the GPU catches up).
        let now = Instant::now();
        self.frame_times.push_back(now);
        if self.frame_times.len() > 31 {
            self.frame_times.pop_front();
        }
        if let (Some(first), n) = (self.frame_times.front(), self.frame_times.len())
            && n > 1
        {
            self.frame_ms = now.duration_since(*first).as_secs_f64() * 1e3 / (n - 1) as f64;
        }
        let scripted = self.run_script();
        self.state.tick();
        // A clip that cannot be posed shows its line once the frame is drawn.
        let posed = self
            .timeline
            .update(
                &mut self.renderer,
                (&self.ctx.device, &self.ctx.queue),
                &self.state,
            )
            .map_err(js_error);
        let size = self.renderer.size();
        let view = self.state.view(&self.renderer.model().framing, size);
        let drawn = self.warp.draw(
            &mut self.renderer,
            &self.ctx,
            &self.state,
            &view,
            self.frame,
        );
        self.frame += 1;
        self.stats = drawn.map_err(js_error)?;
        self.advance_svg(&view)?;
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            _ => {
                // The canvas changed under us: reconfigure and draw the next frame.
                self.surface.configure(device, &self.config);
                return scripted.and(posed);
            }
        };
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr-web present"),
        });
        encoder.copy_texture_to_texture(
            self.renderer.target().color.as_image_copy(),
            frame.texture.as_image_copy(),
            wgpu::Extent3d {
                width: size.0.min(self.config.width),
                height: size.1.min(self.config.height),
                depth_or_array_layers: 1,
            },
        );
        queue.submit(Some(encoder.finish()));
        queue.present(frame);
        // A script's failure shows once the frame is drawn (the model and view stay).
        scripted.and(posed)
    }

    /// Traces the hatching of the view as pen strokes for a plotter, as `npr render --svg`
    /// does: `page` is `a4`, `a3`, `letter` or `WxHmm`, `pen_mm` the pen width. The G-buffer
    /// is read back over the next frames; the SVG then arrives as a download
    /// ([`Viewer::take_actions`], kind `svg`). Fails with one line for an effect other than
    /// hatching, an unknown or too small page, or a pen width not above 0.
    pub fn save_svg(&mut self, file: &str, page: &str, pen_mm: f32) -> Result<(), JsValue> {
        self.state.can_save_svg().map_err(js_error)?;
        let page = npr_hatching::pen::Page {
            pen_mm,
            ..npr_hatching::pen::Page::named(page).map_err(js_error)?
        };
        page.validate().map_err(js_error)?;
        self.svg = Some(SvgRequest {
            file: file.to_string(),
            page,
            readback: None,
        });
        Ok(())
    }

    /// Resizes the canvas surface and the engine's target.
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), JsValue> {
        // A readback in flight holds the old size.
        self.svg = None;
        let (width, height) = (width.max(1), height.max(1));
        self.renderer
            .resize(&self.ctx.device, (width, height))
            .map_err(js_error)?;
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.ctx.device, &self.config);
        self.state.preset.output.width = width;
        self.state.preset.output.height = height;
        Ok(())
    }

    /// Switches the effect by its preset name (`phong`, `specular`, `hatching-pen`, ...).
    pub fn set_effect(&mut self, name: &str) -> Result<(), JsValue> {
        let effect =
            Effect::from_name(name).ok_or_else(|| js_error(format!("unknown effect `{name}`")))?;
        self.state.preset.effect = effect;
        Ok(())
    }

    /// The current effect's name.
    pub fn effect(&self) -> String {
        self.state.preset.effect.name().to_string()
    }

    /// Replaces the preset with `text` (TOML). A bad preset leaves the current one.
    pub fn load_preset(&mut self, text: &str, name: &str) -> Result<(), JsValue> {
        let mut preset = Preset::from_toml(text, Path::new(name)).map_err(js_error)?;
        let size = self.renderer.size();
        preset.output.width = size.0;
        preset.output.height = size.1;
        self.state = ViewerState::new(preset);
        self.renderer.reset_sequence();
        self.warp = WarpLive::default();
        Ok(())
    }

    /// The current preset as TOML (what `npr render --preset` reads): the view's size and
    /// the turntable's angle included.
    pub fn preset_toml(&self) -> Result<String, JsValue> {
        self.state
            .preset_for_render(self.renderer.size())
            .to_toml()
            .map_err(js_error)
    }

    /// Loads an `npr view --script` (the same format: `@FRAME COMMAND ARGS...`); frame 0
    /// is the next frame drawn. Input commands go through the shared viewer state, as in
    /// the window; `resize` resizes the canvas; `screenshot`, `save-preset`, `save-svg` (A4,
    /// 0.3 mm pen) and `report` become downloads ([`Viewer::take_actions`]); `exit` ends the script; `memory` and
    /// `load` need a file system and are refused with their line's message.
    pub fn load_script(&mut self, text: &str, name: &str) -> Result<(), JsValue> {
        let events = script::parse(text, Path::new(name)).map_err(js_error)?;
        if let Some(e) = events
            .iter()
            .find(|e| matches!(e.command, Command::Memory(_) | Command::Load(_)))
        {
            return Err(js_error(format!(
                "{name}: @{} {:?} needs a file system; the browser has none",
                e.frame, e.command
            )));
        }
        self.script = events;
        self.script_start = self.frame;
        self.script_pos = 0;
        Ok(())
    }

    /// Whether the loaded script has run to its end (true when there is none).
    pub fn script_done(&self) -> bool {
        self.script_pos >= self.script.len()
    }

    /// The downloads the script asked for since the last call, as a JSON array of
    /// `{"file", "kind", "text"}` (`kind`: `screenshot`, whose text is empty: the page
    /// saves its canvas; `preset`, TOML; `report`, JSON; `svg`, the pen plotter's SVG).
    pub fn take_actions(&mut self) -> String {
        serde_json::Value::from(std::mem::take(&mut self.actions)).to_string()
    }

    /// Every WGSL shader the passes create, composed as they compose it
    /// (`ShaderFile::full_source`), as a JSON array of `{"crate", "name", "source"}`:
    /// what the page's test hands to the browser's own compiler.
    pub fn shader_sources(&self) -> String {
        let crates = [
            ("npr-gpu", npr_gpu::shaders::ALL),
            ("npr-specular", npr_specular::shaders::ALL),
            ("npr-hatching", npr_hatching::shaders::ALL),
            ("npr-warp", npr_warp::shaders::ALL),
        ];
        let list: Vec<serde_json::Value> = crates
            .iter()
            .flat_map(|(krate, files)| {
                files.iter().map(move |f| {
                    serde_json::json!({ "crate": krate, "name": f.name, "source": f.full_source() })
                })
            })
            .collect();
        serde_json::Value::from(list).to_string()
    }

    /// Replaces the model with a file's bytes (OBJ, PLY, glTF, GLB by `name`'s extension).
    /// A bad file leaves the current model.
    pub fn load_model(&mut self, name: &str, bytes: &[u8]) -> Result<(), JsValue> {
        let model = Model::from_bytes(name, bytes).map_err(js_error)?;
        let timeline = npr_app::viewer::timeline::Timeline::new(&model);
        self.renderer
            .set_model(&self.ctx.device, model)
            .map_err(js_error)?;
        // A readback in flight traces against the model it was drawn from.
        self.svg = None;
        self.timeline = timeline;
        self.state.clip_time = self.state.preset.animation.time;
        self.state.selected = None;
        self.warp = WarpLive::default();
        Ok(())
    }

    /// The model's clips as a JSON array of names (empty for a model without clips).
    pub fn clip_names(&self) -> String {
        serde_json::Value::from(self.timeline.clip_names()).to_string()
    }

    /// Plays clip `name` (a name, an index, `none` for the bind pose, or empty for the
    /// first): the preset's `[animation] clip`. A clip the model lacks leaves the bind
    /// pose drawn; `stats_json`'s `clip_note` says why.
    pub fn set_clip(&mut self, name: &str) {
        self.state.preset.animation.clip = name.to_string();
    }

    /// Moves the clip to `seconds` (the scrub bar).
    pub fn set_clip_time(&mut self, seconds: f32) {
        if seconds.is_finite() {
            self.state.clip_time = seconds;
        }
    }

    /// The length of the clip playing, seconds (0 without one).
    pub fn clip_duration(&self) -> f32 {
        self.timeline.duration()
    }

    /// Plays or pauses the clip; returns whether it now plays.
    pub fn toggle_clip(&mut self) -> bool {
        self.state.clip_playing = !self.state.clip_playing;
        self.state.clip_playing
    }

    /// The model's name.
    pub fn model_name(&self) -> String {
        self.renderer.model().name.clone()
    }

    /// A mouse button went down at canvas pixel (`x`, `y`): `button` 0 left, 1 middle,
    /// 2 right (as `MouseEvent.button`).
    pub fn pointer_down(&mut self, x: f32, y: f32, button: u32, shift: bool, ctrl: bool) {
        let button = match (button, shift, ctrl) {
            (0, _, true) => Button::CtrlLeft,
            (0, true, false) => Button::ShiftLeft,
            (0, false, false) => Button::Left,
            _ => Button::Right,
        };
        self.input(Input::Press {
            at: Vec2::new(x, y),
            button,
        });
    }

    /// The mouse moved to canvas pixel (`x`, `y`).
    pub fn pointer_move(&mut self, x: f32, y: f32) {
        self.input(Input::Move {
            at: Vec2::new(x, y),
        });
    }

    /// The button went up at canvas pixel (`x`, `y`).
    pub fn pointer_up(&mut self, x: f32, y: f32) {
        self.input(Input::Release {
            at: Vec2::new(x, y),
        });
    }

    /// Wheel notches at canvas pixel (`x`, `y`) (positive: away from the user).
    pub fn wheel(&mut self, x: f32, y: f32, notches: f32) {
        self.input(Input::Scroll {
            at: Vec2::new(x, y),
            notches,
        });
    }

    /// A key by its name in `npr view` scripts (`1`–`7`, `t`, `r`, `escape`); false when
    /// the viewer does not answer it.
    pub fn key(&mut self, name: &str) -> bool {
        match Key::from_name(name) {
            Some(k) => {
                self.input(Input::Key(k));
                true
            }
            None => false,
        }
    }

    /// The highlights of the last frame as JSON: each one's id and the canvas pixel of its
    /// centre (`null` when off screen), for picking from a script or a test.
    pub fn highlights_json(&self) -> String {
        let size = self.renderer.size();
        let view = self.state.view(&self.renderer.model().framing, size);
        let list: Vec<serde_json::Value> = self
            .highlights()
            .iter()
            .map(|h| {
                let px = view.to_pixel(h.centre_world, size).map(|p| [p.x, p.y]);
                serde_json::json!({ "id": h.id, "pixel": px })
            })
            .collect();
        serde_json::Value::from(list).to_string()
    }

    /// The last frame's statistics and the time between the last two frames, as JSON.
    pub fn stats_json(&self) -> String {
        let mut value = serde_json::to_value(&self.stats).unwrap_or_default();
        if let Some(map) = value.as_object_mut() {
            map.insert("frame_ms".into(), self.frame_ms.into());
            map.insert("selected".into(), self.state.selected.into());
            map.insert("clip".into(), self.timeline.clip().into());
            map.insert("clip_time".into(), self.state.clip_time.into());
            map.insert("clip_note".into(), self.timeline.note().into());
        }
        value.to_string()
    }
}

impl Viewer {
    /// Moves a "save SVG" on: after the frame it was asked before, starts the readback of
    /// that frame's G-buffer; on a later frame, once the copies have reached the CPU, traces
    /// them and queues the download. A failure drops the request and shows its line.
    fn advance_svg(&mut self, view: &npr_app::view::View) -> Result<(), JsValue> {
        let Some(request) = &mut self.svg else {
            return Ok(());
        };
        let (device, queue) = (&self.ctx.device, &self.ctx.queue);
        let Some((readback, drawn, preset)) = &mut request.readback else {
            let started = self.renderer.start_pen_readback(device, queue);
            match started {
                Ok(Some(r)) => {
                    let preset = self.state.preset.clone();
                    request.readback = Some((r, *view, preset));
                    return Ok(());
                }
                Ok(None) => {
                    self.svg = None;
                    return Err(js_error("save SVG: no hatched frame was drawn"));
                }
                Err(e) => {
                    self.svg = None;
                    return Err(js_error(e));
                }
            }
        };
        let Some(contents) = readback.try_take() else {
            return Ok(());
        };
        let size = self.renderer.size();
        let page = request.page;
        let traced = contents.map_err(js_error).and_then(|c| {
            let pen = (page.pen_px(size), page.fit(size).0);
            let drawing = self
                .renderer
                .pen_drawing_from(&c, preset, drawn, pen)
                .map_err(js_error)?;
            npr_hatching::pen::to_svg(&drawing, &page).map_err(js_error)
        });
        let file = request.file.clone();
        self.svg = None;
        let text = traced?;
        self.actions
            .push(serde_json::json!({ "file": file, "kind": "svg", "text": text }));
        Ok(())
    }

    /// Runs the script's commands due at this frame. Input goes through the shared viewer
    /// state; the rest is the page's to do (or refused).
    fn run_script(&mut self) -> Result<(), JsValue> {
        while let Some(event) = self.script.get(self.script_pos) {
            if self.script_start + event.frame > self.frame {
                break;
            }
            let command = event.command.clone();
            self.script_pos += 1;
            let size = self.renderer.size();
            let view = self.state.view(&self.renderer.model().framing, size);
            let highlights = self.highlights();
            let shell = self
                .state
                .script(command, &view, size, &highlights)
                .map_err(js_error)?;
            let file = |p: &Path| {
                p.file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default()
            };
            match shell {
                Some(Command::Resize(w, h)) => self.resize(w, h)?,
                Some(Command::Screenshot(p)) => self.actions.push(
                    serde_json::json!({ "file": file(&p), "kind": "screenshot", "text": "" }),
                ),
                Some(Command::SavePreset(p)) => {
                    let text = self.preset_toml()?;
                    self.actions.push(
                        serde_json::json!({ "file": file(&p), "kind": "preset", "text": text }),
                    );
                }
                Some(Command::Report(p)) => {
                    let report = serde_json::json!({
                        "frame": self.frame,
                        "view_size": [size.0, size.1],
                        "effect": self.state.preset.effect.name(),
                        "model": self.renderer.model().name,
                        "highlights": highlights.len(),
                        "selected": self.state.selected_report(&view, size, &highlights),
                        "stats": self.stats,
                    });
                    self.actions.push(serde_json::json!({
                        "file": file(&p), "kind": "report", "text": report.to_string()
                    }));
                }
                Some(Command::SaveSvg(p)) => self.save_svg(&file(&p), "a4", 0.3)?,
                Some(Command::Exit) => self.script_pos = self.script.len(),
                Some(other) => {
                    return Err(js_error(format!(
                        "script: {other:?} is not available in the browser"
                    )));
                }
                None => {}
            }
        }
        Ok(())
    }

    /// The highlights of the last frame, for picking.
    fn highlights(&self) -> Vec<HighlightInfo> {
        self.renderer
            .highlight_set()
            .map(HighlightInfo::of_set)
            .unwrap_or_default()
    }

    /// One input event through the shared viewer state, as the window dispatches it.
    fn input(&mut self, input: Input) {
        let size = self.renderer.size();
        let view = self.state.view(&self.renderer.model().framing, size);
        let highlights = self.highlights();
        self.state.input(input, &view, size, &highlights);
    }
}

/// For the browser check's own build (`crates/npr-web/check`), which runs the compute
/// passes on this page's device: not exported to the page.
impl Viewer {
    /// The page's device and queue.
    pub fn gpu(&self) -> (&wgpu::Device, &wgpu::Queue) {
        (&self.ctx.device, &self.ctx.queue)
    }
}
