//! `ophis bsdf`: look inside one BSDF of a scene — directional albedo, f·cos at a direction
//! pair, each with its standard error, per wavelength or in linear sRGB.

use anyhow::{anyhow, bail, Result};
use clap::Parser;
use ophis::bsdf::testing::Estimate;
use ophis::scene::build::build_material;
use ophis::scene::mitsuba::load_file;
use ophis::tools::inspect::{at_wavelength, bsdf_ids, find_bsdf, linear_srgb, plots, Quantity};
use std::path::PathBuf;

/// Arguments of `ophis bsdf`.
#[derive(Parser)]
pub struct BsdfArgs {
    /// The scene file (Mitsuba XML, version 3.x or 0.6).
    scene: PathBuf,
    /// The id of the `<bsdf>` to inspect.
    #[arg(long)]
    id: String,
    /// Set a scene parameter, as Mitsuba's `-D name=value`.
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    defines: Vec<String>,
    /// Print the directional albedo (hemispherical reflectance, delta lobes included) for
    /// incidence at --theta-i.
    #[arg(long)]
    albedo: bool,
    /// Print f·|cos θo| for the pair (--theta-i, 0) → (--theta-o, --phi-o).
    #[arg(long)]
    eval: bool,
    /// Incident polar angle, degrees (negative: from below).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    theta_i: f32,
    /// Outgoing polar angle, degrees (negative: below the surface).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    theta_o: f32,
    /// Outgoing azimuth, degrees (180: the plane of incidence, on the mirror side).
    #[arg(long, default_value_t = 180.0, allow_negative_numbers = true)]
    phi_o: f32,
    /// Report at these wavelengths (nm) instead of linear sRGB; repeat or give a list.
    #[arg(long, value_delimiter = ',')]
    lambda: Vec<f32>,
    /// Number of samples per estimate.
    #[arg(long, default_value_t = 100_000)]
    samples: usize,
    /// Write figures: FILE.png (polar plot of the lobe in the plane of incidence for θi = 0°,
    /// 30°, 60°, 75°) and FILE-hemisphere.png (f·cos over the hemisphere at --theta-i), at the
    /// first --lambda (default 550 nm), spending --samples over all points.
    #[arg(long, value_name = "FILE.png")]
    plot: Option<PathBuf>,
    /// Seed of the random stream.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

fn show(e: &Estimate) -> String {
    format!("{:.6} ± {:.6}", e.mean, e.std_err)
}

/// Runs `ophis bsdf`.
pub fn run(args: BsdfArgs) -> Result<()> {
    if !args.albedo && !args.eval && args.plot.is_none() {
        bail!("nothing to do: give --albedo, --eval and/or --plot");
    }
    if args.samples < 2 {
        bail!("--samples must be at least 2");
    }
    let defines = crate::render::parse_defines(&args.defines)?;
    let (root, warnings) = load_file(&args.scene, &defines)?;
    for w in &warnings {
        eprintln!("{w}");
    }
    let node = find_bsdf(&root, &args.id).ok_or_else(|| {
        anyhow!(
            "no <bsdf> with id '{}' in {} (ids: {})",
            args.id,
            args.scene.display(),
            bsdf_ids(&root).join(", ")
        )
    })?;
    let mut warnings = Vec::new();
    let material = build_material(node, &mut warnings)?;
    for w in &warnings {
        eprintln!("{w}");
    }
    let mut queries = Vec::new();
    if args.albedo {
        queries.push((
            format!("albedo at θi = {}°", args.theta_i),
            Quantity::Albedo {
                theta_i: args.theta_i,
            },
        ));
    }
    if args.eval {
        queries.push((
            format!(
                "f·cos at θi = {}°, θo = {}°, φo = {}°",
                args.theta_i, args.theta_o, args.phi_o
            ),
            Quantity::Eval {
                theta_i: args.theta_i,
                theta_o: args.theta_o,
                phi_o: args.phi_o,
            },
        ));
    }
    println!(
        "bsdf '{}' ({}), {} samples",
        args.id, node.plugin, args.samples
    );
    for (what, q) in queries {
        if args.lambda.is_empty() {
            let [r, g, b] = linear_srgb(&material, q, args.samples, args.seed);
            println!("{what}, linear sRGB:");
            println!("  R {}\n  G {}\n  B {}", show(&r), show(&g), show(&b));
        } else {
            println!("{what}:");
            for &l in &args.lambda {
                if !(l > 0.0 && l.is_finite()) {
                    bail!("--lambda must be positive, got {l}");
                }
                let e = at_wavelength(&material, q, l, args.samples, args.seed);
                println!("  {l} nm {}", show(&e));
            }
        }
    }
    if let Some(path) = &args.plot {
        let lambda = args.lambda.first().copied().unwrap_or(550.0);
        let (polar, hemi) = plots(&material, lambda, args.theta_i, args.samples, args.seed);
        let stem = path.with_extension("");
        let hemi_path = PathBuf::from(format!("{}-hemisphere.png", stem.display()));
        let polar_path = stem.with_extension("png");
        polar.save_png(&polar_path)?;
        hemi.save_png(&hemi_path)?;
        println!("wrote {} and {}", polar_path.display(), hemi_path.display());
    }
    Ok(())
}
