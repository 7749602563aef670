//! `cargo xtask curvature IN.obj OUT.csv`: principal curvatures and the direction of
//! maximum curvature for every `v` line of a user's OBJ file (Eq. (1), §2.2 of the
//! specular paper; see `npr_geometry::curvature`).

use std::io::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context as _;
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

/// Arguments of `cargo xtask curvature`.
#[derive(clap::Args, Debug)]
pub struct CurvatureArgs {
    /// Input Wavefront OBJ file.
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
pub fn run(args: CurvatureArgs) -> anyhow::Result<()> {
    let radius = match (args.radius, args.radius_edges) {
        (Some(r), _) => {
            anyhow::ensure!(
                r.is_finite() && r > 0.0,
                "--radius must be a positive number"
            );
            CurvatureRadius::World(r)
        }
        (None, Some(k)) => {
            anyhow::ensure!(
                k.is_finite() && k > 0.0,
                "--radius-edges must be a positive number"
            );
            CurvatureRadius::EdgeLengths(k)
        }
        (None, None) => CurvatureRadius::default(),
    };
    let obj = npr_geometry::load_obj_with_vertex_map(&args.input)
        .with_context(|| format!("loading {}", args.input.display()))?;

    let start = Instant::now();
    let topo = Topology::new(&obj.welded);
    let field = CurvatureField::compute(
        &topo,
        &CurvatureOptions {
            method: args.method.into(),
            radius,
        },
    );
    let compute_s = start.elapsed().as_secs_f64();

    let file = std::fs::File::create(&args.output)
        .with_context(|| format!("creating {}", args.output.display()))?;
    let mut out = std::io::BufWriter::new(file);
    writeln!(out, "k_min,k_max,dmax_x,dmax_y,dmax_z")?;
    let mut undefined = 0usize;
    for w in &obj.obj_to_welded {
        match w.map(|w| w as usize).filter(|&w| field.valid[w]) {
            Some(w) => {
                let d = field.dir_kappa_max[w];
                writeln!(
                    out,
                    "{},{},{},{},{}",
                    field.kappa_min[w], field.kappa_max[w], d.x, d.y, d.z
                )?;
            }
            None => {
                undefined += 1;
                writeln!(out, ",,,,")?;
            }
        }
    }
    out.flush()?;
    println!("compute_s={compute_s:.6}");
    eprintln!(
        "{} rows ({} undefined), method {}, radius {} world units -> {}",
        obj.obj_to_welded.len(),
        undefined,
        field.method.name(),
        field.radius_world,
        args.output.display()
    );
    Ok(())
}
