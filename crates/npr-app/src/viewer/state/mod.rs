//! The viewer's state without a window: the preset being edited, the orbit camera and
//! light under the mouse, the picked highlight and its §3.4 edits (translate along
//! e_max/e_min, rotate about N, scale), the turntable, and camera prediction for live
//! warping. Every mouse and key action — a person's or a script's — goes through
//! [`ViewerState::input`], so the tests here exercise the same code the window runs.

use super::script::Command;
use crate::AppError;
use crate::preset::{Effect, HighlightEdit, Preset};
use crate::view::View;
use glam::{Vec2, Vec3};
use std::collections::VecDeque;

/// What picking and dragging need to know of one highlight (world space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HighlightInfo {
    /// Stable id (the set's matching keeps it while the highlight lives).
    pub id: u64,
    /// Projector centre (after translation).
    pub centre_world: Vec3,
    /// The found centre on the surface, object space (the edit's anchor).
    pub anchor_object: Vec3,
    /// Unit normal at the centre (the projector axis).
    pub normal: Vec3,
    /// Unit e_max at the found centre.
    pub e_max: Vec3,
    /// Unit e_min at the found centre.
    pub e_min: Vec3,
    /// Projector u axis (after rotation).
    pub axis_u: Vec3,
    /// Half extents of the projector along u and v.
    pub half_extent: Vec2,
}

impl HighlightInfo {
    /// The highlights of a set.
    pub fn of_set(set: &npr_specular::HighlightSet) -> Vec<Self> {
        set.highlights()
            .iter()
            .filter(|h| h.opacity > 0.0)
            .map(|h| Self {
                id: h.id,
                centre_world: h.projector.centre_world,
                anchor_object: h.centre.position_object,
                normal: h.projector.normal,
                e_max: h.centre.dir_kappa_max,
                e_min: h.centre.dir_kappa_min,
                axis_u: h.projector.axis_u,
                half_extent: h.projector.half_extent,
            })
            .collect()
    }
}

/// Keyboard and mouse input, in pixels of the 3-D view (origin top-left).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Input {
    /// A mouse button went down.
    Press {
        /// Position.
        at: Vec2,
        /// Which button.
        button: Button,
    },
    /// The mouse moved.
    Move {
        /// Position.
        at: Vec2,
    },
    /// The button went up.
    Release {
        /// Position.
        at: Vec2,
    },
    /// Wheel notches (positive: away from the user).
    Scroll {
        /// Position.
        at: Vec2,
        /// Notches.
        notches: f32,
    },
    /// A key.
    Key(Key),
}

/// Mouse buttons, with the modifier held at the press.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Button {
    /// Left.
    Left,
    /// Left with Shift (rotate a highlight).
    ShiftLeft,
    /// Left with Ctrl (move the light).
    CtrlLeft,
    /// Right or middle (pan).
    Right,
}

/// The keys the viewer answers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    /// Switch to an effect (keys 1–7).
    Effect(Effect),
    /// Toggle the turntable (T).
    Turntable,
    /// Reset the view (R).
    Reset,
    /// Deselect (Escape).
    Deselect,
    /// Play or pause the model's clip (space).
    PlayPause,
}

impl Key {
    /// A key from its name in scripts and the help text.
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "t" | "T" => Self::Turntable,
            "r" | "R" => Self::Reset,
            "escape" | "esc" => Self::Deselect,
            "space" | " " => Self::PlayPause,
            n => {
                let i: usize = n.parse().ok()?;
                Self::Effect(*Effect::ALL.get(i.checked_sub(1)?)?)
            }
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Drag {
    Orbit {
        last: Vec2,
    },
    Pan {
        last: Vec2,
    },
    Light {
        last: Vec2,
    },
    Translate {
        id: u64,
        start_hit: Vec3,
        start: HighlightEdit,
    },
    Rotate {
        id: u64,
        start_angle: f32,
        start: HighlightEdit,
    },
}

/// The viewer's state (see the module docs).
#[derive(Clone, Debug)]
pub struct ViewerState {
    /// Every parameter; saved as the preset.
    pub preset: Preset,
    /// The preset the view was opened with (what Reset returns to).
    pub initial: Preset,
    /// The selected highlight.
    pub selected: Option<u64>,
    /// Turntable on.
    pub turntable: bool,
    /// Degrees turned by the turntable so far.
    pub turntable_deg: f32,
    /// Degrees per frame of the turntable.
    pub turntable_speed_deg: f32,
    /// Whether the model's clip plays (space).
    pub clip_playing: bool,
    /// The clip's time, seconds (advanced by the preset's `[animation] speed` / 30 a
    /// frame while playing; the scrub bar sets it).
    pub clip_time: f32,
    drag: Option<Drag>,
}

/// A ray from the eye through a pixel of a `size` view.
pub fn pixel_ray(view: &View, size: (u32, u32), px: Vec2) -> (Vec3, Vec3) {
    let ndc = Vec2::new(
        px.x / size.0.max(1) as f32 * 2.0 - 1.0,
        1.0 - px.y / size.1.max(1) as f32 * 2.0,
    );
    let inv = view.camera.clip_from_world().inverse();
    let near = inv.project_point3(ndc.extend(0.0));
    let far = inv.project_point3(ndc.extend(1.0));
    (near, (far - near).normalize_or(Vec3::NEG_Z))
}

/// Where the ray hits the plane through `p` with normal `n` (`None` if parallel or behind).
fn hit_plane(ray: (Vec3, Vec3), p: Vec3, n: Vec3) -> Option<Vec3> {
    let denom = ray.1.dot(n);
    if denom.abs() < 1e-6 {
        return None;
    }
    let t = (p - ray.0).dot(n) / denom;
    (t > 0.0).then(|| ray.0 + ray.1 * t)
}

/// The highlight under pixel `px`: the nearest one whose projector ellipse (its
/// footprint, with a 25 % margin for small ones) the pixel's ray crosses, front-facing.
pub fn pick(view: &View, size: (u32, u32), px: Vec2, highlights: &[HighlightInfo]) -> Option<u64> {
    let ray = pixel_ray(view, size, px);
    highlights
        .iter()
        .filter(|h| h.normal.dot(ray.1) < 0.0)
        .filter_map(|h| {
            let p = hit_plane(ray, h.centre_world, h.normal)?;
            let v_axis = h.normal.cross(h.axis_u);
            let d = p - h.centre_world;
            let (u, v) = (
                d.dot(h.axis_u) / h.half_extent.x.max(1e-6),
                d.dot(v_axis) / h.half_extent.y.max(1e-6),
            );
            (u * u + v * v <= 1.25 * 1.25).then(|| (h.id, (p - ray.0).length()))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(id, _)| id)
}

/// Angle of `p` about the highlight's normal in its (e_max, e_min) frame, radians.
fn angle_about(h: &HighlightInfo, p: Vec3) -> f32 {
    let d = p - h.centre_world;
    d.dot(h.e_min).atan2(d.dot(h.e_max))
}

/// The orbit camera and the model turn of one frame, for warping: yaw, pitch and distance
/// of the camera, and the model's turn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitView {
    /// Camera yaw, degrees.
    pub yaw_deg: f32,
    /// Camera pitch, degrees.
    pub pitch_deg: f32,
    /// Camera distance.
    pub distance: f32,
    /// Model turn, degrees.
    pub turn_deg: f32,
}

impl OrbitView {
    /// The pose of a preset with the turntable at `turntable_deg`.
    pub fn of(preset: &Preset, turntable_deg: f32) -> Self {
        Self {
            yaw_deg: preset.camera.yaw_deg,
            pitch_deg: preset.camera.pitch_deg,
            distance: preset.camera.distance,
            turn_deg: preset.turn_deg + turntable_deg,
        }
    }
}

/// Predicts where the camera will be `ahead` frames from now by extrapolating the last
/// frames' motion (the warping paper's "reference image 2 predicted in time"): linear in
/// yaw, pitch, log-distance and turn, from the two most recent poses. Exact for a steady
/// orbit or turntable.
#[derive(Clone, Debug, Default)]
pub struct CameraPredictor {
    history: VecDeque<(u64, OrbitView)>,
}

impl CameraPredictor {
    /// Records the pose of frame `frame`.
    pub fn push(&mut self, frame: u64, pose: OrbitView) {
        if self.history.back().is_some_and(|(f, _)| *f >= frame) {
            self.history.clear();
        }
        self.history.push_back((frame, pose));
        while self.history.len() > 2 {
            self.history.pop_front();
        }
    }

    /// The pose `ahead` frames after the last recorded one (the last pose when there is
    /// no motion history).
    pub fn predict(&self, ahead: f32) -> Option<OrbitView> {
        let (f1, p1) = *self.history.back()?;
        let Some(&(f0, p0)) = self.history.iter().rev().nth(1) else {
            return Some(p1);
        };
        let dt = (f1 - f0) as f32;
        let rate = |a: f32, b: f32| (b - a) / dt;
        let ld = |d: f32| d.max(1e-6).ln();
        Some(OrbitView {
            yaw_deg: p1.yaw_deg + rate(p0.yaw_deg, p1.yaw_deg) * ahead,
            pitch_deg: (p1.pitch_deg + rate(p0.pitch_deg, p1.pitch_deg) * ahead).clamp(-85.0, 85.0),
            distance: (ld(p1.distance) + rate(ld(p0.distance), ld(p1.distance)) * ahead).exp(),
            turn_deg: p1.turn_deg + rate(p0.turn_deg, p1.turn_deg) * ahead,
        })
    }
}

impl ViewerState {
    /// A state editing `preset`.
    pub fn new(preset: Preset) -> Self {
        let clip_time = preset.animation.time;
        Self {
            initial: preset.clone(),
            preset,
            selected: None,
            turntable: false,
            turntable_deg: 0.0,
            turntable_speed_deg: 1.0,
            clip_playing: true,
            clip_time,
            drag: None,
        }
    }

    /// The edit of highlight `id` (a default one when it has none).
    pub fn edit(&self, id: u64) -> HighlightEdit {
        self.preset
            .specular
            .edits
            .iter()
            .find(|e| e.id == id)
            .copied()
            .unwrap_or(HighlightEdit {
                id,
                ..HighlightEdit::default()
            })
    }

    fn set_edit(&mut self, edit: HighlightEdit, anchor: Option<Vec3>) {
        let mut edit = edit;
        if edit.anchor.is_none() {
            edit.anchor = anchor.map(|a| a.to_array());
        }
        match self
            .preset
            .specular
            .edits
            .iter_mut()
            .find(|e| e.id == edit.id)
        {
            Some(e) => *e = edit,
            None => self.preset.specular.edits.push(edit),
        }
    }

    /// Advances per-frame animation: the turntable, and the clip while it plays (at 30
    /// frames a second of clip time, times `[animation] speed`).
    pub fn tick(&mut self) {
        if self.turntable {
            self.turntable_deg = (self.turntable_deg + self.turntable_speed_deg) % 360.0;
        }
        if self.clip_playing {
            let t = self.clip_time + self.preset.animation.speed / 30.0;
            if t.is_finite() {
                self.clip_time = t;
            }
        }
    }

    /// Handles one input event. `view` and `size` are the current 3-D view's; `highlights`
    /// the highlights drawn in it.
    pub fn input(
        &mut self,
        input: Input,
        view: &View,
        size: (u32, u32),
        highlights: &[HighlightInfo],
    ) {
        let find = |id: u64| highlights.iter().find(|h| h.id == id).copied();
        match input {
            Input::Key(key) => match key {
                Key::Effect(e) => self.preset.effect = e,
                Key::Turntable => self.turntable = !self.turntable,
                Key::PlayPause => self.clip_playing = !self.clip_playing,
                Key::Reset => {
                    self.preset.camera = self.initial.camera;
                    self.preset.light = self.initial.light;
                    self.preset.turn_deg = self.initial.turn_deg;
                    self.turntable_deg = 0.0;
                }
                Key::Deselect => self.selected = None,
            },
            Input::Press { at, button } => {
                let picked = if self.preset.effect == Effect::Specular {
                    pick(view, size, at, highlights)
                } else {
                    None
                };
                self.drag = match (button, picked) {
                    (Button::Left, Some(id)) => {
                        self.selected = Some(id);
                        find(id).and_then(|h| {
                            let hit =
                                hit_plane(pixel_ray(view, size, at), h.centre_world, h.normal)?;
                            Some(Drag::Translate {
                                id,
                                start_hit: hit,
                                start: self.edit(id),
                            })
                        })
                    }
                    (Button::ShiftLeft, _) => self.selected.and_then(find).and_then(|h| {
                        let hit = hit_plane(pixel_ray(view, size, at), h.centre_world, h.normal)?;
                        Some(Drag::Rotate {
                            id: h.id,
                            start_angle: angle_about(&h, hit),
                            start: self.edit(h.id),
                        })
                    }),
                    (Button::Left, None) => Some(Drag::Orbit { last: at }),
                    (Button::CtrlLeft, _) => Some(Drag::Light { last: at }),
                    (Button::Right, _) => Some(Drag::Pan { last: at }),
                };
            }
            Input::Move { at } => self.drag_to(at, view, size, highlights),
            Input::Release { at } => {
                self.drag_to(at, view, size, highlights);
                self.drag = None;
            }
            Input::Scroll { at: _, notches } => {
                let factor = 1.1f32.powf(notches);
                match self.selected.and_then(find) {
                    Some(h) if self.preset.effect == Effect::Specular => {
                        let mut e = self.edit(h.id);
                        e.scale = (Vec2::from(e.scale) * factor)
                            .clamp(Vec2::splat(0.05), Vec2::splat(20.0))
                            .to_array();
                        self.set_edit(e, Some(h.anchor_object));
                    }
                    _ => {
                        let c = &mut self.preset.camera;
                        c.distance = (c.distance / factor).clamp(1.05, 50.0);
                    }
                }
            }
        }
    }

    fn drag_to(&mut self, at: Vec2, view: &View, size: (u32, u32), highlights: &[HighlightInfo]) {
        let Some(drag) = self.drag else { return };
        let find = |id: u64| highlights.iter().find(|h| h.id == id).copied();
        match drag {
            Drag::Orbit { last } => {
                let d = at - last;
                let c = &mut self.preset.camera;
                c.yaw_deg -= d.x * 0.4;
                c.pitch_deg = (c.pitch_deg + d.y * 0.4).clamp(-85.0, 85.0);
                self.drag = Some(Drag::Orbit { last: at });
            }
            Drag::Pan { last } => {
                let d = at - last;
                let c = &mut self.preset.camera;
                let per_px =
                    2.0 * c.distance * (c.fov_deg.to_radians() * 0.5).tan() / size.1.max(1) as f32;
                c.pan[0] -= d.x * per_px;
                c.pan[1] += d.y * per_px;
                self.drag = Some(Drag::Pan { last: at });
            }
            Drag::Light { last } => {
                let d = at - last;
                let dir = Vec3::from(self.preset.light.direction).normalize_or(Vec3::Y);
                let yaw = dir.x.atan2(dir.z) + d.x.to_radians() * 0.5;
                let pitch = (dir.y.asin() - d.y.to_radians() * 0.5).clamp(-1.5, 1.5);
                self.preset.light.direction = [
                    yaw.sin() * pitch.cos(),
                    pitch.sin(),
                    yaw.cos() * pitch.cos(),
                ];
                self.drag = Some(Drag::Light { last: at });
            }
            Drag::Translate {
                id,
                start_hit,
                start,
            } => {
                let Some(h) = find(id) else { return };
                // The plane through the start point, so the highlight follows the cursor.
                let Some(hit) = hit_plane(pixel_ray(view, size, at), start_hit, h.normal) else {
                    return;
                };
                let d = hit - start_hit;
                let mut e = start;
                e.translate = [
                    start.translate[0] + d.dot(h.e_max),
                    start.translate[1] + d.dot(h.e_min),
                ];
                self.set_edit(e, Some(h.anchor_object));
            }
            Drag::Rotate {
                id,
                start_angle,
                start,
            } => {
                let Some(h) = find(id) else { return };
                let Some(hit) = hit_plane(pixel_ray(view, size, at), h.centre_world, h.normal)
                else {
                    return;
                };
                let mut turn = (angle_about(&h, hit) - start_angle).to_degrees();
                if turn > 180.0 {
                    turn -= 360.0;
                } else if turn < -180.0 {
                    turn += 360.0;
                }
                let mut e = start;
                e.rotate_deg = start.rotate_deg + turn;
                self.set_edit(e, Some(h.anchor_object));
            }
        }
    }

    /// The view for a `size` image of `framing`'s model at the current turntable angle.
    pub fn view(&self, framing: &crate::view::Framing, size: (u32, u32)) -> View {
        View::new(&self.preset, framing, size, self.turntable_deg)
    }

    /// The selected highlight's centre in `view`'s pixels (None when nothing is selected
    /// or it is off screen).
    pub fn selected_pixel(
        &self,
        view: &View,
        size: (u32, u32),
        highlights: &[HighlightInfo],
    ) -> Option<Vec2> {
        let id = self.selected?;
        let h = highlights.iter().find(|h| h.id == id)?;
        view.to_pixel(h.centre_world, size)
    }

    /// Whether "save SVG" can draw this view: it traces the hatching, so the effect must
    /// be one of the two hatching styles.
    ///
    /// # Errors
    /// [`AppError::Usage`] naming the effects that can.
    pub fn can_save_svg(&self) -> Result<(), AppError> {
        if self.preset.effect.is_hatching() {
            Ok(())
        } else {
            Err(AppError::Usage(format!(
                "save SVG draws the hatching: switch to hatching-pen or hatching-pencil (the \
                 effect is {})",
                self.preset.effect.name()
            )))
        }
    }

    /// The preset as `npr render` needs it to draw this view: the current parameters, the
    /// view's `size`, and the turntable's angle folded into the model turn.
    pub fn preset_for_render(&self, size: (u32, u32)) -> Preset {
        let mut p = self.preset.clone();
        p.output.width = size.0.max(1);
        p.output.height = size.1.max(1);
        p.turn_deg += self.turntable_deg;
        p
    }

    /// The selected highlight as a script's `report` writes it: id, centre and u axis in
    /// pixels, half extents and its §3.4 edit (`null` when nothing is selected).
    pub fn selected_report(
        &self,
        view: &View,
        size: (u32, u32),
        highlights: &[HighlightInfo],
    ) -> serde_json::Value {
        let Some(h) = self
            .selected
            .and_then(|id| highlights.iter().find(|h| h.id == id))
        else {
            return serde_json::Value::Null;
        };
        let c = view.to_pixel(h.centre_world, size);
        let u = view.to_pixel(h.centre_world + h.axis_u * h.half_extent.x, size);
        let edit = self.edit(h.id);
        serde_json::json!({
            "id": h.id,
            "centre_px": c.map(|c| [c.x, c.y]),
            "u_axis_px": match (c, u) { (Some(c), Some(u)) => Some([u.x - c.x, u.y - c.y]), _ => None },
            "half_extent": [h.half_extent.x, h.half_extent.y],
            "translate": edit.translate,
            "rotate_deg": edit.rotate_deg,
            "scale": edit.scale,
        })
    }

    /// Runs one `npr view --script` command that is input — keys, clicks, drags, the
    /// wheel, effect and turntable switches — as the events a person's hand would send
    /// through [`ViewerState::input`]; the window and the browser page both run scripts
    /// through here. Commands that need the shell (resize, screenshot, files, exit) are
    /// handed back for it to do.
    ///
    /// # Errors
    /// A command that names what is not there: an unknown key, no visible highlight to
    /// click, no selected highlight to drag, turn or grow.
    pub fn script(
        &mut self,
        command: Command,
        view: &View,
        size: (u32, u32),
        highlights: &[HighlightInfo],
    ) -> Result<Option<Command>, AppError> {
        let send = |state: &mut Self, input: Input| state.input(input, view, size, highlights);
        // A press, 8 moves along the way and a release (what a hand's drag sends).
        let drag = |state: &mut Self, from: Vec2, to: Vec2, button: Button| {
            state.input(Input::Press { at: from, button }, view, size, highlights);
            for i in 1..=8 {
                let at = from + (to - from) * (i as f32 / 8.0);
                state.input(Input::Move { at }, view, size, highlights);
            }
            state.input(Input::Release { at: to }, view, size, highlights);
        };
        let selected = |state: &Self, what: &str| {
            state
                .selected_pixel(view, size, highlights)
                .ok_or_else(|| AppError::Usage(format!("script: {what}: no highlight is selected")))
        };
        match command {
            Command::Key(k) => {
                let key = Key::from_name(&k)
                    .ok_or_else(|| AppError::Usage(format!("script: unknown key '{k}'")))?;
                send(self, Input::Key(key));
            }
            Command::Click(x, y) => {
                let at = Vec2::new(x, y);
                drag(self, at, at, Button::Left);
            }
            Command::ClickHighlight => {
                let at = highlights
                    .iter()
                    .filter(|h| h.normal.dot(view.camera.eye - h.centre_world) > 0.0)
                    .max_by(|a, b| {
                        (a.half_extent.x * a.half_extent.y)
                            .total_cmp(&(b.half_extent.x * b.half_extent.y))
                    })
                    .and_then(|h| view.to_pixel(h.centre_world, size))
                    .ok_or_else(|| {
                        AppError::Usage("script: click-highlight: no highlight is visible".into())
                    })?;
                drag(self, at, at, Button::Left);
            }
            Command::Drag([x0, y0, x1, y1], m) => {
                let button = match m.as_str() {
                    "shift" => Button::ShiftLeft,
                    "ctrl" => Button::CtrlLeft,
                    "right" => Button::Right,
                    _ => Button::Left,
                };
                drag(self, Vec2::new(x0, y0), Vec2::new(x1, y1), button);
            }
            Command::DragSelected(dx, dy) => {
                let at = selected(self, "drag-selected")?;
                drag(self, at, at + Vec2::new(dx, dy), Button::Left);
            }
            Command::RotateSelected(deg) => {
                let c = selected(self, "rotate-selected")?;
                // A Shift drag along a circle of 40 px around the centre, in 8 steps.
                let at = |a: f32| c + Vec2::new(a.cos(), -a.sin()) * 40.0;
                send(
                    self,
                    Input::Press {
                        at: at(0.0),
                        button: Button::ShiftLeft,
                    },
                );
                for i in 1..=8 {
                    let a = deg.to_radians() * i as f32 / 8.0;
                    send(self, Input::Move { at: at(a) });
                }
                send(
                    self,
                    Input::Release {
                        at: at(deg.to_radians()),
                    },
                );
            }
            Command::Scroll(x, y, notches) => send(
                self,
                Input::Scroll {
                    at: Vec2::new(x, y),
                    notches,
                },
            ),
            Command::ScrollSelected(notches) => {
                let at = selected(self, "scroll-selected")?;
                send(self, Input::Scroll { at, notches });
            }
            Command::Effect(e) => self.preset.effect = e,
            Command::Turntable(on) => self.turntable = on,
            shell => return Ok(Some(shell)),
        }
        Ok(None)
    }
}

#[cfg(test)]
mod tests;
