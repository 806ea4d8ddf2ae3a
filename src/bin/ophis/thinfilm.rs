//! `ophis thinfilm`: reflectance of a thin film per wavelength and angle, as CSV, as colours,
//! or as plots. The computation lives in `ophis::optics::filmtool`.

use anyhow::{anyhow, bail, Result};
use clap::Parser;
use ophis::optics::filmtool::{
    check_grid, csv, parse_film_ior, parse_interval, parse_ior, parse_list, parse_range, FilmStack,
};
use std::path::PathBuf;

/// Arguments of `ophis thinfilm`.
#[derive(Parser)]
pub struct ThinFilmArgs {
    /// Film index: a number, `keratin` (1.532 + 5890/λ²) or a named dielectric (`water`, …).
    #[arg(long, default_value = "1.56", allow_negative_numbers = true)]
    film_ior: String,
    /// Film thickness in nm.
    #[arg(long, default_value = "900", allow_negative_numbers = true)]
    thickness: String,
    /// Index of the medium the light comes from (number or name).
    #[arg(long, default_value = "1.0", allow_negative_numbers = true)]
    ext_ior: String,
    /// Index of the dielectric under the film (number or name).
    #[arg(long, conflicts_with_all = ["int_eta", "int_k"], allow_negative_numbers = true)]
    int_ior: Option<String>,
    /// Real part n of a metal base's complex index n + ik (with --int-k).
    #[arg(long, requires = "int_k", allow_negative_numbers = true)]
    int_eta: Option<f64>,
    /// Imaginary part k of a metal base's complex index (with --int-eta).
    #[arg(long, requires = "int_eta", allow_negative_numbers = true)]
    int_k: Option<f64>,
    /// Angles of incidence in degrees, comma-separated.
    #[arg(long, default_value = "0", allow_negative_numbers = true)]
    angles: String,
    /// Wavelengths in nm as START:END:STEP.
    #[arg(long, default_value = "380:780:5", allow_negative_numbers = true)]
    wavelengths: String,
    /// Print the linear-sRGB colour of reflected D65 per angle instead of the table.
    #[arg(long)]
    rgb: bool,
    /// Draw R(λ) for each angle into this PNG.
    #[arg(long, value_name = "FILE.png")]
    plot: Option<PathBuf>,
    /// Draw a colour chart, thickness (x) × angle (y), into this PNG.
    #[arg(long, value_name = "FILE.png")]
    chart: Option<PathBuf>,
    /// Thickness range of the chart in nm, A:B.
    #[arg(long, default_value = "0:1500", allow_negative_numbers = true)]
    thickness_range: String,
}

/// Builds the stack from the arguments; errors name the argument.
fn stack(a: &ThinFilmArgs) -> Result<FilmStack> {
    let err = |e: String| anyhow!(e);
    let d: f64 = a
        .thickness
        .trim()
        .parse()
        .map_err(|_| anyhow!("--thickness: '{}' is not a number", a.thickness))?;
    if !(d >= 0.0 && d.is_finite()) {
        bail!("--thickness: the film thickness must be a finite number ≥ 0 nm, got {d}");
    }
    let (base_n, base_k) = match (&a.int_ior, a.int_eta, a.int_k) {
        (Some(s), _, _) => (parse_ior("--int-ior", s).map_err(err)?, 0.0),
        (None, Some(n), Some(k)) => {
            if !(n > 0.0 && n.is_finite()) {
                bail!("--int-eta: must be positive, got {n}");
            }
            if !(k >= 0.0 && k.is_finite()) {
                bail!("--int-k: must be ≥ 0, got {k}");
            }
            (n, k)
        }
        _ => (1.0, 0.0),
    };
    Ok(FilmStack {
        ext: parse_ior("--ext-ior", &a.ext_ior).map_err(err)?,
        film: parse_film_ior("--film-ior", &a.film_ior).map_err(err)?,
        d_nm: d,
        base_n,
        base_k,
    })
}

/// Runs the subcommand.
pub fn run(a: ThinFilmArgs) -> Result<()> {
    let st = stack(&a)?;
    let err = |e: String| anyhow!(e);
    let angles = parse_list("--angles", &a.angles).map_err(err)?;
    let wavelengths = parse_range("--wavelengths", &a.wavelengths).map_err(err)?;
    check_grid(&angles, &wavelengths).map_err(err)?;
    let range = parse_interval("--thickness-range", &a.thickness_range).map_err(err)?;
    if range.0 < 0.0 {
        bail!(
            "--thickness-range: thicknesses must be ≥ 0 nm, got {}",
            range.0
        );
    }
    if a.rgb {
        println!("angle_deg,r,g,b");
        for &ang in &angles {
            let c = st.reflected_rgb(ang);
            println!("{ang},{:.6},{:.6},{:.6}", c[0], c[1], c[2]);
        }
    } else if a.plot.is_none() && a.chart.is_none() {
        print!("{}", csv(&st, &angles, &wavelengths));
    }
    if let Some(p) = &a.plot {
        super::thinfilm_plot::plot(&st, &angles, &wavelengths, p)?;
        eprintln!("wrote {}", p.display());
    }
    if let Some(p) = &a.chart {
        super::thinfilm_plot::chart(&st, range, p)?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
