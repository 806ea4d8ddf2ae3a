//! The `ophis` command line: one subcommand per file beside this one.

mod bsdf;
mod check;
mod gallery;
mod merge;
mod plugins;
mod render;
mod thinfilm;
mod thinfilm_plot;

use clap::{Parser, Subcommand};

/// ophis — a spectral path tracer for structural colour (thin films, layered materials),
/// reading Mitsuba 3 and 0.6 XML scenes.
#[derive(Parser)]
#[command(name = "ophis", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a Mitsuba XML scene to EXR (linear sRGB, float32) and PNG (sRGB, 8-bit).
    Render(render::RenderArgs),
    /// Load a scene as `render` would, print every warning, and exit without rendering
    /// (status 1 if it does not load).
    Check(check::CheckArgs),
    /// Reflectance of a thin film against wavelength and angle: CSV, colours, plots.
    Thinfilm(thinfilm::ThinFilmArgs),
    /// Merge renders of one scene made with different seeds (e.g. on several machines) into
    /// the image one render with all their samples would have made.
    Merge(merge::MergeArgs),
    /// Inspect one BSDF of a scene: directional albedo and f·cos with standard errors.
    Bsdf(bsdf::BsdfArgs),
    /// The plugins ophis reads (BSDFs, textures, …) and their parameters.
    Plugins(plugins::PluginsArgs),
    /// Render every thesis and CEIG 2023 figure and compose labelled contact sheets
    /// (docs/gallery/*.png).
    Gallery(gallery::GalleryArgs),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(args),
        Command::Check(args) => check::run(args),
        Command::Thinfilm(args) => thinfilm::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Bsdf(args) => bsdf::run(args),
        Command::Gallery(args) => gallery::run(args),
        Command::Plugins(args) => plugins::run(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
