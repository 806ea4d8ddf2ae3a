//! The figures of `ophis thinfilm`: R(λ) curves per angle (`--plot`) and the thickness × angle
//! colour chart (`--chart`), drawn with `ophis::tools::plot`.

use anyhow::{anyhow, Context, Result};
use ophis::image_io::RgbImage;
use ophis::optics::filmstack::FilmStack;
use ophis::optics::filmtool::rt_deg;
use ophis::tools::plot::{color_map, LineChart, Plot};
use std::path::Path;

/// "n 1 | 1.56:900 | 1.5": outside medium, layers outside in, base.
fn describe(st: &FilmStack) -> String {
    format!("n {} | {} | {}", st.ext(), st, st.base())
}

/// The chart's title: one film without its (ignored) thickness, a stack as it is.
fn describe_chart(st: &FilmStack) -> String {
    match st.layers().next() {
        Some(l) if st.n_layers() == 1 => format!("n {} | {} | {}", st.ext(), l.ior, st.base()),
        _ => describe(st),
    }
}

/// R(λ) for each angle.
pub fn plot(
    st: &FilmStack,
    angles: &[f64],
    wavelengths: &[f64],
    from_inside: bool,
    path: &Path,
) -> Result<()> {
    let mut ch = LineChart::new(
        &format!("Film reflectance, {}", describe(st)),
        "wavelength (nm)",
        "R",
    );
    for &a in angles {
        let pts = wavelengths
            .iter()
            .map(|&l| (l, rt_deg(st, a, l, from_inside).r()))
            .collect();
        ch.add(&format!("{a} deg"), pts);
    }
    let y_max = ch
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(0.0f64, f64::max);
    ch.y_range = Some((0.0, if y_max > 0.0 { y_max * 1.05 } else { 1.0 }));
    ch.render(900, 560)?
        .save_png(path)
        .with_context(|| format!("writing {}", path.display()))
}

/// Colour of reflected D65 over thickness (x) × angle (y).
pub fn chart(st: &FilmStack, range: (f64, f64), from_inside: bool, path: &Path) -> Result<()> {
    let (w, h) = (300usize, 90usize);
    let data = ophis::optics::filmtool::chart(st, range.0, range.1, w, h, 2, from_inside)
        .map_err(|e| anyhow!("--chart: {e}"))?
        .into_iter()
        .map(|c| c.map(|v| v.clamp(0.0, 1.0)))
        .collect();
    let img = RgbImage {
        width: w,
        height: h,
        data,
    };
    let (fig, _) = color_map(
        &img,
        range,
        (0.0, 90.0),
        &format!("Reflected D65, {}", describe_chart(st)),
        if st.n_layers() > 1 {
            "stack thickness (nm), layers scaled together"
        } else {
            "film thickness (nm)"
        },
        "angle (deg)",
        900,
        420,
    )?;
    fig.save_png(path)
        .with_context(|| format!("writing {}", path.display()))
}
