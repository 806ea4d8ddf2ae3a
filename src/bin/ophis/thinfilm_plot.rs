//! The figures of `ophis thinfilm`: R(λ) curves per angle (`--plot`) and the thickness × angle
//! colour chart (`--chart`), drawn with `ophis::plot`.

use anyhow::{Context, Result};
use ophis::image_io::RgbImage;
use ophis::optics::filmtool::FilmStack;
use ophis::plot::{color_map, LineChart};
use std::path::Path;

fn describe(st: &FilmStack) -> String {
    let film = match st.film {
        ophis::bsdf::film::FilmIor::Constant(n) => format!("{n}"),
        ophis::bsdf::film::FilmIor::Keratin => "keratin".to_string(),
    };
    let base = if st.base_k > 0.0 {
        format!("{}+{}i", st.base_n, st.base_k)
    } else {
        format!("{}", st.base_n)
    };
    format!("n {} | {film} | {base}", st.ext)
}

/// R(λ) for each angle.
pub fn plot(st: &FilmStack, angles: &[f64], wavelengths: &[f64], path: &Path) -> Result<()> {
    let mut ch = LineChart::new(
        &format!("Film reflectance, {}, d = {} nm", describe(st), st.d_nm),
        "wavelength (nm)",
        "R",
    );
    for &a in angles {
        let pts = wavelengths.iter().map(|&l| (l, st.rt(a, l).r())).collect();
        ch.add(&format!("{a} deg"), pts);
    }
    let y_max = ch
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(0.0f64, f64::max);
    ch.y_range = Some((0.0, if y_max > 0.0 { y_max * 1.05 } else { 1.0 }));
    ch.render(900, 560)
        .save_png(path)
        .with_context(|| format!("writing {}", path.display()))
}

/// Colour of reflected D65 over thickness (x) × angle (y).
pub fn chart(st: &FilmStack, range: (f64, f64), path: &Path) -> Result<()> {
    let (w, h) = (300usize, 90usize);
    let data = st
        .chart(range.0, range.1, w, h, 2)
        .into_iter()
        .map(|c| c.map(|v| v.clamp(0.0, 1.0)))
        .collect();
    let img = RgbImage {
        width: w,
        height: h,
        data,
    };
    color_map(
        &img,
        range,
        (0.0, 90.0),
        &format!("Reflected D65, {}", describe(st)),
        "film thickness (nm)",
        "angle (deg)",
        900,
        420,
    )
    .save_png(path)
    .with_context(|| format!("writing {}", path.display()))
}
