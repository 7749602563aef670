//! What the GPU-against-CPU tests share: the fixtures, the frames they compare on and the
//! bounding radius their tolerances are relative to.
#![allow(dead_code, clippy::unwrap_used)]

use glam::{Mat4, Vec3};
use npr_geometry::{LightEye, Mesh, generate};

/// A mesh of the repository's `fixtures/meshes`.
pub fn fixture(name: &str) -> Mesh {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/meshes");
    npr_geometry::io::load(dir.join(name)).unwrap().mesh
}

/// Lights and transforms: two directions, a near point light and eye, and point lights
/// under a non-uniform scale and a shear (the world-space half vector of the shader).
pub fn frames(radius: f32) -> Vec<(LightEye, Mat4)> {
    let d = |x: f32, y: f32, z: f32| Vec3::new(x, y, z).normalize();
    let r = radius;
    let turn = Mat4::from_rotation_y(0.6) * Mat4::from_rotation_x(-0.3);
    let shear = Mat4::from_cols_array(&[
        1.0, 0.0, 0.0, 0.0, 0.35, 1.0, 0.0, 0.0, 0.0, 0.2, 1.0, 0.0, 0.1, -0.2, 0.3, 1.0,
    ]);
    vec![
        (
            LightEye::Directions {
                to_light: d(0.3, 0.8, 0.5),
                to_eye: d(0.0, 0.0, 1.0),
            },
            Mat4::IDENTITY,
        ),
        (
            LightEye::Directions {
                to_light: d(-0.7, 0.2, 0.4),
                to_eye: d(0.2, 0.1, 1.0),
            },
            turn,
        ),
        (
            LightEye::Positions {
                light: Vec3::new(1.5 * r, 2.0 * r, 2.5 * r),
                eye: Vec3::new(0.0, 0.3 * r, 3.0 * r),
            },
            turn,
        ),
        (
            LightEye::Positions {
                light: Vec3::new(-2.0 * r, 1.0 * r, 2.0 * r),
                eye: Vec3::new(0.5 * r, 0.0, 3.5 * r),
            },
            Mat4::from_scale(Vec3::new(1.3, 0.8, 1.0)) * turn,
        ),
        (
            LightEye::Positions {
                light: Vec3::new(2.0 * r, 2.0 * r, 1.0 * r),
                eye: Vec3::new(0.0, 0.0, 3.0 * r),
            },
            shear,
        ),
    ]
}

pub fn bounding_radius(mesh: &Mesh) -> f32 {
    let (lo, hi) = mesh.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let c = 0.5 * (lo + hi);
    mesh.positions
        .iter()
        .map(|p| p.distance(c))
        .fold(0.0, f32::max)
}

/// The meshes both GPU comparisons run on: procedural surfaces (smooth, jittered, the
/// paper's knot) and the scanned fixtures.
pub fn meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("torus", generate::torus(1.0, 0.35, 64, 32)),
        (
            "jittered torus",
            generate::torus_jittered(1.0, 0.35, 48, 24, 0.3, 7),
        ),
        ("ellipsoid", generate::ellipsoid(0.7, 1.4, 1.0, 24)),
        ("paper knot", generate::paper_knot()),
        ("bunny", fixture("stanford-bunny.obj")),
        ("spot", fixture("spot.obj")),
        ("hammer", fixture("hammer.obj")),
    ]
}

/// `z = 0.3 sin(x) sin(y)` over `periods` periods a side, `per` quads a period.
pub fn egg_crate(periods: usize, per: usize) -> npr_geometry::Mesh {
    let n = periods * per;
    let step = std::f32::consts::TAU / per as f32;
    let mut mesh = npr_geometry::Mesh::default();
    for j in 0..=n {
        for i in 0..=n {
            // Half a step off, so no crest or saddle sits on a vertex.
            let (x, y) = ((i as f32 + 0.37) * step, (j as f32 + 0.29) * step);
            mesh.positions
                .push(Vec3::new(x, y, 0.3 * x.sin() * y.sin()));
            mesh.uvs.push(glam::Vec2::ZERO);
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            mesh.indices.extend([a, b, c, a, c, d]);
        }
    }
    mesh.normals = vec![Vec3::Z; mesh.positions.len()];
    mesh.recompute_normals();
    mesh
}

/// The largest difference of two records' matrices and vectors, each relative to the
/// largest entry of the CPU's.
pub fn record_gap(a: &npr_specular::gpu::ProjectorGpu, b: &npr_specular::gpu::ProjectorGpu) -> f32 {
    let m = |p: &npr_specular::gpu::ProjectorGpu| p.tex_from_world.concat();
    let scale = m(b).iter().fold(0f32, |s, x| s.max(x.abs())).max(1e-12);
    let matrix = m(a)
        .iter()
        .zip(m(b))
        .fold(0f32, |s, (x, y)| s.max((x - y).abs() / scale));
    let vectors = [
        (a.axis_u, b.axis_u),
        (a.axis_v, b.axis_v),
        (a.normal, b.normal),
        (a.tint, b.tint),
        (a.params, b.params),
    ]
    .iter()
    .flat_map(|(x, y)| x.iter().zip(y).map(|(p, q)| (p - q).abs()))
    .fold(0f32, f32::max);
    matrix.max(vectors)
}

/// A light turning over the object while it turns too, eye fixed: frame `step` of the
/// twin tests' turn (0.12 rad of light and 0.012 of object a frame).
pub fn turn(radius: f32, step: usize) -> (LightEye, Mat4) {
    let a = step as f32 * 0.12;
    let light_eye = LightEye::Positions {
        light: Vec3::new(
            2.0 * radius * a.cos(),
            1.5 * radius,
            2.0 * radius * a.sin() + radius,
        ),
        eye: Vec3::new(0.0, 0.2 * radius, 3.0 * radius),
    };
    (light_eye, Mat4::from_rotation_y(0.1 * a))
}
