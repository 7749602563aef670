//! Files without normals are split along their crease lines at load time
//! (`Mesh::split_at_creases`): each side of a hard edge gets its own normal, smooth
//! surfaces and scans without crease lines load exactly as before, rigged models stay whole.

use glam::Vec3;
use npr_geometry::io::{Format, LoadNote, load, load_bytes};
use npr_geometry::{Mesh, Topology, weld};

fn fixture(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/meshes")
        .join(name)
}

fn split_note(report: &[LoadNote]) -> Option<usize> {
    report.iter().find_map(|n| match n {
        LoadNote::CreasesSplit { vertices } => Some(*vertices),
        _ => None,
    })
}

/// The largest angle (degrees) between a non-degenerate face's normal and the render
/// normal of one of its corners.
fn worst_corner_angle(mesh: &Mesh) -> f32 {
    let topo = Topology::new(&weld(mesh));
    mesh.triangles()
        .enumerate()
        .filter(|&(f, _)| !topo.is_degenerate(f))
        .flat_map(|(f, t)| {
            let n = topo.face_normals[f];
            t.map(|v| n.angle_between(mesh.normals[v as usize]).to_degrees())
        })
        .fold(0.0, f32::max)
}

#[test]
fn a_cube_without_normals_gets_one_normal_per_face() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
               f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    let l = load_bytes(obj.as_bytes(), Format::Obj).unwrap();
    assert_eq!(split_note(&l.report), Some(16), "{:?}", l.report);
    assert_eq!(l.mesh.vertex_count(), 24);
    assert_eq!(l.mesh.triangle_count(), 12);
    l.mesh.validate().unwrap();
    assert!(worst_corner_angle(&l.mesh) < 1e-3);
    // Same surface: welding gives the 8 corners back.
    assert_eq!(weld(&l.mesh).positions.len(), 8);
}

#[test]
fn a_file_with_normals_is_not_split() {
    // The cube's faces with a normal per corner (here all +z, deliberately wrong):
    // a file's own normals are kept as they are.
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nvn 0 0 1\n\
               f 1//1 4//1 3//1 2//1\nf 5//1 6//1 7//1 8//1\nf 1//1 2//1 6//1 5//1\n\
               f 2//1 3//1 7//1 6//1\nf 3//1 4//1 8//1 7//1\nf 4//1 1//1 5//1 8//1\n";
    let l = load_bytes(obj.as_bytes(), Format::Obj).unwrap();
    assert_eq!(split_note(&l.report), None);
    assert_eq!(l.mesh.vertex_count(), 8);
    assert!(l.mesh.normals.iter().all(|&n| n == Vec3::Z));
}

#[test]
fn the_wing_nut_is_split_along_its_creases_only() {
    let l = load(fixture("wingnut.obj")).unwrap();
    let added = split_note(&l.report).expect("the wing nut has crease lines");
    assert_eq!(l.mesh.vertex_count(), 3047 + added);
    assert_eq!(l.mesh.triangle_count(), 6090);
    // Every corner's normal is its own side's: no render normal averages across a crease
    // of more than 50° (shared, the worst is past 45°).
    let mut shared = l.mesh.clone();
    shared.recompute_normals();
    let (split, whole) = (worst_corner_angle(&l.mesh), worst_corner_angle(&shared));
    assert!(split < whole, "{split}° vs {whole}°");
    assert!(whole > 45.0, "{whole}°");
    // Away from the creases the normals are those of the whole mesh, bit for bit.
    let same = l
        .mesh
        .normals
        .iter()
        .zip(&shared.normals)
        .filter(|(a, b)| a == b)
        .count();
    assert!(same >= 3047 - added, "{same} of {}", l.mesh.vertex_count());
}

#[test]
fn scans_and_rigged_models_load_as_before() {
    // The bunny has no normals and no crease line: the mesh is the plain smooth one.
    let l = load(fixture("stanford-bunny.obj")).unwrap();
    assert_eq!(split_note(&l.report), None);
    let mut plain = l.mesh.clone();
    plain.recompute_normals();
    assert_eq!(plain, l.mesh);
    // The hammer is a scan whose edges are rounded: nothing to split either.
    let l = load(fixture("hammer.obj")).unwrap();
    assert_eq!(split_note(&l.report), None);
    assert_eq!(l.mesh.vertex_count(), 30_082);
    // The Fox has no normals but a rig that recomputes smooth normals per pose: whole.
    let l = load(fixture("Fox.glb")).unwrap();
    assert!(l.rig.is_some());
    assert_eq!(split_note(&l.report), None);
    assert_eq!(l.mesh.vertex_count(), 1728);
}
