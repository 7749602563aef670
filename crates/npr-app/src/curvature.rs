//! `npr curvature IN OUT.csv` (and its alias `cargo xtask curvature`): principal
//! curvatures and the direction of maximum curvature for every vertex of a user's model
//! (Eq. (1), §2.2 of the specular paper; see `npr_geometry::curvature`). The CSV is
//! written all-or-nothing.

use std::io::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use crate::AppError;
use npr_geometry::{CurvatureField, CurvatureMethod, CurvatureOptions, CurvatureRadius, Topology};

/// Which form of Eq. (1) to use.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// The paper's approximation (whole triangles, full edges).
    Paper,
    /// Cohen-Steiner & Morvan's exact clipped edges.
    Clipped,
    /// Area-shared edges, smooth kernel, tangent projection (most accurate).
    #[default]
    Corrected,
}

impl From<Method> for CurvatureMethod {
    fn from(m: Method) -> Self {
        match m {
            Method::Paper => Self::Paper,
            Method::Clipped => Self::Clipped,
            Method::Corrected => Self::Corrected,
        }
    }
}

/// Arguments of `npr curvature`.
#[derive(clap::Args, Debug)]
pub struct CurvatureArgs {
    /// Input model: OBJ (rows follow its `v` lines), PLY or glTF (rows follow the loaded
    /// mesh's vertices).
    pub input: PathBuf,
    /// Output CSV: header `k_min,k_max,dmax_x,dmax_y,dmax_z`, one row per `v` line of
    /// the input in input order; empty fields where curvature is undefined.
    pub output: PathBuf,
    /// Ball radius in world units.
    #[arg(long, conflicts_with = "radius_edges")]
    pub radius: Option<f32>,
    /// Ball radius as a multiple of the mean edge length (default 3).
    #[arg(long)]
    pub radius_edges: Option<f32>,
    /// Form of the curvature tensor.
    #[arg(long, value_enum, default_value_t = Method::Corrected)]
    pub method: Method,
}

/// Runs the command: loads, computes (timed: topology and field, printed as
/// `compute_s=<seconds>` on stdout), writes the CSV.
///
/// # Errors
/// [`AppError::Usage`] for a bad radius, [`AppError::Load`] for a bad model,
/// [`AppError::Io`] when the CSV cannot be written (no partial file is left).
pub fn run(args: CurvatureArgs) -> Result<(), AppError> {
    let radius = match (args.radius, args.radius_edges) {
        (Some(r), _) if !(r.is_finite() && r > 0.0) => {
            return Err(AppError::Usage("--radius must be a positive number".into()));
        }
        (Some(r), _) => CurvatureRadius::World(r),
        (None, Some(k)) if !(k.is_finite() && k > 0.0) => {
            return Err(AppError::Usage(
                "--radius-edges must be a positive number".into(),
            ));
        }
        (None, Some(k)) => CurvatureRadius::EdgeLengths(k),
        (None, None) => CurvatureRadius::default(),
    };
    let is_obj = args
        .input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    let (welded, rows) = if is_obj {
        // One row per `v` line of the file, as before.
        let obj = npr_geometry::load_obj_with_vertex_map(&args.input).map_err(|e| match e {
            npr_geometry::GeometryError::Load(source) => AppError::Load {
                path: args.input.clone(),
                source,
            },
            e => AppError::Geometry(e),
        })?;
        (obj.welded, obj.obj_to_welded)
    } else {
        // One row per vertex of the loaded mesh (for PLY, the file's vertices in order).
        let loaded = npr_geometry::io::load(&args.input).map_err(|source| AppError::Load {
            path: args.input.clone(),
            source,
        })?;
        let welded = npr_geometry::weld(&loaded.mesh);
        let rows = welded.render_to_welded.iter().map(|&w| Some(w)).collect();
        (welded, rows)
    };

    let start = Instant::now();
    let topo = Topology::new(&welded);
    let field = CurvatureField::compute(
        &topo,
        &CurvatureOptions {
            method: args.method.into(),
            radius,
        },
    );
    let compute_s = start.elapsed().as_secs_f64();

    let mut undefined = 0usize;
    let output = args.output.clone();
    crate::output::write_with(&args.output, |out| {
        let io = |e| AppError::io(&output, e);
        writeln!(out, "k_min,k_max,dmax_x,dmax_y,dmax_z").map_err(io)?;
        for w in &rows {
            match w.map(|w| w as usize).filter(|&w| field.valid[w]) {
                Some(w) => {
                    let d = field.dir_kappa_max[w];
                    writeln!(
                        out,
                        "{},{},{},{},{}",
                        field.kappa_min[w], field.kappa_max[w], d.x, d.y, d.z
                    )
                    .map_err(io)?;
                }
                None => {
                    undefined += 1;
                    writeln!(out, ",,,,").map_err(io)?;
                }
            }
        }
        Ok(())
    })?;
    println!("compute_s={compute_s:.6}");
    eprintln!(
        "{} rows ({} undefined), method {}, radius {} world units -> {}",
        rows.len(),
        undefined,
        field.method.name(),
        field.radius_world,
        args.output.display()
    );
    Ok(())
}
