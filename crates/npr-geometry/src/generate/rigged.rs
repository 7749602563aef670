//! Procedural rigged models, each a mesh with a [`Rig`] of one skin and one clip, whose
//! posed shape is known in closed form (or, for the twist, whose failure mode is).

use std::f64::consts::TAU;

use glam::{DVec3, Mat4, Quat, Vec3};

use super::{geodesic_sphere, param_grid};
use crate::Mesh;
use crate::animation::{Channel, Clip, Interpolation, Node, Property, Rig, Sampler, Skin, Trs};

/// A mesh and the rig that animates it.
#[derive(Clone, Debug, Default)]
pub struct Rigged {
    /// The mesh at rest (the rig's bind pose).
    pub mesh: Mesh,
    /// One skin, one clip.
    pub rig: Rig,
}

fn node(name: &str, parent: Option<usize>, translation: Vec3) -> Node {
    Node {
        name: Some(name.to_string()),
        parent,
        rest: Trs {
            translation,
            ..Trs::default()
        },
        matrix: None,
    }
}

fn channel(node: usize, property: Property, times: &[f32], keys: &[Vec<f32>]) -> Option<Channel> {
    let width = keys.first().map_or(0, Vec::len);
    let sampler = Sampler::new(Interpolation::Linear, times.to_vec(), keys.concat(), width).ok()?;
    Some(Channel {
        node,
        property,
        sampler,
    })
}

/// An open tube of radius `tube_radius` along +y, `rings + 1` rings (at least 16) from
/// `y = 0` to the arc length `bend_radius × bend_angle`, `segments` around, each ring
/// bound rigidly (weight 1) to its own joint of a chain. Its clip `"bend"` (1 s, LINEAR)
/// bends the chain: at `t = 0` straight, at `t = 0.5` an arc of radius
/// `2 × bend_radius` through `bend_angle / 2`, at `t = 1` an arc of radius `bend_radius`
/// through `bend_angle`, turning from +y towards −x about the z axis through
/// `(−ρ, 0, 0)` (ρ the arc's radius).
///
/// At the keys the posed mesh is exactly a section of the torus with major radius ρ and
/// minor radius `tube_radius` (every ring a rigid motion of the straight ring): ring `j`
/// at arc length `s` lies in the plane at angle `s / ρ` about that axis. Linear blend
/// skinning between two joints would collapse the bend; one joint per ring does not.
pub fn bent_tube(
    tube_radius: f32,
    bend_radius: f32,
    bend_angle: f32,
    segments: usize,
    rings: usize,
) -> Rigged {
    let nv = rings.max(15);
    let nu = segments.max(3);
    let (r, rho, theta) = (
        f64::from(tube_radius),
        f64::from(bend_radius),
        f64::from(bend_angle),
    );
    let length = rho * theta;
    let h = length / nv as f64;
    let mesh = param_grid(nu, nv, true, false, |i, j| {
        let u = TAU * i as f64 / nu as f64;
        let n = DVec3::new(u.cos(), 0.0, u.sin());
        (DVec3::new(0.0, h * j as f64, 0.0) + r * n, n)
    });
    // Node 0 holds the mesh; joint j is node j + 1, ring j's joint.
    let mut nodes = vec![node("tube", None, Vec3::ZERO)];
    for j in 0..=nv {
        let (parent, t) = if j == 0 {
            (None, Vec3::ZERO)
        } else {
            (Some(j), Vec3::new(0.0, h as f32, 0.0))
        };
        nodes.push(node(&format!("joint {j}"), parent, t));
    }
    let skin = Skin {
        name: Some("tube".into()),
        joints: (1..=nv + 1).collect(),
        inverse_bind: (0..=nv)
            .map(|j| Mat4::from_translation(Vec3::new(0.0, -(h * j as f64) as f32, 0.0)))
            .collect(),
    };
    // A joint's local transform on an arc of radius ρ turning by Δ per joint: the chord
    // ρ (cos Δ − 1, sin Δ, 0) in the parent's frame, then the turn Rz(Δ).
    let local = |delta: f64| -> (Vec<f32>, Vec<f32>) {
        if delta == 0.0 {
            return (vec![0.0, h as f32, 0.0], Quat::IDENTITY.to_array().to_vec());
        }
        let rho = h / delta;
        let t = vec![
            (rho * (delta.cos() - 1.0)) as f32,
            (rho * delta.sin()) as f32,
            0.0,
        ];
        (t, Quat::from_rotation_z(delta as f32).to_array().to_vec())
    };
    let delta = theta / nv as f64;
    let keys = [local(0.0), local(delta / 2.0), local(delta)];
    let times = [0.0, 0.5, 1.0];
    let mut channels = Vec::new();
    for j in 1..=nv {
        let t: Vec<Vec<f32>> = keys.iter().map(|k| k.0.clone()).collect();
        let q: Vec<Vec<f32>> = keys.iter().map(|k| k.1.clone()).collect();
        channels.extend(channel(j + 1, Property::Translation, &times, &t));
        channels.extend(channel(j + 1, Property::Rotation, &times, &q));
    }
    let influences: Vec<Vec<(u16, f32)>> = (0..mesh.vertex_count())
        .map(|v| vec![((v / (nu + 1)) as u16, 1.0)])
        .collect();
    let clip = Clip::new(Some("bend".into()), channels);
    let rig = Rig::skinned(&mesh, nodes, skin, &influences, vec![clip]);
    Rigged { mesh, rig }
}

/// A geodesic sphere of radius 1 and `frequency` (about `10·f²` vertices) centred at
/// `(0, 2, 0)`, bound to one joint there; its clip `"stretch"` (1 s, LINEAR) scales the
/// joint from 1 to `(a, b, c)`, so at `t = 1` the posed mesh is the ellipsoid
/// `x²/a² + (y − 2)²/b² + z²/c² = 1` (as [`super::ellipsoid`] builds it, moved by
/// `(0, 2, 0)`), with the ellipsoid's normals.
pub fn stretched_sphere(a: f32, b: f32, c: f32, frequency: usize) -> Rigged {
    let centre = Vec3::new(0.0, 2.0, 0.0);
    let mut mesh = geodesic_sphere(frequency, 1.0);
    for p in &mut mesh.positions {
        *p += centre;
    }
    let nodes = vec![
        node("sphere", None, Vec3::ZERO),
        node("joint", None, centre),
    ];
    let skin = Skin {
        name: Some("sphere".into()),
        joints: vec![1],
        inverse_bind: vec![Mat4::from_translation(-centre)],
    };
    let clip = Clip::new(
        Some("stretch".into()),
        channel(
            1,
            Property::Scale,
            &[0.0, 1.0],
            &[vec![1.0, 1.0, 1.0], vec![a, b, c]],
        )
        .into_iter()
        .collect(),
    );
    let influences = vec![vec![(0u16, 1.0f32)]; mesh.vertex_count()];
    let rig = Rig::skinned(&mesh, nodes, skin, &influences, vec![clip]);
    Rigged { mesh, rig }
}

/// A capped square bar (`width` across, `length` along y, centred at the origin,
/// `rings` rows of quads) between two joints at its ends, weights blending linearly
/// along y. Its clip `"twist"` (1 s, LINEAR through 90° at `t = 0.5`) turns the top
/// joint by 180° about y: the linear blend skinning "candy wrapper", whose middle
/// collapses onto the axis. No closed-form target; posing must stay finite.
pub fn twisted_bar(width: f32, length: f32, rings: usize) -> Rigged {
    let half = 0.5 * length;
    let mesh = super::cylinder(
        width * std::f32::consts::FRAC_1_SQRT_2,
        length,
        4,
        rings.max(2),
        true,
    );
    let nodes = vec![
        node("bar", None, Vec3::ZERO),
        node("bottom", None, Vec3::new(0.0, -half, 0.0)),
        node("top", Some(1), Vec3::new(0.0, length, 0.0)),
    ];
    let skin = Skin {
        name: Some("bar".into()),
        joints: vec![1, 2],
        inverse_bind: vec![
            Mat4::from_translation(Vec3::new(0.0, half, 0.0)),
            Mat4::from_translation(Vec3::new(0.0, -half, 0.0)),
        ],
    };
    let q = |deg: f32| Quat::from_rotation_y(deg.to_radians()).to_array().to_vec();
    let clip = Clip::new(
        Some("twist".into()),
        channel(
            2,
            Property::Rotation,
            &[0.0, 0.5, 1.0],
            &[q(0.0), q(90.0), q(180.0)],
        )
        .into_iter()
        .collect(),
    );
    let influences = two_joints(&mesh, |p| ((p.y + half) / length).clamp(0.0, 1.0));
    let rig = Rig::skinned(&mesh, nodes, skin, &influences, vec![clip]);
    Rigged { mesh, rig }
}

/// Any mesh given a two-joint rig, for measuring what posing costs at a mesh's own
/// size: a base joint at its lowest point and a top joint at its highest (along y),
/// weights blending smoothly with height, and a clip `"sway"` (2 s, LINEAR) that leans
/// the top joint 15° to each side about z and back. No closed-form target.
pub fn swaying(mesh: Mesh) -> Rigged {
    let (lo, hi) = mesh.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let (lo, hi) = if lo.x <= hi.x {
        (lo, hi)
    } else {
        (Vec3::ZERO, Vec3::Y)
    };
    let height = (hi.y - lo.y).max(f32::MIN_POSITIVE);
    let base = Vec3::new(0.5 * (lo.x + hi.x), lo.y, 0.5 * (lo.z + hi.z));
    let middle = base + Vec3::new(0.0, 0.5 * height, 0.0);
    let nodes = vec![
        node("mesh", None, Vec3::ZERO),
        node("base", None, base),
        node("top", Some(1), middle - base),
    ];
    let skin = Skin {
        name: Some("sway".into()),
        joints: vec![1, 2],
        inverse_bind: vec![
            Mat4::from_translation(-base),
            Mat4::from_translation(-middle),
        ],
    };
    let q = |deg: f32| Quat::from_rotation_z(deg.to_radians()).to_array().to_vec();
    let clip = Clip::new(
        Some("sway".into()),
        channel(
            2,
            Property::Rotation,
            &[0.0, 0.5, 1.5, 2.0],
            &[q(0.0), q(15.0), q(-15.0), q(0.0)],
        )
        .into_iter()
        .collect(),
    );
    let influences = two_joints(&mesh, |p| {
        // Smoothstep across the middle third of the height.
        let s = ((p.y - lo.y) / height * 3.0 - 1.0).clamp(0.0, 1.0);
        s * s * (3.0 - 2.0 * s)
    });
    let rig = Rig::skinned(&mesh, nodes, skin, &influences, vec![clip]);
    Rigged { mesh, rig }
}

/// Per vertex of `mesh`, joints 0 and 1 weighted `1 − w` and `w` (`w = top(p)`), zero
/// weights left out.
fn two_joints(mesh: &Mesh, top: impl Fn(Vec3) -> f32) -> Vec<Vec<(u16, f32)>> {
    mesh.positions
        .iter()
        .map(|&p| {
            let w1 = top(p);
            [(0u16, 1.0 - w1), (1u16, w1)]
                .into_iter()
                .filter(|x| x.1 > 0.0)
                .collect()
        })
        .collect()
}
