//! Tests of the parent module.

use super::*;
use crate::view::Framing;
use npr_geometry::generate;

fn highlight(view: &View) -> HighlightInfo {
    // A highlight on the sphere facing the camera.
    let n = (view.camera.eye - Vec3::ZERO).normalize();
    let e_max = n.cross(Vec3::Y).normalize();
    let e_min = n.cross(e_max);
    HighlightInfo {
        id: 7,
        centre_world: n,
        anchor_object: n,
        normal: n,
        e_max,
        e_min,
        axis_u: e_max,
        half_extent: Vec2::splat(0.2),
    }
}

fn setup() -> (ViewerState, View, (u32, u32), Vec<HighlightInfo>) {
    let preset = Preset {
        effect: Effect::Specular,
        ..Preset::default()
    };
    let framing = Framing::of(&generate::icosphere(2, 1.0));
    let size = (400, 300);
    let state = ViewerState::new(preset);
    let view = state.view(&framing, size);
    let h = highlight(&view);
    // A second highlight off to the side.
    let mut other = h;
    other.id = 9;
    other.centre_world = (h.centre_world + h.e_max * 0.6).normalize();
    (state, view, size, vec![h, other])
}

#[test]
fn the_picking_ray_hits_the_right_highlight() {
    let (_, view, size, hs) = setup();
    for h in &hs {
        let px = view.to_pixel(h.centre_world, size).unwrap();
        assert_eq!(pick(&view, size, px, &hs), Some(h.id));
    }
    // Far from both: nothing.
    assert_eq!(pick(&view, size, Vec2::new(2.0, 2.0), &hs), None);
}

#[test]
fn dragging_scrolling_and_shift_dragging_edit_the_picked_highlight() {
    let (mut s, view, size, hs) = setup();
    let h = hs[0];
    let at = view.to_pixel(h.centre_world, size).unwrap();
    s.input(
        Input::Press {
            at,
            button: Button::Left,
        },
        &view,
        size,
        &hs,
    );
    assert_eq!(s.selected, Some(7));
    // Drag 40 px to the right: the translation follows e_max's screen direction.
    let to = at + Vec2::new(40.0, 0.0);
    s.input(Input::Move { at: to }, &view, size, &hs);
    s.input(Input::Release { at: to }, &view, size, &hs);
    let e = s.edit(7);
    let moved = h.e_max * e.translate[0] + h.e_min * e.translate[1];
    let moved_px = view.to_pixel(h.centre_world + moved, size).unwrap() - at;
    assert!(
        (moved_px - Vec2::new(40.0, 0.0)).length() < 2.0,
        "{moved_px}"
    );
    assert!(e.anchor.is_some());
    // The camera did not orbit.
    assert_eq!(s.preset.camera, s.initial.camera);

    // Scroll up three notches: the highlight grows, the camera stays.
    s.input(Input::Scroll { at, notches: 3.0 }, &view, size, &hs);
    let e = s.edit(7);
    assert!((e.scale[0] - 1.1f32.powi(3)).abs() < 1e-4);
    assert_eq!(s.preset.camera.distance, s.initial.camera.distance);

    // Shift-drag a quarter turn around the centre: rotation by about ±90°.
    let r = 50.0;
    let start = at + Vec2::new(r, 0.0);
    s.input(
        Input::Press {
            at: start,
            button: Button::ShiftLeft,
        },
        &view,
        size,
        &hs,
    );
    s.input(
        Input::Release {
            at: at + Vec2::new(0.0, -r),
        },
        &view,
        size,
        &hs,
    );
    let turned = s.edit(7).rotate_deg;
    assert!((turned.abs() - 90.0).abs() < 10.0, "{turned}");
}

#[test]
fn an_edit_survives_the_next_frame_matching() {
    // Edits are keyed by the highlight's id, which the set keeps while it is tracked:
    // run a real set over two frames with a small light move and check the id and
    // the applied control persist.
    let mesh = generate::icosphere(4, 1.0);
    let mut set =
        npr_specular::HighlightSet::new(&mesh, &npr_geometry::CurvatureOptions::default()).unwrap();
    let le = |x: f32| npr_geometry::LightEye::Directions {
        to_light: Vec3::new(x, 0.3, 1.0),
        to_eye: Vec3::Z,
    };
    set.update(le(0.0), glam::Mat4::IDENTITY);
    let id = set.highlights()[0].id;
    let mut preset = Preset::default();
    preset.specular.edits.push(HighlightEdit {
        id,
        scale: [2.0, 2.0],
        ..HighlightEdit::default()
    });
    crate::engine::apply_controls(&mut set, &preset, 0, 0.15);
    set.update(le(0.02), glam::Mat4::IDENTITY);
    let h = set
        .highlights()
        .iter()
        .find(|h| h.id == id)
        .unwrap()
        .clone();
    set.update(le(0.04), glam::Mat4::IDENTITY);
    let h2 = set.highlights().iter().find(|h| h.id == id).unwrap();
    assert!(
        (h2.projector.half_extent - h.projector.half_extent)
            .abs()
            .max_element()
            < 0.05 * h.projector.half_extent.x
    );
    let plain = {
        let mut s2 =
            npr_specular::HighlightSet::new(&mesh, &npr_geometry::CurvatureOptions::default())
                .unwrap();
        s2.update(le(0.04), glam::Mat4::IDENTITY);
        s2.highlights()[0].projector.half_extent
    };
    assert!((h2.projector.half_extent.x / plain.x - 2.0).abs() < 0.05);
}

#[test]
fn camera_prediction_is_exact_for_steady_orbiting() {
    let mut p = CameraPredictor::default();
    let pose = |f: f32| OrbitView {
        yaw_deg: 10.0 + 1.5 * f,
        pitch_deg: 20.0 - 0.25 * f,
        distance: 3.0 * 1.01f32.powf(f),
        turn_deg: 2.0 * f,
    };
    for f in 0..5u64 {
        p.push(f, pose(f as f32));
    }
    let got = p.predict(10.0).unwrap();
    let want = pose(14.0);
    assert!((got.yaw_deg - want.yaw_deg).abs() < 1e-3);
    assert!((got.pitch_deg - want.pitch_deg).abs() < 1e-3);
    assert!((got.distance / want.distance - 1.0).abs() < 1e-4);
    assert!((got.turn_deg - want.turn_deg).abs() < 1e-3);
}

#[test]
fn keys_switch_effects_and_reset_the_view() {
    let (mut s, view, size, hs) = setup();
    s.input(Input::Key(Key::from_name("5").unwrap()), &view, size, &hs);
    assert_eq!(s.preset.effect, Effect::HatchingPen);
    s.input(
        Input::Press {
            at: Vec2::new(10.0, 10.0),
            button: Button::Left,
        },
        &view,
        size,
        &hs,
    );
    s.input(
        Input::Release {
            at: Vec2::new(60.0, 10.0),
        },
        &view,
        size,
        &hs,
    );
    assert_ne!(s.preset.camera, s.initial.camera);
    s.input(Input::Key(Key::Reset), &view, size, &hs);
    assert_eq!(s.preset.camera, s.initial.camera);
    assert_eq!(Key::from_name("8"), None);
    assert_eq!(Key::from_name("0"), None);
}
