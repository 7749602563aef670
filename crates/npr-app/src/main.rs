//! `npr`: the workspace's techniques on your own model.
//!
//! ```text
//! npr render MODEL [--effect E] [--preset FILE] [--size WxH] [--out PATH]
//!                  [--turntable N [--gif]] [--json PATH]
//! npr view [MODEL] [--preset FILE] [--script FILE] [--screenshot PNG] [--exit-after-frames N]
//!                  [--animation NAME|INDEX|none] [--time S] [--frames N] [--fps F] [--no-loop]
//! npr curvature IN OUT.csv [--radius R | --radius-edges K] [--method M]
//! npr pose MODEL [--animation NAME|INDEX|none] [--time S] --out POSED.obj|.ply
//! ```

#[cfg(not(target_arch = "wasm32"))]
use clap::{Parser, Subcommand};
#[cfg(not(target_arch = "wasm32"))]
use std::process::ExitCode;

#[cfg(not(target_arch = "wasm32"))]
#[derive(Parser)]
#[command(name = "npr", version, about = "Real-time NPR on your own model")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[cfg(not(target_arch = "wasm32"))]
#[derive(Subcommand)]
enum Command {
    /// Render a model with an effect to PNG, numbered PNG frames or a GIF.
    Render(npr_app::render::RenderArgs),
    /// Open a live window on a model (the built-in bunny when none is given).
    View(npr_app::viewer::ViewArgs),
    /// Per-vertex principal curvatures of a model, as CSV.
    Curvature(npr_app::curvature::CurvatureArgs),
    /// Write a glTF model posed at one moment of a clip, as OBJ or PLY.
    Pose(npr_app::animation::PoseArgs),
}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = npr_app::ensure_runtime_dir() {
        eprintln!("npr: warning: {e}");
    }
    let result = match cli.command {
        Command::Render(args) => npr_app::render::run(&args).map(|summary| {
            for note in &summary.notes {
                eprintln!("npr: note: {note}");
            }
            for path in &summary.written {
                println!("{}", path.display());
            }
        }),
        Command::View(args) => npr_app::viewer::run(args),
        Command::Curvature(args) => npr_app::curvature::run(args),
        Command::Pose(args) => npr_app::animation::pose(&args).map(|p| println!("{}", p.display())),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("npr: error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The command line needs a process: on wasm32 the library is used by the web front end
/// (`npr-web`) instead, and this binary does nothing.
#[cfg(target_arch = "wasm32")]
fn main() {}
