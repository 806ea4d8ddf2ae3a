//! `ophis check`: load a scene as `ophis render` would, print every warning, render nothing.

use anyhow::{bail, Result};
use clap::Parser;
use ophis::scene::build::{load_scene_into, LoadOptions};
use std::path::PathBuf;

/// Arguments of `ophis check`.
#[derive(Parser)]
pub struct CheckArgs {
    /// The scene file (Mitsuba XML, version 3.x or 0.x).
    scene: PathBuf,
    /// Set a scene parameter, as Mitsuba's `-D name=value` (fills `$name`, overrides `<default>`).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    defines: Vec<String>,
    /// Exit with status 1 when there is any warning, not only on an error.
    #[arg(long)]
    strict: bool,
}

pub fn run(args: CheckArgs) -> Result<()> {
    let opts = LoadOptions {
        defines: super::render::parse_defines(&args.defines)?,
        ..Default::default()
    };
    let mut warnings = Vec::new();
    let loaded = load_scene_into(&args.scene, &opts, &mut warnings);
    for w in &warnings {
        // A warning displays as "file:line:col: warning: …".
        eprintln!("{w}");
    }
    let scene = loaded?;
    let n = warnings.len();
    println!(
        "{}: loads: {} shapes ({} primitives), {} materials, {} lights, {}x{} at {} spp; {n} warning{}",
        args.scene.display(),
        scene.shapes.len(),
        scene.primitive_count(),
        scene.materials.len(),
        scene.lights.len(),
        scene.width,
        scene.height,
        scene.sampler.spp,
        if n == 1 { "" } else { "s" }
    );
    if args.strict && n > 0 {
        bail!("{n} warning{} (--strict)", if n == 1 { "" } else { "s" });
    }
    Ok(())
}
