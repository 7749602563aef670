//! The panel's Clip section: a glTF model's clips in the window.

use crate::viewer::state::ViewerState;
use crate::viewer::timeline::Timeline;
use egui::Color32;

/// A glTF model's clips: the clip list, play/pause (space), the scrub bar, the speed and
/// looping; why a clip cannot play, in red.
pub(super) fn timeline_section(ui: &mut egui::Ui, state: &mut ViewerState, timeline: &Timeline) {
    if !timeline.has_clips() {
        return;
    }
    egui::CollapsingHeader::new("Clip")
        .default_open(true)
        .show(ui, |ui| {
            let names = timeline.clip_names();
            let a = &mut state.preset.animation;
            let current = match a.clip.as_str() {
                "" => names.first().cloned().unwrap_or_default(),
                c => c.to_string(),
            };
            egui::ComboBox::from_label("clip")
                .selected_text(current)
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut a.clip, "none".to_string(), "none (bind pose)");
                    for n in &names {
                        ui.selectable_value(&mut a.clip, n.clone(), n);
                    }
                });
            ui.horizontal(|ui| {
                let label = if state.clip_playing { "pause" } else { "play" };
                if ui.button(label).on_hover_text("space").clicked() {
                    state.clip_playing = !state.clip_playing;
                }
                ui.checkbox(&mut state.preset.animation.looped, "loop");
            });
            let d = timeline.duration().max(1e-3);
            let mut t = if state.preset.animation.looped {
                state.clip_time.rem_euclid(d)
            } else {
                state.clip_time.clamp(0.0, d)
            };
            if ui
                .add(egui::Slider::new(&mut t, 0.0..=d).text("time (s)"))
                .changed()
            {
                state.clip_time = t;
            }
            ui.add(egui::Slider::new(&mut state.preset.animation.speed, 0.0..=4.0).text("speed"));
            if let Some(note) = timeline.note() {
                ui.colored_label(Color32::from_rgb(220, 60, 60), note);
            }
        });
}
