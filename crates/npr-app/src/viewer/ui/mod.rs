//! The viewer's egui side: the panel (every preset field, files, heads-up line) and the
//! central 3-D view (mouse and keys turned into [`Input`], debug overlays).

mod clip;

use super::state::{Button, HighlightInfo, Input, Key, ViewerState};
use crate::engine::{FrameStats, Renderer};
use crate::model::Model;
use crate::preset::{
    BaseModel, BlendPreset, BoundaryPreset, DirectionPreset, Effect, Preset, UpPreset,
};
use egui::{Color32, Pos2, Sense, Stroke};
use glam::{Vec2, Vec3};
use std::path::PathBuf;

/// What the 3-D view shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DebugImage {
    /// The effect.
    #[default]
    Shaded,
    /// Mean curvature as colour (blue concave, white flat, red convex).
    Curvature,
    /// The hatching G-buffer's tone.
    Tone,
    /// The hatching G-buffer's stroke direction, one colour per direction bin (Eq. (1)).
    Bins,
}

/// Debug views of the 3-D view.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Debug {
    /// What the view shows.
    pub image: DebugImage,
    /// The highlight frusta (projector footprints and axes).
    pub frusta: bool,
    /// Principal directions (e_max) as a line field.
    pub directions: bool,
}

/// A colour per direction bin (`bins` of them), for the bins debug view.
pub fn bin_colour(bin: usize, bins: usize) -> [u8; 3] {
    let h = bin as f32 / bins.max(1) as f32 * 6.0;
    let x = 1.0 - ((h % 2.0) - 1.0).abs();
    let (r, g, b) = match h as u32 {
        0 => (1.0, x, 0.0),
        1 => (x, 1.0, 0.0),
        2 => (0.0, 1.0, x),
        3 => (0.0, x, 1.0),
        4 => (x, 0.0, 1.0),
        _ => (1.0, 0.0, x),
    };
    [
        (r * 230.0) as u8 + 20,
        (g * 230.0) as u8 + 20,
        (b * 230.0) as u8 + 20,
    ]
}

/// The G-buffer as a debug image: tone as grey, or the direction bin as colour
/// (background pixels, tone ≥ 1 with no stroke, stay white).
pub fn gbuffer_image(
    inputs: &npr_hatching::HatchInputs,
    bins: u32,
    show_bins: bool,
) -> egui::ColorImage {
    let (w, h) = (inputs.width() as usize, inputs.height() as usize);
    let pixels = inputs
        .tone()
        .iter()
        .zip(inputs.theta())
        .map(|(&t, &theta)| {
            if show_bins {
                let n = bins.max(1) as usize;
                // The bin the hatching pass reads (nearest, not floor).
                let b = npr_hatching::nearest_bin(theta, bins) as usize % n;
                let [r, g, bl] = bin_colour(b, n);
                let k = t.clamp(0.0, 1.0) * 0.5 + 0.5;
                Color32::from_rgb(
                    (f32::from(r) * k) as u8,
                    (f32::from(g) * k) as u8,
                    (f32::from(bl) * k) as u8,
                )
            } else {
                let g = (t.clamp(0.0, 1.0) * 255.0) as u8;
                Color32::from_gray(g)
            }
        })
        .collect();
    egui::ColorImage::new([w, h], pixels)
}

/// Mean curvature → colour: blue (concave) through white to red (convex).
fn curvature_colour(h: f32) -> Color32 {
    let t = (h / 3.0).clamp(-1.0, 1.0);
    let c = |a: f32| (a.clamp(0.0, 1.0) * 255.0) as u8;
    if t >= 0.0 {
        Color32::from_rgb(255, c(1.0 - t), c(1.0 - t))
    } else {
        Color32::from_rgb(c(1.0 + t), c(1.0 + t), 255)
    }
}

/// File actions asked for in the panel this frame.
#[derive(Clone, Debug, Default)]
pub struct Actions {
    /// Open this model.
    pub open_model: Option<PathBuf>,
    /// Save the preset here.
    pub save_preset: Option<PathBuf>,
    /// Load a preset from here.
    pub load_preset: Option<PathBuf>,
    /// Write a screenshot here.
    pub screenshot: Option<PathBuf>,
    /// Write the hatching as an SVG for pen plotters here.
    pub save_svg: Option<PathBuf>,
    /// Restart highlight tracking.
    pub reset_sequence: bool,
}

fn path_field(ui: &mut egui::Ui, id: &str, label: &str) -> Option<PathBuf> {
    let key = egui::Id::unique(("npr-path", id));
    let mut text: String = ui.data_mut(|d| d.get_temp::<String>(key).unwrap_or_default());
    let mut go = false;
    ui.horizontal(|ui| {
        let r = ui.add(egui::TextEdit::singleline(&mut text).desired_width(170.0));
        go = ui.button(label).clicked()
            || (r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)));
    });
    ui.data_mut(|d| d.insert_temp(key, text.clone()));
    (go && !text.trim().is_empty()).then(|| PathBuf::from(text.trim()))
}

fn rgb(ui: &mut egui::Ui, label: &str, c: &mut [f32; 3]) {
    ui.horizontal(|ui| {
        ui.label(label);
        ui.color_edit_button_rgb(c);
    });
}

/// The side panel. Returns the file actions asked for.
#[allow(clippy::too_many_arguments)]
pub fn panel(
    ui: &mut egui::Ui,
    state: &mut ViewerState,
    debug: &mut Debug,
    stats: &FrameStats,
    warp: &super::live::WarpLive,
    frame_ms: f64,
    model: &Model,
    timeline: &super::timeline::Timeline,
    status: Option<&str>,
) -> Actions {
    let mut actions = Actions::default();
    egui::Panel::right("npr-panel")
        .resizable(true)
        .default_size(300.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                model_header(ui, model, status);
                ui.separator();
                effect_row(ui, state);
                clip::timeline_section(ui, state, timeline);
                let selected = state.selected;
                let p = &mut state.preset;
                camera_light_section(ui, p);
                base_shading_section(ui, p);
                specular_section(ui, p, selected, &mut actions);
                hatching_section(ui, p);
                warp_section(ui, p);
                outlines_section(ui, p);
                debug_views_section(ui, p.effect, debug);
                ui.separator();
                file_actions(ui, &mut actions);
                ui.separator();
                frame_lines(ui, state, stats, warp, frame_ms);
            });
        });
    actions
}

/// The model's name, size and notes, and the last status line (red for an error).
fn model_header(ui: &mut egui::Ui, model: &Model, status: Option<&str>) {
    ui.heading(&model.name);
    ui.label(format!(
        "{} triangles, {} vertices",
        model.mesh.triangle_count(),
        model.mesh.vertex_count()
    ));
    for note in &model.notes {
        ui.small(note);
    }
    if let Some(s) = status {
        let color = if s.starts_with("error") {
            Color32::from_rgb(220, 60, 60)
        } else {
            Color32::GRAY
        };
        ui.colored_label(color, s);
    }
    ui.separator();
}

/// The effect menu, the turntable switch and the view reset.
fn effect_row(ui: &mut egui::Ui, state: &mut ViewerState) {
    let p = &mut state.preset;
    egui::ComboBox::from_label("effect")
        .selected_text(p.effect.name())
        .show_ui(ui, |ui| {
            for e in Effect::ALL {
                ui.selectable_value(&mut p.effect, e, e.name());
            }
        });
    ui.horizontal(|ui| {
        ui.checkbox(&mut state.turntable, "turntable (T)");
        if ui.button("reset view (R)").clicked() {
            p.camera = state.initial.camera;
            p.light = state.initial.light;
            p.turn_deg = state.initial.turn_deg;
            state.turntable_deg = 0.0;
        }
    });
}

/// The panel's section on camera and light: the orbit camera and the light direction.
fn camera_light_section(ui: &mut egui::Ui, p: &mut Preset) {
    egui::CollapsingHeader::new("camera and light").show(ui, |ui| {
        ui.add(egui::Slider::new(&mut p.camera.yaw_deg, -180.0..=180.0).text("yaw"));
        ui.add(egui::Slider::new(&mut p.camera.pitch_deg, -85.0..=85.0).text("pitch"));
        ui.add(
            egui::Slider::new(&mut p.camera.distance, 1.05..=20.0)
                .logarithmic(true)
                .text("distance"),
        );
        ui.add(egui::Slider::new(&mut p.camera.fov_deg, 10.0..=90.0).text("fov"));
        let d = Vec3::from(p.light.direction).normalize_or(Vec3::Y);
        let (mut yaw, mut pitch) = (d.x.atan2(d.z).to_degrees(), d.y.asin().to_degrees());
        let a = ui.add(egui::Slider::new(&mut yaw, -180.0..=180.0).text("light yaw"));
        let b = ui.add(egui::Slider::new(&mut pitch, -89.0..=89.0).text("light pitch"));
        if a.changed() || b.changed() {
            let (y, q) = (yaw.to_radians(), pitch.to_radians());
            p.light.direction = [y.sin() * q.cos(), q.sin(), y.cos() * q.cos()];
        }
        ui.small("Ctrl-drag in the view also moves the light.");
    });
}

/// The panel's section on base shading: model, material, cel bands.
fn base_shading_section(ui: &mut egui::Ui, p: &mut Preset) {
    egui::CollapsingHeader::new("base shading")
        .default_open(true)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                for (m, n) in [
                    (BaseModel::Phong, "Phong"),
                    (BaseModel::Gouraud, "Gouraud"),
                    (BaseModel::Cel, "cel"),
                ] {
                    ui.radio_value(&mut p.base.model, m, n);
                }
            });
            rgb(ui, "diffuse", &mut p.base.diffuse);
            rgb(ui, "background", &mut p.base.background);
            ui.add(egui::Slider::new(&mut p.base.ks, 0.0..=1.0).text("k_s"));
            ui.add(
                egui::Slider::new(&mut p.base.shininess, 1.0..=256.0)
                    .logarithmic(true)
                    .text("shininess"),
            );
            let mut bands = p.base.cel_bands.len();
            if ui
                .add(egui::Slider::new(&mut bands, 2..=6).text("cel bands"))
                .changed()
            {
                p.base.cel_bands = (0..bands)
                    .map(|i| (70 + 185 * i / (bands - 1).max(1)) as u8)
                    .collect();
            }
        });
}

/// The panel's section on the highlights (Lee & Choi): projector controls and the selected highlight's edit.
fn specular_section(
    ui: &mut egui::Ui,
    p: &mut Preset,
    selected: Option<u64>,
    actions: &mut Actions,
) {
    egui::CollapsingHeader::new("specular (Lee & Choi)")
    .default_open(p.effect == Effect::Specular)
    .show(ui, |ui| {
        ui.add(egui::Slider::new(&mut p.specular.sigma, 0.5..=0.99).text("σ"));
        egui::ComboBox::from_label("shape")
            .selected_text(p.specular.shape.clone())
            .show_ui(ui, |ui| {
                for s in npr_specular::HighlightShape::ALL {
                    ui.selectable_value(&mut p.specular.shape, s.name().to_string(), s.name());
                }
            });
        if let Some(png) = path_field(ui, "shape", "use PNG") {
            p.specular.shape = png.display().to_string();
        }
        ui.horizontal(|ui| {
            ui.label("up");
            ui.radio_value(&mut p.specular.up, UpPreset::EMin, "e_min");
            ui.radio_value(&mut p.specular.up, UpPreset::EMax, "e_max");
        });
        ui.add(
            egui::Slider::new(&mut p.specular.smoothing_edges, 1.0..=12.0)
                .text("curvature smoothing (edges)"),
        );
        ui.add(
            egui::Slider::new(&mut p.specular.abstraction, 0.0..=crate::preset::MAX_ABSTRACTION)
                .text("abstraction (× radius)"),
        );
        ui.horizontal(|ui| {
            ui.label("edges");
            ui.radio_value(&mut p.specular.boundary, BoundaryPreset::Smooth, "smooth");
            ui.radio_value(&mut p.specular.boundary, BoundaryPreset::PerFace, "per face");
        });
        ui.add(egui::Slider::new(&mut p.specular.base_ks, 0.0..=1.0).text("base k_s"));
        if let Some(id) = selected {
            ui.label(format!("selected highlight #{id}"));
            if let Some(e) = p.specular.edits.iter_mut().find(|e| e.id == id) {
                ui.add(egui::Slider::new(&mut e.rotate_deg, -180.0..=180.0).text("rotate"));
                ui.add(egui::Slider::new(&mut e.scale[0], 0.05..=10.0).logarithmic(true).text("scale e_max"));
                ui.add(egui::Slider::new(&mut e.scale[1], 0.05..=10.0).logarithmic(true).text("scale e_min"));
            }
        } else {
            ui.small("Click a highlight to pick it; drag moves it, Shift-drag turns it, the wheel scales it.");
        }
        if !p.specular.edits.is_empty() && ui.button("clear edits").clicked() {
            p.specular.edits.clear();
        }
        if ui.button("restart tracking").clicked() {
            actions.reset_sequence = true;
        }
    });
}

/// The panel's section on hatching (Kim & Lee): map, bins, blending, shadows, stroke space and directions.
fn hatching_section(ui: &mut egui::Ui, p: &mut Preset) {
    egui::CollapsingHeader::new("hatching (Kim & Lee)")
        .default_open(p.effect.is_hatching())
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.radio_value(&mut p.effect, Effect::HatchingPen, "pen");
                ui.radio_value(&mut p.effect, Effect::HatchingPencil, "pencil");
            });
            ui.add(
                egui::Slider::new(
                    &mut p.hatching.bins,
                    npr_hatching::MIN_BINS..=npr_hatching::MAX_BINS,
                )
                .text("bins"),
            );
            ui.add(
                egui::Slider::new(&mut p.hatching.stroke_scale, 0.25..=4.0)
                    .logarithmic(true)
                    .text("stroke scale"),
            );
            ui.horizontal(|ui| {
                ui.radio_value(&mut p.hatching.blend, BlendPreset::CutAndPaste, "cut");
                ui.radio_value(&mut p.hatching.blend, BlendPreset::Blended, "blended");
                ui.radio_value(&mut p.hatching.blend, BlendPreset::Offset, "offset");
            });
            ui.checkbox(&mut p.hatching.shadows, "shadows");
            ui.horizontal(|ui| {
                ui.label("strokes");
                ui.radio_value(
                    &mut p.hatching.space,
                    crate::preset::SpacePreset::Surface,
                    "move with the surface",
                );
                ui.radio_value(
                    &mut p.hatching.space,
                    crate::preset::SpacePreset::Screen,
                    "screen (paper)",
                );
            });
            ui.horizontal(|ui| {
                ui.label("direction");
                ui.radio_value(&mut p.hatching.direction, DirectionPreset::Smooth, "smooth");
                ui.radio_value(
                    &mut p.hatching.direction,
                    DirectionPreset::SmoothCurvatureOnly,
                    "smooth, no crease/flat rule",
                );
                ui.radio_value(
                    &mut p.hatching.direction,
                    DirectionPreset::KMax,
                    "raw k_max",
                );
                ui.radio_value(
                    &mut p.hatching.direction,
                    DirectionPreset::KMin,
                    "raw k_min",
                );
            });
        });
}

/// The panel's section on warping (Park & Ihm): interval, proxy, path, antialiasing.
fn warp_section(ui: &mut egui::Ui, p: &mut Preset) {
    egui::CollapsingHeader::new("warp (Park & Ihm)")
    .default_open(p.effect == Effect::Warp)
    .show(ui, |ui| {
        ui.add(egui::Slider::new(&mut p.warp.k, 1..=30).text("k"));
        ui.add(
            egui::Slider::new(&mut p.warp.proxy_ratio, 0.001..=1.0)
                .logarithmic(true)
                .text("proxy ratio"),
        );
        ui.horizontal(|ui| {
            ui.radio_value(&mut p.warp.mode, crate::preset::WarpMode::Ours, "ours");
            ui.radio_value(&mut p.warp.mode, crate::preset::WarpMode::Paper, "paper's path");
        });
        ui.add_enabled(
            p.warp.mode == crate::preset::WarpMode::Ours,
            egui::Checkbox::new(&mut p.warp.depth_test, "reference depth test"),
        );
        ui.horizontal(|ui| {
            use crate::preset::WarpAntialiasing as Aa;
            ui.label("antialiasing");
            ui.radio_value(&mut p.warp.antialiasing, Aa::None, "none");
            ui.radio_value(&mut p.warp.antialiasing, Aa::Msaa4, "msaa4");
            ui.radio_value(&mut p.warp.antialiasing, Aa::Msaa4Blend, "msaa4-blend");
        });
        ui.small("References every k frames, at the camera predicted k frames ahead; turn the turntable on to see warping. Full frames (and the full render the PSNR compares with) use the warp's antialiasing.");
    });
}

/// The panel's section on outlines: on/off, width, crease angle, colour.
fn outlines_section(ui: &mut egui::Ui, p: &mut Preset) {
    egui::CollapsingHeader::new("outlines").show(ui, |ui| {
        ui.checkbox(&mut p.outline.enabled, "silhouettes and creases");
        ui.add(egui::Slider::new(&mut p.outline.width_px, 1.0..=15.0).text("width (px)"));
        ui.add(egui::Slider::new(&mut p.outline.crease_deg, 1.0..=179.0).text("crease angle"));
        rgb(ui, "colour", &mut p.outline.color);
    });
}

/// The panel's section on the debug views.
fn debug_views_section(ui: &mut egui::Ui, effect: Effect, debug: &mut Debug) {
    egui::CollapsingHeader::new("debug views").show(ui, |ui| {
        ui.radio_value(&mut debug.image, DebugImage::Shaded, "the effect");
        ui.radio_value(
            &mut debug.image,
            DebugImage::Curvature,
            "mean curvature as colour",
        );
        let hatching = effect.is_hatching();
        ui.add_enabled_ui(hatching, |ui| {
            ui.radio_value(&mut debug.image, DebugImage::Tone, "tone (hatching)");
            ui.radio_value(
                &mut debug.image,
                DebugImage::Bins,
                "direction bins (hatching)",
            );
        });
        ui.checkbox(&mut debug.frusta, "highlight frusta");
        ui.checkbox(&mut debug.directions, "principal directions");
    });
}

/// The file fields: open a model, save or load a preset, take a screenshot.
fn file_actions(ui: &mut egui::Ui, actions: &mut Actions) {
    if let Some(p) = path_field(ui, "open", "open model") {
        actions.open_model = Some(p);
    }
    if let Some(p) = path_field(ui, "save", "save preset") {
        actions.save_preset = Some(p);
    }
    if let Some(p) = path_field(ui, "load", "load preset") {
        actions.load_preset = Some(p);
    }
    if let Some(p) = path_field(ui, "shot", "screenshot") {
        actions.screenshot = Some(p);
    }
    if let Some(p) = path_field(ui, "svg", "save SVG (pen plotter)") {
        actions.save_svg = Some(p);
    }
}

/// The frame's timing and statistics, and the warp's rates and PSNR.
fn frame_lines(
    ui: &mut egui::Ui,
    state: &ViewerState,
    stats: &FrameStats,
    warp: &super::live::WarpLive,
    frame_ms: f64,
) {
    ui.small(format!(
        "{frame_ms:.1} ms/frame · setup {:.0} µs · {} highlights · {} receivers · {} \
         triangles",
        stats.setup_us, stats.highlights, stats.receiver_faces, stats.triangles
    ));
    if let Some(backend) = &stats.backend {
        ui.small(format!("highlights: {backend}"));
    }
    if state.preset.effect == Effect::Warp {
        let fps = |ms: f64| if ms > 0.0 { 1e3 / ms } else { 0.0 };
        ui.small(format!(
            "warp: full frames {:.0} fps ({:.1} ms), warped {:.0} fps ({:.1} ms)",
            fps(warp.full_ms),
            warp.full_ms,
            fps(warp.warped_ms),
            warp.warped_ms,
        ));
        match stats.psnr_db {
            Some(psnr) => ui.small(format!("last measured warped frame: PSNR {psnr:.1} dB")),
            None => ui.small("PSNR: measured half-way between references"),
        };
    }
}

fn to_pos(rect: egui::Rect, ppp: f32, px: Vec2) -> Pos2 {
    rect.min + egui::vec2(px.x, px.y) / ppp
}

/// The central 3-D view. Appends the view's mouse and key input to `inputs` and returns
/// the size the view wants, in physical pixels.
#[allow(clippy::too_many_arguments)]
pub fn central(
    ui: &mut egui::Ui,
    texture: egui::TextureId,
    size: (u32, u32),
    inputs: &mut Vec<Input>,
    debug: &Debug,
    state: &ViewerState,
    highlights: &[HighlightInfo],
    renderer: &Renderer,
    debug_texture: Option<egui::TextureId>,
) -> (u32, u32) {
    let mut want = size;
    egui::CentralPanel::no_frame().show(ui, |ui| {
        let ppp = ui.ctx().pixels_per_point();
        let avail = ui.available_size();
        want = (
            (avail.x * ppp).round().max(1.0) as u32,
            (avail.y * ppp).round().max(1.0) as u32,
        );
        let shown = egui::vec2(size.0 as f32, size.1 as f32) / ppp;
        let texture = match (debug.image, debug_texture) {
            (DebugImage::Tone | DebugImage::Bins, Some(t)) => t,
            _ => texture,
        };
        let resp = ui.add(
            egui::Image::new(egui::load::SizedTexture::new(texture, shown))
                .sense(Sense::click_and_drag()),
        );
        let rect = resp.rect;
        push_inputs(ui, &resp, ppp, inputs);
        // Overlays.
        let painter = ui.painter_at(rect);
        let view = state.view(&renderer.model().framing, size);
        let proj = |p: Vec3| view.to_pixel(p, size).map(|px| to_pos(rect, ppp, px));
        if let (DebugImage::Curvature, Some(h)) = (debug.image, renderer.cached_mean_curvature()) {
            painter.rect_filled(rect, 0.0, Color32::from_gray(40));
            painter.add(curvature_mesh(renderer.model(), h, &view, size, rect, ppp));
        }
        for h in highlights {
            if debug.frusta || state.selected == Some(h.id) {
                draw_frustum(&painter, h, state.selected == Some(h.id), &proj);
            }
        }
        if debug.directions {
            draw_directions(&painter, renderer, &view, &proj);
        }
        painter.text(
            rect.left_top() + egui::vec2(6.0, 4.0),
            egui::Align2::LEFT_TOP,
            format!("{} · {}", state.preset.effect.name(), renderer.model().name),
            egui::FontId::monospace(12.0),
            Color32::DARK_GRAY,
        );
    });
    want
}

/// Turns this frame's pointer, wheel and key events over the view `resp` into [`Input`]s.
fn push_inputs(ui: &egui::Ui, resp: &egui::Response, ppp: f32, inputs: &mut Vec<Input>) {
    let rect = resp.rect;
    let to_px = |p: Pos2| Vec2::new((p.x - rect.min.x) * ppp, (p.y - rect.min.y) * ppp);
    let keyboard_free = !ui.ctx().egui_wants_keyboard_input();
    let events = ui.input(|i| i.events.clone());
    for ev in events {
        match ev {
            egui::Event::PointerButton {
                pos,
                button,
                pressed,
                modifiers,
            } => {
                if pressed && rect.contains(pos) {
                    let button = match button {
                        egui::PointerButton::Primary if modifiers.shift => Button::ShiftLeft,
                        egui::PointerButton::Primary if modifiers.ctrl || modifiers.command => {
                            Button::CtrlLeft
                        }
                        egui::PointerButton::Primary => Button::Left,
                        _ => Button::Right,
                    };
                    inputs.push(Input::Press {
                        at: to_px(pos),
                        button,
                    });
                } else if !pressed {
                    inputs.push(Input::Release { at: to_px(pos) });
                }
            }
            egui::Event::PointerMoved(pos) => inputs.push(Input::Move { at: to_px(pos) }),
            egui::Event::MouseWheel { delta, unit, .. } if resp.hovered() => {
                let notches = match unit {
                    egui::MouseWheelUnit::Point => delta.y / 50.0,
                    _ => delta.y,
                };
                if let Some(p) = ui.input(|i| i.pointer.hover_pos()) {
                    inputs.push(Input::Scroll {
                        at: to_px(p),
                        notches,
                    });
                }
            }
            egui::Event::Key {
                key, pressed: true, ..
            } if keyboard_free => {
                let name = match key {
                    egui::Key::T => "t",
                    egui::Key::R => "r",
                    egui::Key::Escape => "escape",
                    egui::Key::Num1 => "1",
                    egui::Key::Num2 => "2",
                    egui::Key::Num3 => "3",
                    egui::Key::Num4 => "4",
                    egui::Key::Num5 => "5",
                    egui::Key::Num6 => "6",
                    egui::Key::Num7 => "7",
                    _ => "",
                };
                if let Some(k) = Key::from_name(name) {
                    inputs.push(Input::Key(k));
                }
            }
            _ => {}
        }
    }
}

/// Draws a highlight's projector footprint (its ellipse and `e_max` axis), orange when
/// selected.
fn draw_frustum(
    painter: &egui::Painter,
    h: &HighlightInfo,
    selected: bool,
    proj: &impl Fn(Vec3) -> Option<Pos2>,
) {
    let v = h.normal.cross(h.axis_u);
    let pts: Vec<Pos2> = (0..=32)
        .filter_map(|i| {
            let a = i as f32 / 32.0 * std::f32::consts::TAU;
            proj(
                h.centre_world
                    + h.axis_u * h.half_extent.x * a.cos()
                    + v * h.half_extent.y * a.sin(),
            )
        })
        .collect();
    let color = if selected {
        Color32::from_rgb(255, 160, 0)
    } else {
        Color32::from_rgb(0, 160, 255)
    };
    painter.add(egui::Shape::line(pts, Stroke::new(1.5, color)));
    if let (Some(c), Some(u)) = (
        proj(h.centre_world),
        proj(h.centre_world + h.axis_u * h.half_extent.x),
    ) {
        painter.line_segment([c, u], Stroke::new(1.5, color));
    }
}

/// Draws the `κ_max` directions of up to about 3,000 front-facing vertices.
fn draw_directions(
    painter: &egui::Painter,
    renderer: &Renderer,
    view: &crate::view::View,
    proj: &impl Fn(Vec3) -> Option<Pos2>,
) {
    let mesh = &renderer.model().mesh;
    let step = (mesh.vertex_count() / 3000).max(1);
    let len = 0.03;
    let dirs = renderer
        .cached_directions(DirectionPreset::KMax)
        .unwrap_or(&[]);
    for (i, (p, d)) in mesh.positions.iter().zip(dirs).enumerate().step_by(step) {
        let n = view
            .world_from_object
            .transform_vector3(mesh.normals[i])
            .normalize_or_zero();
        let pw = view.world_from_object.transform_point3(*p);
        if n.dot(view.camera.eye - pw) <= 0.0 {
            continue;
        }
        let dw = view
            .world_from_object
            .transform_vector3(*d)
            .normalize_or_zero()
            * len;
        if let (Some(a), Some(b)) = (proj(pw - dw), proj(pw + dw)) {
            painter.line_segment([a, b], Stroke::new(1.0, Color32::from_rgb(200, 40, 40)));
        }
    }
}

/// The model as an egui mesh coloured by mean curvature: front faces only, sorted back to
/// front (egui has no depth buffer).
fn curvature_mesh(
    model: &Model,
    mean_curvature: &[f32],
    view: &crate::view::View,
    size: (u32, u32),
    rect: egui::Rect,
    ppp: f32,
) -> egui::Shape {
    let m = &model.mesh;
    let world: Vec<Vec3> = m
        .positions
        .iter()
        .map(|p| view.world_from_object.transform_point3(*p))
        .collect();
    let view_from_world = view.camera.view_from_world();
    let mut tris: Vec<(f32, [u32; 3])> = m
        .triangles()
        .filter(|t| t.iter().all(|&i| (i as usize) < world.len()))
        .filter_map(|t| {
            let [a, b, c] = t.map(|i| world[i as usize]);
            let n = (b - a).cross(c - a);
            (n.dot(view.camera.eye - a) > 0.0)
                .then(|| (view_from_world.transform_point3((a + b + c) / 3.0).z, t))
        })
        .collect();
    tris.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut mesh = egui::Mesh::default();
    for (_, t) in tris {
        for i in t {
            let Some(px) = view.to_pixel(world[i as usize], size) else {
                continue;
            };
            let h = mean_curvature.get(i as usize).copied().unwrap_or(0.0);
            mesh.vertices.push(egui::epaint::Vertex {
                pos: to_pos(rect, ppp, px),
                uv: egui::epaint::WHITE_UV,
                color: curvature_colour(h),
            });
        }
        let n = mesh.vertices.len() as u32;
        if n.is_multiple_of(3) {
            mesh.indices.extend([n - 3, n - 2, n - 1]);
        } else {
            mesh.vertices.truncate(n as usize - (n as usize % 3));
        }
    }
    egui::Shape::mesh(mesh)
}
