//! CPU test of an edited highlight on a moving body: an ellipsoid on a two-joint sway rig
//! (`generate::swaying`), its top third bound to the top joint alone, lit by a light that
//! turns with that joint. In the joint's frame nothing changes, so the highlight's
//! `N = H` point (§3.2) stays on the same surface point; the user's §3.4 edit (a drag
//! along the principal directions, a turn and a growth) must stay there too, with its id,
//! as the body sways.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec2, Vec3};
use npr_geometry::{CurvatureOptions, LightEye, generate};
use npr_specular::HighlightSet;

#[test]
fn an_edited_highlight_stays_on_its_surface_point_as_the_body_moves() {
    let (a, b, c) = (0.7, 1.4, 1.0);
    let rigged = generate::swaying(generate::ellipsoid(a, b, c, 24));
    let rig = &rigged.rig;
    let clip = &rig.clips()[0];
    let options = CurvatureOptions::default();
    // Towards the top cap, off every axis (the top is bound to the top joint alone).
    let to_light_rest = Vec3::new(0.35, 1.0, 0.45).normalize();
    let pose_at = |t: f32| {
        let pose = rig.sample(clip, t);
        // Skin joint 1 (the top): rest -> posed for the vertices bound to it.
        let top: Mat4 = pose.joint_matrices(0)[1];
        (rig.pose_mesh(&pose), top)
    };
    let light_for = |top: Mat4| {
        let d = top.transform_vector3(to_light_rest).normalize();
        LightEye::Directions {
            to_light: d,
            to_eye: d,
        }
    };
    let (rest, top0) = pose_at(0.0);
    let mut set = HighlightSet::new(&rest, &options).unwrap();
    let first = set.update(light_for(top0), Mat4::IDENTITY).to_vec();
    let edited = first
        .iter()
        .filter(|h| h.found && h.piece == 0 && h.centre.position_world.y > 0.9)
        .max_by(|p, q| {
            p.projector
                .half_extent
                .x
                .total_cmp(&q.projector.half_extent.x)
        })
        .expect("a highlight on the top cap");
    let id = edited.id;
    let radius = b;
    {
        let controls = set.controls_mut(id);
        controls.translate = Vec2::new(0.12, -0.06) * radius;
        controls.rotate_rad = 0.5;
        controls.scale = Vec2::new(1.3, 0.8);
    }
    let projector = |set: &HighlightSet| {
        set.highlights()
            .iter()
            .find(|h| h.id == id && h.piece == 0)
            .map(|h| h.projector)
    };
    set.update(light_for(top0), Mat4::IDENTITY);
    let p0 = projector(&set).expect("the edited highlight keeps its id");
    let inv0 = top0.inverse();
    let (c0, u0) = (
        inv0.transform_point3(p0.centre_world),
        inv0.transform_vector3(p0.axis_u).normalize(),
    );
    assert!(
        p0.centre_world.distance(p0.anchor_world) > 0.1 * radius,
        "the drag moved the projector off its N = H point"
    );
    let mut worst = (0.0f32, 0.0f32, 0.0f32);
    // The clip leans the top 15 degrees each way: 16 poses over its 2 s.
    for i in 1..=16 {
        let t = clip.duration() * i as f32 / 16.0;
        let (posed, top) = pose_at(t);
        set.repose(&posed, &options).unwrap();
        set.update(light_for(top), Mat4::IDENTITY);
        let p = projector(&set).unwrap_or_else(|| panic!("t = {t}: highlight {id} lost"));
        let inv = top.inverse();
        let centre = inv.transform_point3(p.centre_world);
        let anchor_moved = top.transform_point3(c0).distance(p0.centre_world);
        let u = inv.transform_vector3(p.axis_u).normalize();
        worst.0 = worst.0.max(centre.distance(c0) / radius);
        worst.1 = worst.1.max(u.dot(u0).clamp(-1.0, 1.0).acos().to_degrees());
        worst.2 = worst.2.max(anchor_moved / radius);
    }
    eprintln!(
        "edited centre off its surface point by {:.2e} of the radius, axis by {:.3} deg; \
         the point itself moved {:.3} of the radius in the world",
        worst.0, worst.1, worst.2
    );
    // The body moved (the top leans 15 degrees), the edit stayed on the surface.
    assert!(worst.2 > 0.1, "{worst:?}");
    assert!(worst.0 < 2e-3, "{worst:?}");
    assert!(worst.1 < 1.0, "{worst:?}");
}
