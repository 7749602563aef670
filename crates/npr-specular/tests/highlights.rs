//! CPU tests of the highlight set: the sphere's single highlight and its projector
//! (Eq. (7)–(8)), visibility (§4.2), frame coherence, and bad input.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat3, Mat4, Vec2, Vec3};
use npr_geometry::{CurvatureOptions, LightEye, Mesh, NormalInterpolation, generate};
use npr_specular::{HighlightSet, ProjectorControls, projector::frustum_size};

fn set_for(mesh: &Mesh) -> HighlightSet {
    HighlightSet::new(mesh, &CurvatureOptions::default()).expect("set")
}

fn concat(a: &Mesh, b: &Mesh) -> Mesh {
    let mut m = a.clone();
    let off = m.positions.len() as u32;
    m.positions.extend(&b.positions);
    m.normals.extend(&b.normals);
    m.uvs.extend(&b.uvs);
    m.indices.extend(b.indices.iter().map(|i| i + off));
    m
}

#[test]
fn sphere_has_one_highlight_at_the_analytic_point_with_eq8_sizes() {
    let r = 2.0;
    let mut set = set_for(&generate::icosphere(4, r));
    set.tuning.size_cap_radius = Some(100.0);
    let dir = Vec3::new(0.3, 0.5, 0.8).normalize();
    let l = Vec3::new(0.8, 0.4, 0.2).normalize();
    let h = (dir + l).normalize();
    let hs = set
        .update(
            LightEye::Directions {
                to_light: l,
                to_eye: dir,
            },
            Mat4::IDENTITY,
        )
        .to_vec();
    assert_eq!(hs.len(), 1, "{hs:?}");
    let c = &hs[0];
    // The analytic centre is R·Ĥ.
    let err = c.centre.position_world.distance(h * r);
    assert!(err < 2e-3 * r, "centre off by {err}");
    let p = &c.projector;
    for (a, b) in [
        (p.axis_u, p.axis_v),
        (p.axis_u, p.normal),
        (p.axis_v, p.normal),
    ] {
        assert!(a.dot(b).abs() < 1e-4);
    }
    for a in [p.axis_u, p.axis_v, p.normal] {
        assert!((a.length() - 1.0).abs() < 1e-4);
    }
    assert!(
        (p.axis_u.cross(p.axis_v) - p.normal).length() < 1e-4,
        "right-handed"
    );
    // Eq. (8) for κ = 1/R on both axes, full width s, half extent s/2.
    let sigma = ProjectorControls::default().sigma;
    let want = frustum_size(1.0 / r, sigma, 100.0) * 0.5;
    for got in [p.half_extent.x, p.half_extent.y] {
        assert!(
            (got - want).abs() < 0.02 * want,
            "half extent {got} vs {want}"
        );
    }
    assert!((want - (1.0 - sigma * sigma).sqrt() * r).abs() < 1e-5);
}

#[test]
fn rigid_motion_moves_the_highlight_with_the_object() {
    let mesh = generate::icosphere(4, 1.0);
    let mut set = set_for(&mesh);
    let le = LightEye::Directions {
        to_light: Vec3::Z,
        to_eye: Vec3::Z,
    };
    let m = Mat4::from_translation(Vec3::new(3.0, -1.0, 2.0)) * Mat4::from_rotation_y(0.7);
    let hs = set.update(le, m).to_vec();
    assert_eq!(hs.len(), 1);
    let want = Vec3::new(3.0, -1.0, 3.0);
    assert!(
        hs[0].centre.position_world.distance(want) < 5e-3,
        "{}",
        hs[0].centre.position_world
    );
}

/// §4.2: receivers are reachable from the centre, inside the frustum, and face the
/// projector. On nested shells the frustum also covers the inner shell; on a thin torus it
/// covers the tube's underside; neither may receive.
#[test]
fn visibility_keeps_only_the_connected_front_part() {
    // Nested shells: outer R = 1, inner R = 0.85 (both outward).
    let outer = generate::icosphere(4, 1.0);
    let inner = generate::icosphere(4, 0.85);
    let outer_faces = outer.indices.len() / 3;
    let shells = concat(&outer, &inner);
    let mut set = set_for(&shells);
    let le = LightEye::Directions {
        to_light: Vec3::Z,
        to_eye: Vec3::Z,
    };
    let hs = set.update(le, Mat4::IDENTITY).to_vec();
    assert_eq!(hs.len(), 2, "one centre per shell");
    let topo = set.topology();
    for h in &hs {
        let on_outer = (h.centre.face as usize) < outer_faces;
        let faces = &set.receiver_faces()[h.receivers.clone()];
        assert!(faces.len() > 10);
        assert!(
            faces
                .iter()
                .all(|&f| ((f as usize) < outer_faces) == on_outer),
            "receivers cross shells"
        );
        // The frustum alone would also take the other shell: the test can fail.
        let other_in_frustum = (0..topo.face_count())
            .filter(|&f| (f < outer_faces) != on_outer)
            .any(|f| {
                let t = topo.triangles[f].map(|v| topo.positions[v as usize]);
                npr_specular::cpu::visibility::triangle_touches_frustum(&h.projector, t)
            });
        assert!(
            other_in_frustum,
            "test setup: the frustum should reach the other shell"
        );
    }

    // Thin torus seen from above with a point light: underside faces are in the frustum's
    // depth range but face away.
    let torus = generate::torus(1.0, 0.12, 96, 24);
    let mut set = set_for(&torus);
    let le = LightEye::Positions {
        light: Vec3::new(0.4, 3.0, 0.3),
        eye: Vec3::new(-0.2, 3.0, 0.5),
    };
    let hs = set.update(le, Mat4::IDENTITY).to_vec();
    assert!(!hs.is_empty());
    let topo = set.topology();
    // A highlight drawn as pieces has no receivers of its own (its pieces have them).
    for h in hs.iter().filter(|h| h.pieces == 0) {
        let faces = &set.receiver_faces()[h.receivers.clone()];
        assert!(!faces.is_empty());
        for &f in faces {
            assert!(topo.face_normals[f as usize].dot(h.projector.normal) > 0.0);
        }
        let back_in_frustum = (0..topo.face_count()).any(|f| {
            let t = topo.triangles[f].map(|v| topo.positions[v as usize]);
            topo.face_normals[f].dot(h.projector.normal) < -0.5
                && npr_specular::cpu::visibility::triangle_touches_frustum(&h.projector, t)
        });
        assert!(
            back_in_frustum,
            "test setup: the frustum should reach the underside"
        );
    }

    // Folded sheet: a plane, and a second plane just below it facing down, joined at one
    // end. The lower layer is inside the frustum but faces away.
    let top = generate::plane(2.0, 2.0, 24, 24);
    let mut bottom = generate::plane(2.0, 2.0, 24, 24);
    let flip = Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0))
        * Mat4::from_rotation_z(std::f32::consts::PI);
    for p in &mut bottom.positions {
        *p = flip.transform_point3(*p);
    }
    for n in &mut bottom.normals {
        *n = Mat3::from_mat4(flip) * *n;
    }
    let sheet = concat(&top, &bottom);
    let top_faces = top.indices.len() / 3;
    let mut set = set_for(&sheet);
    let le = LightEye::Positions {
        light: Vec3::new(0.5, 1.0, 0.0),
        eye: Vec3::new(-0.5, 1.0, 0.0),
    };
    let hs = set.update(le, Mat4::IDENTITY).to_vec();
    let on_top: Vec<_> = hs
        .iter()
        .filter(|h| (h.centre.face as usize) < top_faces)
        .collect();
    assert_eq!(on_top.len(), 1, "{hs:?}");
    let faces = &set.receiver_faces()[on_top[0].receivers.clone()];
    assert!(faces.len() > 20);
    assert!(faces.iter().all(|&f| (f as usize) < top_faces));
}

/// Largest ratio of a step to the median of its neighbouring steps (±3 frames) along
/// each track: continuous motion, even accelerating, stays near 1; a jump does not. The
/// first and last two steps of a track are left out: centres are born and annihilate in
/// pairs at folds of the N = H map, where their speed diverges.
fn worst_jump(tracks: &std::collections::HashMap<(u64, u32), Vec<f32>>) -> f32 {
    let mut worst = 0f32;
    for steps in tracks.values() {
        for k in 2..steps.len().saturating_sub(2) {
            let mut window: Vec<f32> = (k.saturating_sub(3)..(k + 4).min(steps.len()))
                .filter(|&j| j != k)
                .map(|j| steps[j])
                .collect();
            if window.len() < 4 {
                continue;
            }
            window.sort_by(f32::total_cmp);
            let med = window[window.len() / 2];
            let ratio = if med > 0.0 {
                steps[k] / med
            } else if steps[k] > 1e-6 {
                f32::INFINITY
            } else {
                0.0
            };
            worst = worst.max(ratio);
        }
    }
    worst
}

/// Frame coherence on the paper's 2,880-face knot rotating 360° in 1° steps: no matched
/// centre jumps (a step over 3× the median of its neighbouring steps), while snapping each
/// centre to its face's best vertex (§3.1's rejected per-vertex approach) jumps.
///
/// The step is compared with its neighbours, not with the track's global median: a
/// centre's speed is the rotation speed over the curvature along its path, which varies
/// about 10× along the knot's tube (measured: largest/median step up to 10 on one track),
/// and diverges where two centres are born or annihilate together.
/// (worst jump of the centres, worst jump of the vertex-snapped baseline, matched steps,
/// mean highlight count) over the 360° rotation.
fn knot_rotation(interpolation: NormalInterpolation) -> (f32, f32, usize, f32) {
    let mesh = generate::paper_knot();
    assert_eq!(mesh.indices.len() / 3, 2880);
    let mut set = set_for(&mesh);
    set.set_interpolation(interpolation);
    let to_light = Vec3::new(0.5, 0.6, 1.0).normalize();
    let to_eye = Vec3::Z;
    let h = (to_light + to_eye).normalize();
    let le = LightEye::Directions { to_light, to_eye };
    type Track = std::collections::HashMap<(u64, u32), Vec<f32>>;
    let mut segment: std::collections::HashMap<u64, u32> = Default::default();
    let mut prev: std::collections::HashMap<u64, (Vec3, Vec3)> = Default::default();
    let (mut tracks, mut snap_tracks): (Track, Track) = Default::default();
    let mut counts = Vec::new();
    for deg in 0..=360 {
        let m = Mat4::from_rotation_y((deg as f32).to_radians()) * Mat4::from_rotation_x(0.3);
        let hs = set.update(le, m).to_vec();
        counts.push(hs.iter().filter(|h| h.found && !h.peak).count());
        let topo = set.topology();
        let nm = Mat3::from_mat4(m);
        let mut now = std::collections::HashMap::new();
        // The N = H centres (a bright region without one has its centre at its maximum
        // of N·H instead, not what this measures).
        let nh_centre = |hl: &&npr_specular::Highlight| !hl.peak;
        for hl in hs.iter().filter(|h| h.found).filter(nh_centre) {
            let t = topo.triangles[hl.centre.face as usize];
            let best = t
                .iter()
                .max_by(|a, b| {
                    let da = (nm * topo.vertex_normals[**a as usize]).dot(h);
                    let db = (nm * topo.vertex_normals[**b as usize]).dot(h);
                    da.total_cmp(&db)
                })
                .map(|v| m.transform_point3(topo.positions[*v as usize]))
                .unwrap();
            now.insert(hl.id, (hl.centre.position_world, best));
        }
        for (id, (p, snap)) in &now {
            // A highlight whose centre was not an N = H point in the last frame starts a
            // new track: its N = H centres were just born (at a fold, in a pair).
            let key = (*id, *segment.entry(*id).or_insert(0));
            if let Some((q, qs)) = prev.get(id) {
                tracks.entry(key).or_default().push(p.distance(*q));
                snap_tracks.entry(key).or_default().push(snap.distance(*qs));
            }
        }
        for id in prev.keys() {
            if !now.contains_key(id) {
                *segment.entry(*id).or_insert(0) += 1;
            }
        }
        prev = now;
    }
    let steps: usize = tracks.values().map(Vec::len).sum();
    let avg = counts.iter().sum::<usize>() as f32 / counts.len() as f32;
    (worst_jump(&tracks), worst_jump(&snap_tracks), steps, avg)
}

#[test]
fn knot_rotation_is_coherent_and_vertex_snapping_is_not() {
    let (smooth, snapped, steps, avg) = knot_rotation(NormalInterpolation::Curvature);
    assert!(steps > 1000, "{steps} matched steps");
    assert!(
        smooth <= 3.0,
        "a matched centre jumped: step {smooth:.2}x its neighbours' median"
    );
    assert!(
        snapped > 3.0,
        "the vertex-snapping baseline should jump, worst {snapped:.2}"
    );
    assert!((3.0..=12.0).contains(&avg), "mean highlight count {avg}");
    // The paper's linear normal interpolation (Eq. (4)) is continuous but its speed jumps
    // at face crossings: it must measure worse than the curvature-blended field.
    let (linear, ..) = knot_rotation(NormalInterpolation::Linear);
    assert!(
        linear > smooth,
        "linear {linear:.2} vs curvature-blended {smooth:.2}"
    );
    eprintln!(
        "knot: {steps} steps, worst jump {smooth:.2} (paper's linear field {linear:.2}, \
         vertex snapping {snapped:.2}), mean count {avg:.2}"
    );
}

/// Every float the GPU would receive for the set's highlights is finite; returns how many
/// highlights there are.
fn check_finite(set: &HighlightSet) -> usize {
    for h in set.highlights() {
        let p = &h.projector;
        assert!(p.tex_from_world.is_finite() && p.normal.is_finite() && h.opacity.is_finite());
        let gpu = npr_specular::gpu::projector_gpu(h, h.controls.texture_layer, false);
        let floats = [gpu.axis_u, gpu.axis_v, gpu.normal, gpu.tint, gpu.params];
        assert!(
            gpu.tex_from_world
                .iter()
                .chain(&floats)
                .flatten()
                .all(|x| x.is_finite()),
            "{gpu:?}"
        );
    }
    set.highlights().len()
}

#[test]
fn bad_input_gives_no_panic_and_no_nan() {
    let mesh = generate::icosphere(3, 1.0);
    let mut set = set_for(&mesh);
    for le in [
        LightEye::Directions {
            to_light: Vec3::ZERO,
            to_eye: Vec3::Z,
        },
        LightEye::Directions {
            to_light: Vec3::NAN,
            to_eye: Vec3::Z,
        },
        LightEye::Positions {
            light: Vec3::ZERO,
            eye: Vec3::new(0.0, 0.0, 5.0),
        },
        LightEye::Positions {
            light: Vec3::splat(f32::INFINITY),
            eye: Vec3::new(0.0, 0.0, 5.0),
        },
    ] {
        set.reset();
        set.update(le, Mat4::IDENTITY);
        assert_eq!(check_finite(&set), 0, "{le:?} should give no highlight");
    }
    // A singular object transform: no highlight, no NaN.
    set.update(
        LightEye::Directions {
            to_light: Vec3::Z,
            to_eye: Vec3::Z,
        },
        Mat4::ZERO,
    );
    assert_eq!(check_finite(&set), 0);
    // Light exactly opposite the eye: H = 0, so there is no N = H point anywhere.
    set.reset();
    set.update(
        LightEye::Directions {
            to_light: -Vec3::Z,
            to_eye: Vec3::Z,
        },
        Mat4::IDENTITY,
    );
    assert_eq!(check_finite(&set), 0);
    // The light behind the surface point the eye sees: the centre sits where N = H,
    // on the silhouette side; still one finite highlight.
    set.reset();
    let le = LightEye::Directions {
        to_light: Vec3::new(0.0, 0.3, -1.0),
        to_eye: Vec3::Z,
    };
    set.update(le, Mat4::IDENTITY);
    assert_eq!(check_finite(&set), 1);
    // Flat mesh: κ = 0, the size falls back to 2r; exactly one highlight.
    let mut flat = set_for(&generate::plane(2.0, 2.0, 10, 10));
    let le = LightEye::Positions {
        light: Vec3::new(0.3, 1.0, 0.0),
        eye: Vec3::new(-0.3, 1.0, 0.0),
    };
    flat.update(le, Mat4::IDENTITY);
    assert_eq!(check_finite(&flat), 1);
    // Degenerate faces: still a highlight, finite.
    let mut degenerate = generate::icosphere(2, 1.0);
    degenerate.indices[4] = degenerate.indices[3];
    let mut set = set_for(&degenerate);
    set.update(
        LightEye::Directions {
            to_light: Vec3::Z,
            to_eye: Vec3::Z,
        },
        Mat4::IDENTITY,
    );
    assert_eq!(check_finite(&set), 1);
    assert!(HighlightSet::new(&Mesh::default(), &CurvatureOptions::default()).is_err());
}

/// A highlight that is lost while the OBJECT moves (not only the light) fades out where it
/// was on the object: its projector and its receivers follow the model matrix.
#[test]
fn a_fading_highlight_follows_object_motion() {
    let mut set = set_for(&generate::torus(1.0, 0.4, 64, 32));
    set.tuning.fade_frames = 4;
    let (to_light, to_eye) = (Vec3::new(0.3, 0.9, 0.4).normalize(), Vec3::Z);
    let first = set
        .update(LightEye::Directions { to_light, to_eye }, Mat4::IDENTITY)
        .to_vec();
    assert!(!first.is_empty());
    // The object moves and turns, and the light goes where no centre exists (L = -V):
    // every highlight is lost and fades.
    let world_from_object =
        Mat4::from_translation(Vec3::new(3.0, -1.0, 0.5)) * Mat4::from_rotation_y(0.7);
    let lost = LightEye::Directions {
        to_light: -to_eye,
        to_eye,
    };
    for frame in 1..4 {
        let fading = set.update(lost, world_from_object).to_vec();
        assert_eq!(
            fading.len(),
            first.len(),
            "frame {frame}: all fade, none vanish"
        );
        for h in &fading {
            assert!(!h.found && h.opacity < 1.0);
            let on_object = world_from_object.transform_point3(h.centre.position_object);
            let moved = h.centre.position_world.distance(on_object);
            assert!(moved < 1e-4, "frame {frame}: centre left behind by {moved}");
            let p = h.projector.anchor_world.distance(on_object);
            assert!(p < 1e-3, "frame {frame}: projector left behind by {p}");
            // The footprint's offset from the centre (the measured region's centroid)
            // moves rigidly with it.
            let offset = h.projector.centre_world.distance(h.projector.anchor_world);
            let want = h.footprint.offset.length();
            assert!(
                (offset - want).abs() < 1e-3,
                "frame {frame}: footprint offset {offset} vs {want}"
            );
            let n = world_from_object.transform_vector3(h.centre.normal_object);
            assert!(h.centre.normal_world.dot(n.normalize()) > 0.9999);
            assert!(!h.receivers.is_empty(), "frame {frame}: no receivers");
        }
    }
}

/// The N = H search solves on the normals the mesh is shaded with: a sphere whose normals
/// are all tilted by 25° about z has its highlight where the TILTED normal faces H, not
/// where the geometric (area-weighted) normal does.
#[test]
fn the_centre_lands_on_the_peak_of_the_mesh_normals() {
    let mut mesh = generate::icosphere(4, 1.0);
    let tilt = Mat3::from_rotation_z(25f32.to_radians());
    for n in &mut mesh.normals {
        *n = tilt * *n;
    }
    let mut set = set_for(&mesh);
    let h = Vec3::Y;
    let hs = set
        .update(
            LightEye::Directions {
                to_light: h,
                to_eye: h,
            },
            Mat4::IDENTITY,
        )
        .to_vec();
    assert_eq!(hs.len(), 1, "{hs:?}");
    // Shaded peak: tilt · p = H, p = tiltᵀ H; the geometric peak would be H itself.
    let shaded_peak = tilt.transpose() * h;
    let c = hs[0].centre.position_object;
    assert!(
        c.distance(shaded_peak) < 0.01,
        "centre {c} is {} from the shaded peak {shaded_peak} ({} from the geometric one)",
        c.distance(shaded_peak),
        c.distance(h)
    );
    assert!(hs[0].centre.normal_object.dot(h) > 0.9999);
}

#[test]
fn whole_runs_receive_exactly_the_faces_of_the_face_by_face_search() {
    // `receivers_within_clustered` takes connected runs of faces whole where they face
    // the projector and sit inside its frustum: it must receive exactly the faces of the
    // face-by-face §4.2 search, for every highlight of a turning dense sphere and the
    // bunny (locality-ordered as `npr` loads them, and in file order), for the paper's
    // N·N_max > 0 and for our normal limits.
    use npr_specular::cpu::visibility::{
        FaceClusters, VisibilityScratch, receivers_within, receivers_within_clustered,
    };
    let path = format!(
        "{}/../../fixtures/meshes/stanford-bunny.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    let bunny = npr_geometry::load_obj(&path).unwrap();
    // A dense sphere: its one highlight spans many patches.
    let sphere = generate::icosphere(6, 1.0);
    let mut whole_runs = 0usize;
    for (name, mesh) in [
        (
            "bunny",
            npr_geometry::locality::reorder_for_locality(&bunny).mesh,
        ),
        ("bunny, file order", bunny.clone()),
        (
            "sphere",
            npr_geometry::locality::reorder_for_locality(&sphere).mesh,
        ),
    ] {
        let mut set = set_for(&mesh);
        let topo = set.topology().clone();
        let clusters = FaceClusters::new(&topo);
        let (lo, hi) = topo.positions.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
        let normalize = Mat4::from_scale(Vec3::splat(1.0 / r)) * Mat4::from_translation(-c);
        let (mut a, mut b) = (VisibilityScratch::default(), VisibilityScratch::default());
        let mut checked = 0;
        for frame in 0..8 {
            // Frusta of several sizes and offsets (§3.4 controls), so that their sides cut
            // through patches.
            set.tuning.controls.scale = Vec2::splat(0.6 + 0.4 * frame as f32);
            set.tuning.controls.translate =
                Vec2::new(0.3 * (frame as f32).sin(), 0.2 * frame as f32 - 0.7);
            set.tuning.controls.rotate_rad = 0.4 * frame as f32;
            let world = Mat4::from_rotation_y((frame as f32 * 20.0).to_radians()) * normalize;
            let le = LightEye::Positions {
                light: Vec3::new(20.0, 30.0, 50.0),
                eye: Vec3::new(0.0, 0.3, 3.0),
            };
            set.update(le, world);
            for h in set.highlights() {
                for min_cos in [0.0, 0.3, 0.8] {
                    let (mut x, mut y) = (Vec::new(), Vec::new());
                    receivers_within(
                        &topo,
                        world,
                        &h.projector,
                        h.centre.face,
                        min_cos,
                        &mut a,
                        &mut x,
                    );
                    receivers_within_clustered(
                        &topo,
                        &clusters,
                        world,
                        &h.projector,
                        h.centre.face,
                        min_cos,
                        &mut b,
                        &mut y,
                    );
                    whole_runs += b.runs_taken();
                    x.sort_unstable();
                    y.sort_unstable();
                    assert_eq!(
                        x, y,
                        "{name} frame {frame} highlight {} min_cos {min_cos}",
                        h.id
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 0, "{name}: no highlight");
    }
    // The dense sphere's highlight covers whole patches: the shortcut is taken.
    assert!(whole_runs > 100, "{whole_runs} patches taken whole");
}

/// A bright region with no `N = H` point (a cap whose normals stop 2° short of `H`, like
/// a limb turned slightly away) still gets its highlight, at its brightest point, and
/// the footprint covers the region's side of the cap.
#[test]
fn a_bright_region_without_an_n_equals_h_point_gets_a_highlight() {
    let sphere = generate::icosphere(4, 1.0);
    let within = 20f32.to_radians().cos();
    let mut cap = sphere.clone();
    cap.indices = sphere
        .indices
        .chunks_exact(3)
        .filter(|t| t.iter().all(|&i| sphere.normals[i as usize].z >= within))
        .flatten()
        .copied()
        .collect();
    let mut set = set_for(&cap);
    let h = Vec3::new(0.0, 22f32.to_radians().sin(), 22f32.to_radians().cos());
    let le = LightEye::Directions {
        to_light: h,
        to_eye: h,
    };
    let hs = set.update(le, Mat4::IDENTITY).to_vec();
    assert_eq!(set.stats().centres, 0, "the cap holds no N = H point");
    assert_eq!(hs.len(), 1, "{hs:?}");
    let c = &hs[0].centre;
    // The brightest point of the cap: its rim towards H (normals 18–20° from z there).
    assert!(c.normal_world.dot(h) > 0.99, "{c:?}");
    assert!(hs[0].footprint.region_area > 0.0);
    // The region N·H ≥ 0.9 covers most of the cap; so does the footprint.
    let cap_radius = 20f32.to_radians().sin();
    let half = hs[0].footprint.half_extent;
    assert!(half.min_element() > 0.3 * cap_radius, "{half:?}");
    // Without the peak centres (the paper's sizing searches N = H only) nothing shows.
    set.tuning.sizing = npr_specular::HighlightSizing::Paper;
    set.reset();
    assert!(set.update(le, Mat4::IDENTITY).is_empty());
}
