//! Project automation (the cargo-xtask pattern): `cargo xtask test | demo | bench NAME |
//! fixtures | curvature | web`. One module per subcommand.

mod bench;
mod browser;
mod cargo;
mod demo;
mod fixtures;
mod gallery;
mod gpu_setup;
mod test;
mod tidy;
mod web;

use clap::{Parser, Subcommand};
use std::path::PathBuf;

#[derive(Parser)]
#[command(name = "cargo xtask", about = "npr workspace automation")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// rustfmt check, clippy (warnings denied), every workspace test including the GPU
    /// ones (installs Mesa's software Vulkan driver on Debian/Ubuntu when no adapter exists).
    Test,
    /// Render the demo images into target/demo/ and the gallery page target/demo/index.html.
    Demo,
    /// Run a benchmark and print its tables (`curvature`, ...).
    Bench {
        /// Which benchmark.
        name: String,
        /// Also write the rows as JSON to this file.
        #[arg(long)]
        json: Option<PathBuf>,
        /// A mesh (OBJ, PLY, glTF) to run on; repeatable. Only for the benchmarks that take
        /// meshes (`hatching-directions`, `specular`, `specular-fidelity`).
        #[arg(long)]
        mesh: Vec<PathBuf>,
        /// A clip (name or index) that the `--mesh` models play, beside their rigid turn
        /// (`specular-fidelity`, `hatching-coherence`).
        #[arg(long, value_name = "NAME|INDEX")]
        animation: Option<String>,
    },
    /// Regenerate fixtures/ from the code that defines them.
    Fixtures,
    /// Find (and on Debian/Ubuntu as root, install) a GPU adapter, Xvfb and Chromium; print
    /// them.
    Doctor,
    /// Per-vertex principal curvatures of a model, as CSV (an alias of `npr curvature`).
    Curvature(npr_app::curvature::CurvatureArgs),
    /// Build the browser viewer into target/web/ (a static site) and serve it on 127.0.0.1.
    Web {
        /// Build only; do not serve.
        #[arg(long)]
        build_only: bool,
        /// Open the page in headless Chromium and compare each effect with the native
        /// render (FLIP); needs chromium and chromium-driver.
        #[arg(long, conflicts_with = "build_only")]
        check: bool,
        /// The port to serve on.
        #[arg(long, default_value_t = 8000)]
        port: u16,
    },
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    gpu_setup::ensure_runtime_dir()?;
    match cli.command {
        Command::Test => test::run(),
        Command::Demo => demo::run(),
        Command::Bench {
            name,
            json,
            mesh,
            animation,
        } => bench::run(&name, &mesh, json.as_deref(), animation.as_deref()),
        Command::Fixtures => fixtures::run(),
        Command::Doctor => {
            println!("adapter: {}", gpu_setup::ensure_adapter()?);
            gpu_setup::ensure_xvfb()?;
            println!("xvfb-run: found (the windowed `npr view` test runs under it)");
            gpu_setup::ensure_chromium()?;
            println!("chromium, chromedriver: found (the browser test drives them)");
            Ok(())
        }
        Command::Curvature(args) => Ok(npr_app::curvature::run(args)?),
        Command::Web {
            build_only,
            check,
            port,
        } => web::run(build_only, check, port),
    }
}

/// The workspace root (parent of the xtask crate).
pub fn project_root() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    dir.parent().map(PathBuf::from).unwrap_or(dir)
}

/// `fixtures/meshes/NAME`: the real meshes the project ships (see its README).
pub use npr_gpu::figures::fixture_mesh;
