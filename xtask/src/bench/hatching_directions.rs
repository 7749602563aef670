//! `cargo xtask bench hatching-directions [--mesh PATH]... [--json PATH]`: how smooth the
//! hatching stroke directions are and how well they follow curvature, for the
//! raw principal field (`raw`, `npr_hatching::DirectionSource::Principal`) and the smooth
//! line field (`smooth`, Knöppel et al. 2013, the default), exactly as the hatching pass
//! receives them (per render vertex, with the `y × n` fallback).
//!
//! Per mesh and field: `jump30_edge_share`, the share (0–1) of mesh edges across which the
//! stroke line turns by more than 30° (line angle mod 180°, both ends projected onto the
//! plane normal to the mean vertex normal); `aniso_dev_deg`, the mean angle to the
//! direction of maximum curvature at the vertices of the most anisotropic half
//! (`|κ_max − κ_min|` at or above the median); on the analytic torus also
//! `exact_dev_max_deg`, the largest angle to the exact principal direction. Default
//! meshes: the analytic torus R = 2, r = 0.7 with 10,000 vertices, the Stanford bunny and
//! Spot. Targets: jumps on ≤ 2 % of edges (bunny, Spot), ≤ 10° deviation, torus ≤ 0.5°.
//! `directions_ms` is the CPU wall time of the whole direction computation (curvature
//! included), on this machine, for scale only.
//!
//! Hard edges: `jump30_smooth_edge_share` is `jump30_edge_share` over the
//! edges whose dihedral angle is below the crease angle (50°, the outlines'), compared
//! within each face between the render vertices it draws with (a jump at a crease is
//! correct and not counted); `planar_spread_deg` is, over the flat regions (a fixed
//! region growing, independent of the field's own planar rule: connected faces whose
//! normals stay within 5° of the region's mean normal, each region covering ≥ 1 % of the
//! area), the area-weighted median of each region's circular standard deviation of the
//! stroke line (`npr_geometry::RenderFieldStats`), and `planar_area_share` the share of
//! the area those regions cover. Targets: ≤ 2 % and ≤ 3° on every mesh. The CAD meshes
//! (the procedural parts of `npr_geometry::generate::cad_parts`: a block with a
//! through-hole, a stepped shaft, a bent bracket; the wing nut, the scanned hammer and
//! the OpenCascade flange of `fixtures/meshes`) are default meshes, and one on which the measure finds no flat
//! region fails the bench rather than leaving a blank. A third
//! field, `smooth-curvature-only` (`StrokeFieldOptions::curvature_only()`, the field
//! before the hard-edge rules), shows what the crease cuts and the planar rule change.

use super::table::{Cell, Table, emit};
use glam::Vec3;
use npr_geometry::{
    CurvatureField, CurvatureOptions, LineFieldStats, Mesh, RenderFieldStats, StrokeFieldOptions,
    analytic, generate, line_angle_deg,
};
use npr_hatching::DirectionSource;
use npr_hatching::figures::directions_from;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The analytic torus of the benchmark: (R, r).
const TORUS: (f32, f32) = (2.0, 0.7);

/// A benchmark mesh: its name, the mesh, whether it is the analytic torus, and whether
/// it is a CAD mesh (which must have flat regions).
type Case = (String, Mesh, bool, bool);

fn default_meshes() -> anyhow::Result<Vec<Case>> {
    let (big, small) = TORUS;
    let (nu, nv) = generate::torus_segments_for(big, small, 10_000);
    let mut out = vec![(
        "torus R=2 r=0.7 (10k)".to_string(),
        generate::torus(big, small, nu, nv),
        true,
        false,
    )];
    for (name, cad) in [
        ("stanford-bunny.obj", false),
        ("spot.obj", false),
        ("wingnut.obj", true),
        ("hammer.obj", true),
        ("flange.obj", true),
    ] {
        out.push((
            name.trim_end_matches(".obj").to_string(),
            npr_geometry::load_obj(crate::fixture_mesh(name))?,
            false,
            cad,
        ));
    }
    out.push(("cad-parts".to_string(), generate::cad_parts(), false, true));
    Ok(out)
}

/// Runs the benchmark on `meshes` (OBJ paths), or the default meshes when empty.
pub fn run(meshes: &[PathBuf], json: Option<&Path>) -> anyhow::Result<()> {
    let cases = if meshes.is_empty() {
        default_meshes()?
    } else {
        meshes
            .iter()
            .map(|p| {
                let mesh = npr_geometry::io::load(p)?.mesh;
                Ok((p.display().to_string(), mesh, false, false))
            })
            .collect::<anyhow::Result<_>>()?
    };
    let mut table = Table::new(
        "hatching-directions: stroke-line jumps > 30° across edges and deviation from the principal direction (anisotropic half)",
        &[
            "mesh",
            "field",
            "vertices",
            "jump30_edge_share",
            "jump30_smooth_edge_share",
            "planar_spread_deg",
            "planar_area_share",
            "aniso_dev_deg",
            "exact_dev_max_deg",
            "directions_ms",
        ],
    );
    let opts = CurvatureOptions::default();
    let mut no_flat = Vec::new();
    for (name, mesh, is_torus, cad) in &cases {
        let (welded, topo, curvature) = CurvatureField::for_mesh(mesh, &opts);
        // One render vertex per welded vertex.
        let mut rep = vec![None; topo.vertex_count()];
        for (v, &w) in welded.render_to_welded.iter().enumerate() {
            if let Some(slot) = rep.get_mut(w as usize) {
                slot.get_or_insert(v);
            }
        }
        let crease_deg = StrokeFieldOptions::default().crease_angle_deg;
        for (label, source) in [
            ("raw", DirectionSource::Principal),
            ("smooth", DirectionSource::default()),
            (
                "smooth-curvature-only",
                DirectionSource::Smooth(StrokeFieldOptions::curvature_only()),
            ),
        ] {
            let start = Instant::now();
            let render = directions_from(mesh, &source);
            let ms = start.elapsed().as_secs_f64() * 1e3;
            let dirs: Vec<Vec3> = rep
                .iter()
                .map(|r| r.and_then(|v| render.get(v).copied()).unwrap_or(Vec3::ZERO))
                .collect();
            let stats = LineFieldStats::measure(&topo, &curvature, &dirs, 30.0);
            let hard = RenderFieldStats::measure(mesh, &topo, &render, 30.0, crease_deg);
            if *cad && hard.planar_spread_deg.is_none() && label == "raw" {
                no_flat.push(name.clone());
            }
            let exact = is_torus.then(|| {
                let (big, small) = TORUS;
                topo.positions
                    .iter()
                    .zip(&dirs)
                    .zip(&curvature.normal)
                    .filter_map(|((p, d), n)| {
                        let e = analytic::torus(*p, f64::from(big), f64::from(small));
                        line_angle_deg(*d, e.dir_kappa_max.as_vec3(), *n)
                    })
                    .fold(0.0f64, f64::max)
            });
            table.push(vec![
                name.as_str().into(),
                label.into(),
                topo.vertex_count().into(),
                Cell::Num(stats.jump_edge_share, 4),
                Cell::Num(hard.jump_smooth_edge_share, 4),
                hard.planar_spread_deg
                    .map_or(Cell::Empty, |x| Cell::Num(x, 2)),
                Cell::Num(hard.planar_area_share, 3),
                Cell::Num(stats.aniso_dev_deg, 2),
                exact.map_or(Cell::Empty, |x| Cell::Num(x, 3)),
                Cell::Num(ms, 0),
            ]);
        }
    }
    emit(&[table], json)?;
    anyhow::ensure!(
        no_flat.is_empty(),
        "the flat-region measure finds no region on the CAD meshes {no_flat:?}: their \
         planar spread cannot be judged"
    );
    Ok(())
}
