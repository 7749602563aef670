//! The desktop shell of `npr view`: the winit window, the egui panel and the frame loop
//! around the shared [`super::state::ViewerState`]. Native only.

use super::live::WarpLive;
use super::script::{self, Command, Event};
use super::state::{HighlightInfo, Input, ViewerState};
use super::ui;
use crate::engine::{FrameStats, Renderer};
use crate::model::Model;
use crate::preset::Preset;
use crate::{AppError, output};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

/// Arguments of `npr view`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ViewArgs {
    /// The model (OBJ, PLY, glTF); the built-in bunny when left out.
    pub model: Option<PathBuf>,
    /// A preset TOML to start from.
    #[arg(long)]
    pub preset: Option<PathBuf>,
    /// Initial window size WxH.
    #[arg(long, value_parser = crate::render::parse_size, default_value = "1200x800")]
    pub size: (u32, u32),
    /// On exit, write the 3-D view (without the panel) as PNG.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Close after this many frames.
    #[arg(long)]
    pub exit_after_frames: Option<u64>,
    /// A file of timed input events (see `npr_app::viewer::script`).
    #[arg(long)]
    pub script: Option<PathBuf>,
}

/// Whether a windowing system is reachable at all (checked before winit is asked, so
/// that a headless machine gets one clear line rather than a backend's panic).
pub fn display_available() -> bool {
    if cfg!(any(target_os = "windows", target_os = "macos")) {
        return true;
    }
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

fn no_display(detail: &str) -> AppError {
    AppError::NoDisplay(format!(
        "{detail}; `npr view` needs a window: use `npr render MODEL --out image.png` for images without one"
    ))
}

/// Runs `npr view` until the window closes.
///
/// # Errors
/// [`AppError::NoDisplay`] without a display; load, preset and script errors before the
/// window opens; GPU errors while it opens.
pub fn run(args: ViewArgs) -> Result<(), AppError> {
    if !display_available() {
        return Err(no_display(
            "no display (DISPLAY and WAYLAND_DISPLAY are unset)",
        ));
    }
    let preset = match &args.preset {
        Some(p) => Preset::load(p)?,
        None => Preset::default(),
    };
    let script = match &args.script {
        Some(p) => script::load(p)?,
        None => Vec::new(),
    };
    let model = match &args.model {
        Some(p) => Model::load(p)?,
        None => Model::bunny()?,
    };
    let event_loop = EventLoop::new().map_err(|e| no_display(&format!("no display ({e})")))?;
    let mut app = App {
        args,
        state: ViewerState::new(preset),
        model: Some(model),
        script,
        script_pos: 0,
        gfx: None,
        frame: 0,
        result: Ok(()),
        status: None,
        stats: FrameStats::default(),
        frame_ms: 0.0,
        last_frame: Instant::now(),
        pending_resize: None,
        debug: ui::Debug::default(),
        debug_texture: None,
        warp: WarpLive::default(),
        timeline: super::timeline::Timeline::default(),
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| no_display(&format!("the event loop failed ({e})")))?;
    app.result
}

/// Everything that needs the window.
struct Gfx {
    window: Arc<Window>,
    ctx: npr_gpu::GpuContext,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    renderer: Renderer,
    view_texture: egui::TextureId,
    /// Size of the 3-D view in physical pixels (0 when minimised).
    view_size: (u32, u32),
    highlights: Vec<HighlightInfo>,
    /// The last frame's submission: the next frame waits for it before it submits its
    /// own, so that at most two frames are queued on the GPU (see [`Self::throttle`]).
    in_flight: Option<wgpu::SubmissionIndex>,
}

struct App {
    args: ViewArgs,
    state: ViewerState,
    model: Option<Model>,
    script: Vec<Event>,
    script_pos: usize,
    gfx: Option<Gfx>,
    frame: u64,
    result: Result<(), AppError>,
    status: Option<String>,
    stats: FrameStats,
    frame_ms: f64,
    last_frame: Instant,
    pending_resize: Option<(u32, u32)>,
    debug: ui::Debug,
    debug_texture: Option<egui::TextureHandle>,
    warp: WarpLive,
    timeline: super::timeline::Timeline,
}

/// Writes `value` as pretty JSON, atomically.
fn write_json(path: &std::path::Path, value: &serde_json::Value) -> Result<(), AppError> {
    let text = serde_json::to_string_pretty(value).map_err(|e| AppError::Encode {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    output::write_atomic(path, text.as_bytes())
}

impl Gfx {
    /// Waits for the frame before `submitted` to finish on the GPU. Without it, a window
    /// whose presentation does not block (a software rasterizer, a compositor that never
    /// throttles) queues frames as fast as the CPU records them, and every queued frame
    /// keeps its command buffers and the objects it dropped alive; the driver's pools grow
    /// to the deepest queue they ever saw and keep that memory.
    fn throttle(&mut self, submitted: wgpu::SubmissionIndex) {
        if let Some(previous) = self.in_flight.replace(submitted) {
            let _ = self.ctx.device.poll(wgpu::PollType::Wait {
                submission_index: Some(previous),
                timeout: None,
            });
        }
    }
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: AppError) {
        self.result = Err(e);
        event_loop.exit();
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<Gfx, AppError> {
        let (w, h) = self.args.size;
        let attrs = Window::default_attributes()
            .with_title("npr view")
            .with_inner_size(winit::dpi::PhysicalSize::new(w, h));
        let window = Arc::new(
            event_loop
                .create_window(attrs)
                .map_err(|e| no_display(&format!("cannot open a window ({e})")))?,
        );
        let descriptor = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(
            event_loop.owned_display_handle(),
        ));
        let target = window.clone();
        let (ctx, surface) =
            npr_gpu::GpuContext::for_surface(descriptor, move |i| i.create_surface(target))?;
        let caps = surface.get_capabilities(&ctx.adapter);
        // egui blends in gamma space and prefers a non-sRGB target.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| !f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| AppError::Gpu(npr_gpu::GpuError::Surface("no surface format".into())))?;
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        if size.width > 0 && size.height > 0 {
            surface.configure(&ctx.device, &config);
        }
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(ctx.device.limits().max_texture_dimension_2d as usize),
        );
        let mut egui_renderer =
            egui_wgpu::Renderer::new(&ctx.device, format, egui_wgpu::RendererOptions::default());
        let model = match self.model.take() {
            Some(m) => m,
            None => Model::bunny()?,
        };
        self.timeline = super::timeline::Timeline::new(&model);
        let renderer = Renderer::new(&ctx, model, (64, 64))?;
        let view_texture = egui_renderer.register_native_texture(
            &ctx.device,
            &renderer.target().color_view,
            wgpu::FilterMode::Nearest,
        );
        Ok(Gfx {
            window,
            ctx,
            surface,
            config,
            egui_ctx,
            egui_state,
            egui_renderer,
            renderer,
            view_texture,
            view_size: (64, 64),
            highlights: Vec::new(),
            in_flight: None,
        })
    }

    /// Resizes the window surface; 0×0 (minimised) only stops drawing.
    fn resize_surface(gfx: &mut Gfx, size: (u32, u32)) {
        if size.0 > 0 && size.1 > 0 {
            gfx.config.width = size.0;
            gfx.config.height = size.1;
            gfx.surface.configure(&gfx.ctx.device, &gfx.config);
        }
    }

    fn load_model(&mut self, path: &std::path::Path) {
        let Some(gfx) = &mut self.gfx else { return };
        let loaded = Model::load(path).and_then(|m| {
            let timeline = super::timeline::Timeline::new(&m);
            gfx.renderer.set_model(&gfx.ctx.device, m)?;
            Ok(timeline)
        });
        match loaded {
            Ok(timeline) => {
                self.timeline = timeline;
                self.state.clip_time = self.state.preset.animation.time;
                self.state.selected = None;
                self.status = Some(format!("opened {}", path.display()));
            }
            // The current model stays loaded; the panel shows why the new one did not.
            Err(e) => self.status = Some(format!("error: {e}")),
        }
    }

    /// Runs the script's events due at this frame.
    fn run_script(&mut self, event_loop: &ActiveEventLoop) {
        while let Some(ev) = self.script.get(self.script_pos).cloned() {
            if ev.frame > self.frame {
                break;
            }
            self.script_pos += 1;
            if let Err(e) = self.script_command(event_loop, ev.command) {
                self.fail(event_loop, e);
                return;
            }
        }
    }

    fn dispatch(&mut self, input: Input) {
        let Some(gfx) = &self.gfx else { return };
        let view = self
            .state
            .view(&gfx.renderer.model().framing, gfx.view_size);
        self.state
            .input(input, &view, gfx.view_size, &gfx.highlights);
    }

    fn script_command(&mut self, event_loop: &ActiveEventLoop, c: Command) -> Result<(), AppError> {
        let command = match &self.gfx {
            Some(gfx) => {
                let view = self
                    .state
                    .view(&gfx.renderer.model().framing, gfx.view_size);
                self.state
                    .script(c, &view, gfx.view_size, &gfx.highlights)?
            }
            None => Some(c),
        };
        let Some(command) = command else {
            return Ok(());
        };
        match command {
            Command::Resize(w, h) => {
                if let Some(gfx) = &mut self.gfx {
                    // The window system applies the request (it cannot make a real 0×0
                    // window); the size is also handed to the same handler a
                    // minimise reaches, so 0×0 is exercised.
                    let _ = gfx
                        .window
                        .request_inner_size(winit::dpi::PhysicalSize::new(w.max(1), h.max(1)));
                    Self::resize_surface(gfx, (w, h));
                    self.pending_resize = Some((w, h));
                }
            }
            Command::Screenshot(p) => self.screenshot(&p)?,
            Command::SaveSvg(p) => self.save_svg(&p)?,
            Command::SavePreset(p) => self.save_preset(&p)?,
            Command::Report(p) => self.report(&p)?,
            Command::Memory(p) => self.memory(&p)?,
            Command::Load(p) => self.load_model(&p),
            Command::Exit => event_loop.exit(),
            // Input: [`ViewerState::script`] ran it (or there is no window yet).
            _ => {}
        }
        Ok(())
    }

    /// Writes the hatching of the view as pen strokes on an A4 page (see `npr render
    /// --svg`).
    fn save_svg(&self, path: &std::path::Path) -> Result<(), AppError> {
        let Some(gfx) = &self.gfx else { return Ok(()) };
        self.state.can_save_svg()?;
        let preset = &self.state.preset;
        let page = npr_hatching::pen::Page::default();
        let size = gfx.view_size;
        let view = self.state.view(&gfx.renderer.model().framing, size);
        let drawing = gfx
            .renderer
            .pen_drawing(
                &gfx.ctx.device,
                &gfx.ctx.queue,
                preset,
                &view,
                (page.pen_px(size), page.fit(size).0),
            )?
            .unwrap_or_default();
        let svg = npr_hatching::pen::to_svg(&drawing, &page)?;
        output::write_atomic(path, svg.as_bytes())
    }

    fn screenshot(&self, path: &std::path::Path) -> Result<(), AppError> {
        let Some(gfx) = &self.gfx else { return Ok(()) };
        let img = gfx.renderer.read(&gfx.ctx.device, &gfx.ctx.queue)?;
        output::save_png(path, &img)
    }

    /// The preset as `npr render` needs it to draw this view: the current parameters, the
    /// view's size, and the turntable's angle folded into the model turn.
    fn preset_for_render(&self) -> Preset {
        match &self.gfx {
            Some(gfx) => self.state.preset_for_render(gfx.view_size),
            None => self.state.preset_for_render((
                self.state.preset.output.width,
                self.state.preset.output.height,
            )),
        }
    }

    fn save_preset(&self, path: &std::path::Path) -> Result<(), AppError> {
        self.preset_for_render().save(path)
    }

    /// Writes a [`crate::memory::MemoryReading`] (after the device has finished its work)
    /// with the frame number.
    fn memory(&self, path: &std::path::Path) -> Result<(), AppError> {
        let Some(gfx) = &self.gfx else { return Ok(()) };
        let reading = crate::memory::MemoryReading::take(&gfx.ctx.instance, &gfx.ctx.device);
        let report = serde_json::json!({
            "frame": self.frame,
            "heap_bytes": reading.heap_bytes,
            "resident_bytes": reading.resident_bytes,
            "gpu_objects": reading.gpu_objects,
        });
        write_json(path, &report)
    }

    fn report(&self, path: &std::path::Path) -> Result<(), AppError> {
        let Some(gfx) = &self.gfx else { return Ok(()) };
        let view = self
            .state
            .view(&gfx.renderer.model().framing, gfx.view_size);
        let report = serde_json::json!({
            "frame": self.frame,
            "view_size": [gfx.view_size.0, gfx.view_size.1],
            "effect": self.state.preset.effect.name(),
            "model": gfx.renderer.model().name,
            "status": self.status,
            "clip": self.timeline.clip(),
            "clip_time": self.state.clip_time,
            "clip_playing": self.state.clip_playing,
            "clip_note": self.timeline.note(),
            "highlights": gfx.highlights.len(),
            "selected": self.state.selected_report(&view, gfx.view_size, &gfx.highlights),
            "stats": self.stats,
        });
        write_json(path, &report)
    }

    /// Draws egui's output over the window's next surface texture and presents it (a
    /// surface that changed under us is reconfigured, and the frame is skipped).
    fn present(gfx: &mut Gfx, full: egui::FullOutput) {
        let frame = match gfx.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                // The surface changed under us (resize, compositor restart): reconfigure
                // and draw the next frame.
                let size = gfx.window.inner_size();
                Self::resize_surface(gfx, (size.width, size.height));
                return;
            }
            _ => return,
        };
        let target = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [gfx.config.width, gfx.config.height],
            pixels_per_point: full.pixels_per_point,
        };
        let jobs = gfx.egui_ctx.tessellate(full.shapes, full.pixels_per_point);
        for (id, deltas) in &full.textures_delta.set {
            for delta in deltas {
                gfx.egui_renderer
                    .update_texture(&gfx.ctx.device, &gfx.ctx.queue, *id, delta);
            }
        }
        let mut encoder = gfx
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("npr view egui"),
            });
        let extra = gfx.egui_renderer.update_buffers(
            &gfx.ctx.device,
            &gfx.ctx.queue,
            &mut encoder,
            &jobs,
            &screen,
        );
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("npr view egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            gfx.egui_renderer
                .render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        let submitted = gfx
            .ctx
            .queue
            .submit(extra.into_iter().chain(Some(encoder.finish())));
        gfx.throttle(submitted);
        gfx.window.pre_present_notify();
        gfx.ctx.queue.present(frame);
        for id in &full.textures_delta.free {
            gfx.egui_renderer.free_texture(id);
        }
    }

    /// Refreshes the tone or bins debug picture from the hatching G-buffer when that view
    /// is on.
    fn update_debug_texture(
        gfx: &mut Gfx,
        state: &ViewerState,
        debug: &ui::Debug,
        debug_texture: &mut Option<egui::TextureHandle>,
    ) {
        if matches!(debug.image, ui::DebugImage::Tone | ui::DebugImage::Bins)
            && state.preset.effect.is_hatching()
            && let Ok(Some(inputs)) = gfx.renderer.hatch_inputs(&gfx.ctx.device, &gfx.ctx.queue)
        {
            let image = ui::gbuffer_image(
                &inputs,
                state.preset.hatching.bins,
                debug.image == ui::DebugImage::Bins,
            );
            match debug_texture {
                Some(t) => t.set(image, egui::TextureOptions::NEAREST),
                None => {
                    *debug_texture = Some(gfx.egui_ctx.load_texture(
                        "npr-debug",
                        image,
                        egui::TextureOptions::NEAREST,
                    ));
                }
            }
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<(), AppError> {
        self.run_script(event_loop);
        if self.result.is_err() {
            return Ok(());
        }
        let now = Instant::now();
        self.frame_ms = now.duration_since(self.last_frame).as_secs_f64() * 1e3;
        self.last_frame = now;
        let Some(gfx) = &mut self.gfx else {
            return Ok(());
        };
        if let Some((w, h)) = self.pending_resize.take()
            && (w == 0 || h == 0)
        {
            // Minimised: skip the frame, but count it.
            self.frame += 1;
            return Ok(());
        }
        let win = gfx.window.inner_size();
        if win.width == 0 || win.height == 0 {
            self.frame += 1;
            return Ok(());
        }

        // UI: the panel edits the preset, the central image is the 3-D view.
        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let mut inputs = Vec::new();
        let mut view_px = gfx.view_size;
        let mut ui_actions = ui::Actions::default();
        if self.debug.directions {
            gfx.renderer
                .directions(crate::preset::DirectionPreset::KMax);
        }
        if self.debug.image == ui::DebugImage::Curvature {
            gfx.renderer.mean_curvature();
        }
        let debug_texture = self.debug_texture.as_ref().map(egui::TextureHandle::id);
        let full = gfx.egui_ctx.run_ui(raw, |ui| {
            ui_actions = ui::panel(
                ui,
                &mut self.state,
                &mut self.debug,
                &self.stats,
                &self.warp,
                self.frame_ms,
                gfx.renderer.model(),
                &self.timeline,
                self.status.as_deref(),
            );
            view_px = ui::central(
                ui,
                gfx.view_texture,
                gfx.view_size,
                &mut inputs,
                &self.debug,
                &self.state,
                &gfx.highlights,
                &gfx.renderer,
                debug_texture,
            );
        });
        gfx.egui_state
            .handle_platform_output(&gfx.window, full.platform_output.clone());
        if view_px != gfx.view_size && view_px.0 > 0 && view_px.1 > 0 {
            gfx.renderer.resize(&gfx.ctx.device, view_px)?;
            gfx.egui_renderer.update_egui_texture_from_wgpu_texture(
                &gfx.ctx.device,
                &gfx.renderer.target().color_view,
                wgpu::FilterMode::Nearest,
                gfx.view_texture,
            );
            gfx.view_size = view_px;
        }
        for input in inputs {
            self.dispatch(input);
        }
        self.handle_actions(ui_actions)?;
        let Some(gfx) = &mut self.gfx else {
            return Ok(());
        };

        // The 3-D view.
        self.state.tick();
        if let Err(e) = self.timeline.update(
            &mut gfx.renderer,
            (&gfx.ctx.device, &gfx.ctx.queue),
            &self.state,
        ) {
            self.status = Some(format!("error: {e}"));
        }
        let view = self
            .state
            .view(&gfx.renderer.model().framing, gfx.view_size);
        let result = self
            .warp
            .draw(&mut gfx.renderer, &gfx.ctx, &self.state, &view, self.frame);
        match result {
            Ok(stats) => self.stats = stats,
            Err(e) => self.status = Some(format!("error: {e}")),
        }
        Self::update_debug_texture(gfx, &self.state, &self.debug, &mut self.debug_texture);
        gfx.highlights = gfx
            .renderer
            .highlight_set()
            .filter(|_| self.state.preset.effect == crate::preset::Effect::Specular)
            .map(HighlightInfo::of_set)
            .unwrap_or_default();

        // egui over the window.
        Self::present(gfx, full);
        self.frame += 1;
        if self.args.exit_after_frames.is_some_and(|n| self.frame >= n) {
            event_loop.exit();
        }
        Ok(())
    }

    fn handle_actions(&mut self, a: ui::Actions) -> Result<(), AppError> {
        if let Some(p) = a.open_model {
            self.load_model(&p);
        }
        if let Some(p) = a.save_preset {
            match self.save_preset(&p) {
                Ok(()) => self.status = Some(format!("saved {}", p.display())),
                Err(e) => self.status = Some(format!("error: {e}")),
            }
        }
        if let Some(p) = a.load_preset {
            match Preset::load(&p) {
                Ok(preset) => {
                    self.state.preset = preset;
                    self.status = Some(format!("loaded {}", p.display()));
                }
                Err(e) => self.status = Some(format!("error: {e}")),
            }
        }
        if let Some(p) = a.save_svg {
            match self.save_svg(&p) {
                Ok(()) => self.status = Some(format!("wrote {}", p.display())),
                Err(e) => self.status = Some(format!("error: {e}")),
            }
        }
        if let Some(p) = a.screenshot {
            match self.screenshot(&p) {
                Ok(()) => self.status = Some(format!("wrote {}", p.display())),
                Err(e) => self.status = Some(format!("error: {e}")),
            }
        }
        if a.reset_sequence
            && let Some(gfx) = &mut self.gfx
        {
            gfx.renderer.reset_sequence();
        }
        Ok(())
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(gfx) => {
                gfx.window.request_redraw();
                self.gfx = Some(gfx);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gfx) = &mut self.gfx else { return };
        let _ = gfx.egui_state.on_window_event(&gfx.window, &event);
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => Self::resize_surface(gfx, (size.width, size.height)),
            WindowEvent::DroppedFile(path) => self.load_model(&path),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(gfx) = &self.gfx {
            gfx.window.request_redraw();
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        if self.result.is_err() {
            return;
        }
        if let Some(path) = self.args.screenshot.clone()
            && let Err(e) = self.screenshot(&path)
        {
            self.result = Err(e);
        }
    }
}
