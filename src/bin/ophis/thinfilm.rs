//! `ophis thinfilm`: reflectance of a thin film or an interference stack per wavelength and
//! angle, as CSV, as colours, or as plots. The computation lives in `ophis::optics::filmtool`
//! and `ophis::optics::filmstack`; the stack syntax in `ophis::optics::stackspec`.

use anyhow::{anyhow, bail, Result};
use clap::Parser;
use ophis::optics::filmstack::FilmStack;
use ophis::optics::filmtool::{
    check_grid, csv, parse_index, parse_interval, parse_list, parse_range, stack_rgb,
};
use ophis::optics::ior::Ior;
use ophis::optics::stackspec::parse_items;
use std::path::PathBuf;

/// Arguments of `ophis thinfilm`.
#[derive(Parser)]
pub struct ThinFilmArgs {
    /// Film index: a number, `keratin` (1.532 + 5890/λ²), `cauchy(A,B)`, n+ki, or a name
    /// (`water`, `bk7`, a metal such as `Ag`).
    #[arg(long, default_value = "1.56", allow_negative_numbers = true)]
    film_ior: String,
    /// Film thickness in nm.
    #[arg(long, default_value = "900", allow_negative_numbers = true)]
    thickness: String,
    /// An interference stack instead of one film, outside in: INDEX:NM,INDEX:NM,… with periodic
    /// groups (INDEX:NM,…)xCOUNT, e.g. `(2.3:60,1.38:100)x10,2.3:60` (INDEX as for --film-ior).
    #[arg(long, conflicts_with_all = ["film_ior", "thickness"], allow_negative_numbers = true)]
    stack: Option<String>,
    /// Index of the medium the light comes from (transparent: number or name).
    #[arg(long, default_value = "1.0", allow_negative_numbers = true)]
    ext_ior: String,
    /// Index of the base under the film (as for --film-ior; a metal name or n+ki for a metal).
    #[arg(long, conflicts_with_all = ["int_eta", "int_k"], allow_negative_numbers = true)]
    int_ior: Option<String>,
    /// Real part n of a metal base's complex index n + ik (with --int-k).
    #[arg(long, requires = "int_k", allow_negative_numbers = true)]
    int_eta: Option<f64>,
    /// Imaginary part k of a metal base's complex index (with --int-eta).
    #[arg(long, requires = "int_eta", allow_negative_numbers = true)]
    int_k: Option<f64>,
    /// Light arrives from the base (which must be transparent); angles are measured there.
    #[arg(long)]
    from_base: bool,
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
    /// Thickness range of the chart in nm, A:B (a stack's total thickness, all layers scaled
    /// together; default 0:1500 for a film, 0 to twice the total for a stack).
    #[arg(long, allow_negative_numbers = true)]
    thickness_range: Option<String>,
}

/// The base index from --int-ior or --int-eta/--int-k (vacuum if neither).
fn base(a: &ThinFilmArgs) -> Result<Ior> {
    Ok(match (&a.int_ior, a.int_eta, a.int_k) {
        (Some(s), _, _) => parse_index("--int-ior", s).map_err(|e| anyhow!(e))?,
        (None, Some(n), Some(k)) => {
            if !(n > 0.0 && n.is_finite()) {
                bail!("--int-eta: must be positive, got {n}");
            }
            if !(k >= 0.0 && k.is_finite()) {
                bail!("--int-k: must be ≥ 0, got {k}");
            }
            Ior::complex(n, k).map_err(|e| anyhow!("--int-eta/--int-k: {e}"))?
        }
        _ => Ior::Real(1.0),
    })
}

/// The stack the table, colours and plot use, and the one the chart scales (for one film: the
/// film at 1 nm, so that the chart's axis is the film thickness whatever --thickness says).
fn stacks(a: &ThinFilmArgs) -> Result<(FilmStack, FilmStack)> {
    let ext = parse_index("--ext-ior", &a.ext_ior).map_err(|e| anyhow!(e))?;
    if !ext.is_lossless() {
        bail!("--ext-ior: the medium the light comes from must be transparent, got {ext}");
    }
    let base = base(a)?;
    if a.from_base && !base.is_lossless() {
        bail!("--from-base: light can only come from a transparent base, got {base}");
    }
    if let Some(spec) = &a.stack {
        let items = parse_items(spec).map_err(|e| anyhow!("--stack: {e}"))?;
        let st = FilmStack::new(ext, items, base).map_err(|e| anyhow!("--stack: {e}"))?;
        return Ok((st.clone(), st));
    }
    let d: f64 = a
        .thickness
        .trim()
        .parse()
        .map_err(|_| anyhow!("--thickness: '{}' is not a number", a.thickness))?;
    if !(d >= 0.0 && d.is_finite()) {
        bail!("--thickness: the film thickness must be a finite number ≥ 0 nm, got {d}");
    }
    let film = parse_index("--film-ior", &a.film_ior).map_err(|e| anyhow!(e))?;
    let one =
        |d| FilmStack::film(ext.clone(), film.clone(), d, base.clone()).map_err(|e| anyhow!(e));
    Ok((one(d)?, one(1.0)?))
}

/// Runs the subcommand.
pub fn run(a: ThinFilmArgs) -> Result<()> {
    let (st, chart_st) = stacks(&a)?;
    let err = |e: String| anyhow!(e);
    let angles = parse_list("--angles", &a.angles).map_err(err)?;
    let wavelengths = parse_range("--wavelengths", &a.wavelengths).map_err(err)?;
    check_grid(&angles, &wavelengths).map_err(err)?;
    let range = match &a.thickness_range {
        Some(r) => parse_interval("--thickness-range", r).map_err(err)?,
        None if a.stack.is_some() => (0.0, (2.0 * st.total_thickness()).max(1.0)),
        None => (0.0, 1500.0),
    };
    if range.0 < 0.0 {
        bail!(
            "--thickness-range: thicknesses must be ≥ 0 nm, got {}",
            range.0
        );
    }
    if a.rgb {
        println!("angle_deg,r,g,b");
        for &ang in &angles {
            let c = stack_rgb(&st, ang, a.from_base);
            println!("{ang},{:.6},{:.6},{:.6}", c[0], c[1], c[2]);
        }
    } else if a.plot.is_none() && a.chart.is_none() {
        print!("{}", csv(&st, &angles, &wavelengths, a.from_base));
    }
    if let Some(p) = &a.plot {
        super::thinfilm_plot::plot(&st, &angles, &wavelengths, a.from_base, p)?;
        eprintln!("wrote {}", p.display());
    }
    if let Some(p) = &a.chart {
        super::thinfilm_plot::chart(&chart_st, range, a.from_base, p)?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
