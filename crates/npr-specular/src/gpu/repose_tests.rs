//! A pose's tables made on the GPU against the CPU's of the same pose: rigged models
//! posed by their clips, at abstraction 0 (the mesh's normals, the field as measured) and
//! at the default abstraction (diffused and analysed again), each table the search, the
//! regions, the receivers and the highlight draw read compared entry by entry with the
//! CPU's set built on the same pose from the same field (`CurvaturePass`'s, read back: the
//! field itself is `npr-gpu`'s tests' business; how far it is from the CPU's on a pose is
//! reported here).

use super::*;
use crate::{gpu::CentreSearchPass, gpu::ReceiverPass, gpu::RegionPass};
use glam::Vec3;
use npr_geometry::{CurvatureOptions, CurvatureRadius};
use npr_gpu::testing::{copy_for_readback, read_mapped};

/// The tables of one mesh's search, regions and receivers, read back as `f32`.
struct Tables {
    solve: Vec<f32>,
    ordered: Vec<u32>,
    clusters: Vec<f32>,
    field: Vec<f32>,
    region_vertices: Vec<f32>,
    region_faces: Vec<u32>,
    positions: Vec<f32>,
    receiver_faces: Vec<u32>,
}

fn read(device: &wgpu::Device, queue: &wgpu::Queue, buffers: &[&wgpu::Buffer]) -> Vec<Vec<u8>> {
    let mut encoder = device.create_command_encoder(&Default::default());
    let copies: Vec<_> = buffers
        .iter()
        .map(|b| copy_for_readback(device, &mut encoder, b))
        .collect();
    queue.submit([encoder.finish()]);
    copies.iter().map(|c| read_mapped(device, c)).collect()
}

fn tables(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    (search, regions, receivers): (&SearchObject, &RegionObject, &ReceiverObject),
) -> Tables {
    let s = search.pose_tables();
    let r = regions.pose_tables();
    let q = receivers.pose_tables();
    let bytes = read(
        device,
        queue,
        &[s[0], s[1], s[2], s[3], r[0], r[1], q[0], q[1]],
    );
    let f = |i: usize| bytemuck::cast_slice::<u8, f32>(&bytes[i]).to_vec();
    let u = |i: usize| bytemuck::cast_slice::<u8, u32>(&bytes[i]).to_vec();
    Tables {
        solve: f(0),
        ordered: u(1),
        clusters: f(2),
        field: f(3),
        region_vertices: f(4),
        region_faces: u(5),
        positions: f(6),
        receiver_faces: u(7),
    }
}

/// The largest absolute difference of `a` and `b` over the entries `keep` selects
/// (index within a record of `width`).
fn worst(a: &[f32], b: &[f32], width: usize, keep: impl Fn(usize) -> bool) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .enumerate()
        .filter(|(i, _)| keep(i % width))
        .map(|(_, (x, y))| (x - y).abs())
        .fold(0.0, f32::max)
}

#[test]
fn a_pose_made_on_the_gpu_is_the_cpus_repose() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("a_pose_made_on_the_gpu_is_the_cpus_repose")
    else {
        return;
    };
    let (device, queue) = (&ctx.device, &ctx.queue);
    let models = [
        (
            "stretched sphere",
            npr_geometry::generate::stretched_sphere(1.0, 0.7, 0.5, 12),
        ),
        (
            "swaying knot",
            npr_geometry::generate::swaying(npr_geometry::generate::paper_knot()),
        ),
    ];
    let repose = ReposePass::new(device);
    let curvature_pass = npr_gpu::CurvaturePass::new(device);
    let (search_pass, region_pass, receiver_pass) = (
        CentreSearchPass::new(device),
        RegionPass::new(device),
        ReceiverPass::new(device),
    );
    let mut frame = FrameId::default();
    let mut checked = 0;
    for (name, rigged) in models {
        let (rest, rig) = (&rigged.mesh, &rigged.rig);
        let clip = &rig.clips()[0];
        let radius = CurvatureRadius::default();
        let options = CurvatureOptions {
            radius,
            ..CurvatureOptions::default()
        };
        for abstraction in [0.0, crate::DEFAULT_ABSTRACTION] {
            let set = HighlightSet::with_abstraction(rest, &options, abstraction).unwrap();
            let gpu = GpuMesh::upload(device, rest).unwrap();
            let mut curvature = curvature_pass
                .create_object_with_reach(device, &gpu, rest, radius, npr_gpu::POSE_REACH)
                .unwrap();
            let objects = |set: &HighlightSet| {
                (
                    search_pass.create_object_with_peaks(device, set).unwrap(),
                    region_pass.create_object(device, set).unwrap(),
                    receiver_pass
                        .create_object(device, set, &rest.indices)
                        .unwrap(),
                )
            };
            let on_gpu = objects(&set);
            let targets = ReposeTargets {
                search: &on_gpu.0,
                regions: &on_gpu.1,
                receivers: &on_gpu.2,
            };
            let mut object = repose
                .create_object(device, &set, (rest, &gpu), &curvature, targets)
                .unwrap();
            for t in [0.3, 0.7] {
                let posed = rig.pose_mesh(&rig.sample(clip, clip.duration() * t));
                gpu.write_vertices(queue, &posed).unwrap();
                frame = frame.next();
                let mut encoder = device.create_command_encoder(&Default::default());
                let c = curvature_pass
                    .prepare(queue, &mut curvature, &npr_gpu::CurvatureInput { frame })
                    .unwrap();
                curvature_pass.record(&mut encoder, &curvature, &c).unwrap();
                let prepared = repose
                    .prepare(queue, &mut object, &ReposeInput { frame })
                    .unwrap();
                repose.record(&mut encoder, &object, &prepared).unwrap();
                queue.submit([encoder.finish()]);
                let got = tables(device, queue, (&on_gpu.0, &on_gpu.1, &on_gpu.2));
                let field_bytes = read(device, queue, &[curvature.output()]);
                let field = curvature.decode(&field_bytes[0]);
                // The field on the pose is the CPU's repose's (the built pose's ball, in
                // world units): the 1e-3 of the largest |κ|, and 0.5° where the
                // principal curvatures differ.
                let same_ball = CurvatureOptions {
                    radius: CurvatureRadius::World(curvature.radius_world()),
                    ..options
                };
                let (_, _, measured) = npr_geometry::CurvatureField::for_mesh(&posed, &same_ball);
                let d = measured.difference(&field);
                assert!(
                    d.kappa <= 1e-3 && d.direction_deg <= 0.5 && d.validity == 0,
                    "{name} at t = {t}: the GPU's curvature on the pose is {d:?} from the CPU's"
                );
                let normals = read(device, queue, &[object.render_normals()]);
                let normals: &[[f32; 4]] = bytemuck::cast_slice(&normals[0]);
                // The CPU's set of this pose on the GPU's field, at the built pose's
                // diffusion steps (a repose keeps them, as the GPU does).
                let welded = npr_geometry::weld(&posed);
                let topology = npr_geometry::Topology::new(&welded);
                let steps = (abstraction, Some(set.diffusion_steps()));
                let cpu =
                    HighlightSet::from_field(&posed, (&welded, topology), &field, steps).unwrap();
                assert_eq!(cpu.diffusion_steps(), object.diffusion_steps());
                let order = on_gpu.0.face_order();
                let what = format!("{name} at abstraction {abstraction}, t = {t}");
                let render: Vec<[u32; 3]> = posed
                    .indices
                    .chunks(3)
                    .map(|t| [t[0], t[1], t[2]])
                    .collect();
                compare(&what, &got, (&cpu, &render), order);
                compare_normals(&what, normals, &cpu, &posed);
                // And the set at the abstraction's scale is the CPU's own repose's.
                let mut own = HighlightSet::with_abstraction(rest, &options, abstraction).unwrap();
                own.repose(&posed, &options).unwrap();
                let (over, worst) = field_gap(&cpu, &own);
                assert_eq!(
                    over, 0,
                    "{what}: the field at the abstraction's scale is {worst:.1e} of the largest |κ| from the CPU repose's"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 8);
}

fn half_diagonal(p: &[Vec3]) -> f32 {
    let (lo, hi) = p.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), q| {
        (lo.min(*q), hi.max(*q))
    });
    0.5 * (hi - lo).length()
}

/// The largest |κ| of a set's field.
fn largest_kappa(set: &HighlightSet) -> f32 {
    set.search()
        .field_floats()
        .iter()
        .filter(|f| f[11] > 0.5)
        .map(|f| f[3].abs().max(f[7].abs()))
        .fold(0.0f32, f32::max)
}

/// Vertices whose principal curvatures in `a` and `b` differ by more than 1e-3 of the
/// largest |κ|, and the largest difference as a fraction of it.
fn field_gap(a: &HighlightSet, b: &HighlightSet) -> (usize, f32) {
    let kappa = largest_kappa(b).max(1e-12);
    let gaps: Vec<f32> = a
        .search()
        .field_floats()
        .iter()
        .zip(b.search().field_floats())
        .map(|(x, y)| (x[3] - y[3]).abs().max((x[7] - y[7]).abs()) / kappa)
        .collect();
    (
        gaps.iter().filter(|g| **g > 1e-3).count(),
        gaps.iter().copied().fold(0.0, f32::max),
    )
}

fn floats(v: &[[f32; 4]]) -> Vec<f32> {
    v.iter().flatten().copied().collect()
}

fn bits(v: &[u32]) -> Vec<f32> {
    v.iter().map(|b| f32::from_bits(*b)).collect()
}

/// Each table against `cpu`'s records (`order`: the search's fixed face order; `render`: the
/// render mesh's triangles): within `f32` rounding of the same arithmetic (1e-5 of the
/// unit normals and the radius, 1e-4 of the largest |κ| for the shape operators, 1e-3
/// rad for the principal directions, signs included, 5e-4 rad for cones and slack),
/// indices exact.
fn compare(what: &str, got: &Tables, (cpu, render): (&HighlightSet, &[[u32; 3]]), order: &[u32]) {
    use crate::gpu::search::tables;
    let search = cpu.search();
    let kappa = largest_kappa(cpu).max(1e-6);
    let size = half_diagonal(&cpu.topology().positions);
    let solve = search.solve_vertices();
    let want: Vec<f32> = solve.iter().flat_map(|v| v.to_floats()).collect();
    let at = |w: usize, keep: &dyn Fn(usize) -> bool| worst(&got.solve, &want, w, keep);
    let checks = [
        ("solve positions", at(20, &|i| i < 4) / size, 1e-5),
        ("solve normals", at(20, &|i| (4..8).contains(&i)), 1e-5),
        ("shape operators", at(20, &|i| i >= 8) / kappa, 1e-4),
    ];
    let field: Vec<f32> = search.field_floats().concat();
    let kappas = worst(&got.field, &field, 12, |i| i == 3 || i == 7) / kappa;
    let field_normals = worst(&got.field, &field, 12, |i| i < 3 || i == 11);
    // Directions where the principal curvatures differ (a umbilic's are any), signed.
    let turned = got
        .field
        .chunks(12)
        .zip(field.chunks(12))
        .filter(|(_, w)| w[11] > 0.5 && (w[3] - w[7]).abs() > 1e-2 * kappa)
        .map(|(g, w)| {
            let d = |x: &[f32]| Vec3::new(x[4], x[5], x[6]);
            d(g).dot(d(w)).clamp(-1.0, 1.0).acos()
        })
        .fold(0.0f32, f32::max);
    let margins = search.face_margins();
    let ordered = tables::ordered_triangles(search, &margins, order);
    let ordered_ok = got
        .ordered
        .chunks(4)
        .zip(&ordered)
        .all(|(g, w)| g[..3] == w[..3]);
    let slack = worst(&bits(&got.ordered), &bits(&ordered.concat()), 4, |i| i == 3);
    let clusters =
        crate::cpu::clusters::cluster_records(search.triangles(), &margins, &solve, order);
    let cluster_floats: Vec<f32> = clusters
        .iter()
        .flat_map(|c| [c.axis, c.sphere, c.margin])
        .flatten()
        .collect();
    let cones = worst(&got.clusters, &cluster_floats, 12, |i| i < 4 || i == 8);
    let spheres = worst(&got.clusters, &cluster_floats, 12, |i| (4..8).contains(&i)) / size;
    let region_v = floats(
        &crate::gpu::regions::records::vertex_records(cpu)
            .iter()
            .flat_map(|r| [r.position, r.normal])
            .collect::<Vec<_>>(),
    );
    let regions = worst(&got.region_vertices, &region_v, 8, |_| true) / size.max(1.0);
    let region_f = crate::gpu::regions::records::face_records(cpu);
    let faces_ok = got
        .region_faces
        .chunks(8)
        .zip(&region_f)
        .all(|(g, w)| g[..4] == w.tri);
    let face_normals = worst(
        &bits(&got.region_faces),
        &region_f
            .iter()
            .flat_map(|f| [[0.0; 4], f.normal])
            .flatten()
            .collect::<Vec<_>>(),
        8,
        |i| i >= 4,
    );
    let positions = worst(
        &got.positions,
        &cpu.topology()
            .positions
            .iter()
            .flat_map(|p| p.extend(1.0).to_array())
            .collect::<Vec<_>>(),
        4,
        |_| true,
    ) / size;
    let receivers: Vec<[[u32; 4]; 3]> =
        bytemuck::cast_slice(&crate::gpu::receivers::face_records(cpu, render)).to_vec();
    let receivers_ok = got
        .receiver_faces
        .chunks(12)
        .zip(&receivers)
        .all(|(g, w)| g[..4] == w[0] && g[4..7] == w[1][..3]);
    let receiver_floats: Vec<f32> = receivers.iter().flat_map(|r| bits(&r.concat())).collect();
    let slack_r = worst(&bits(&got.receiver_faces), &receiver_floats, 12, |i| {
        i == 7 || i >= 8
    });
    let checks = checks.into_iter().chain([
        ("field curvatures", kappas, 1e-4),
        ("field normals", field_normals, 1e-5),
        ("principal directions (rad)", turned, 1e-3),
        ("faces' slack", slack, 1e-4),
        // An angle from `acos` near 1 carries √(2 × 6e-8) ≈ 3.5e-4 rad of the sums'
        // rounding (the cones' safety is 0.02 rad).
        ("cluster cones", cones, 5e-4),
        ("cluster spheres", spheres, 1e-5),
        ("region vertices", regions, 1e-5),
        ("face normals", face_normals, 1e-5),
        ("receiver positions", positions, 1e-6),
        ("receivers' slack", slack_r, 5e-4),
    ]);
    for (table, gap, bound) in checks {
        assert!(
            gap <= bound,
            "{what}: {table} {gap:.2e} apart (bound {bound:.0e})"
        );
    }
    assert!(
        ordered_ok && faces_ok && receivers_ok,
        "{what}: faces' corners differ"
    );
}

/// The highlight draw's normals: the set's where it gives its own, else zero (the draw
/// keeps the posed vertex buffer's, the mesh's own normals there).
fn compare_normals(what: &str, got: &[[f32; 4]], cpu: &HighlightSet, posed: &npr_geometry::Mesh) {
    let own = cpu.render_normals();
    assert_eq!(got.len(), own.len(), "{what}");
    let worst = got
        .iter()
        .zip(own)
        .enumerate()
        .map(|(r, (g, w))| {
            let g3 = Vec3::new(g[0], g[1], g[2]);
            if g[3] == 0.0 {
                (posed.normals[r] - *w).length()
            } else {
                (g3 - *w).length()
            }
        })
        .fold(0.0f32, f32::max);
    assert!(
        worst <= 1e-5,
        "{what}: the draw's normals {worst:.2e} apart"
    );
}
