//! Figures for the tools, drawn with the `plotters` crate on its in-memory bitmap backend with
//! DejaVu Sans (from the `dejavu` crate, so no system font is needed): line charts
//! (`line.rs`), colour maps over labelled axes (`map.rs`), polar lobe charts (`polar.rs`) and
//! contact sheets of renders (`sheet.rs`). What is ours here is only the layout and the
//! conversions: a [`Figure`] is an 8-bit sRGB buffer that plotters draws on and that is written
//! through the project's own PNG writer.

mod line;
mod map;
mod polar;
mod sheet;

pub use line::{LineChart, PlotArea};
pub use map::{color_map, heat};
pub(crate) use polar::PolarChart;
pub use sheet::{contact_sheet, MISSING};

use crate::image_io::{linear_to_srgb, srgb_to_linear, write_png, ImageError, RgbImage};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

/// Eight distinct series colours (sRGB), chosen to stay apart on white and in print.
pub(crate) const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 89, 191),    // blue
    RGBColor(242, 140, 0),   // orange
    RGBColor(25, 153, 51),   // green
    RGBColor(217, 25, 64),   // crimson
    RGBColor(140, 76, 204),  // violet
    RGBColor(0, 166, 179),   // teal
    RGBColor(140, 89, 38),   // brown
    RGBColor(102, 102, 102), // grey
];

/// Grid lines: light enough not to compete with the curves.
pub(crate) const GRID: RGBColor = RGBColor(225, 225, 225);
/// Legend frames and the incident ray.
pub(crate) const MID_GREY: RGBColor = RGBColor(170, 170, 170);

/// The largest figure side drawn, in pixels; larger requests are clamped (a PNG of more would be
/// refused by the writer anyway).
const MAX_SIDE: u32 = 16384;

/// What went wrong drawing a figure (in practice: a font that could not be loaded).
#[derive(Debug, thiserror::Error)]
#[error("drawing a figure: {0}")]
pub struct PlotError(String);

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> PlotError {
        PlotError(e.to_string())
    }
}

/// One named curve: `points` are (x, y) data pairs; NaN points break the curve.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub color: RGBColor,
    pub points: Vec<(f64, f64)>,
}

/// What the line and the polar chart share: a list of series, and a figure to draw them on.
pub trait Plot {
    /// Where the data went on the figure.
    type Area;

    /// The series, in legend order.
    fn series_mut(&mut self) -> &mut Vec<Series>;

    /// Draws the chart over all of `fig`, its texts and lines scaled by `s`; returns where its
    /// data went.
    fn draw_scaled(&self, fig: &mut Figure, s: f64) -> Result<Self::Area, PlotError>;

    /// Draws the chart over all of `fig`, scaled to the figure's size; returns where its data
    /// went.
    fn draw(&self, fig: &mut Figure) -> Result<Self::Area, PlotError> {
        self.draw_scaled(fig, text_scale(fig.width(), fig.height()))
    }

    /// Adds a series coloured from `PALETTE` in turn.
    fn add(&mut self, label: &str, points: Vec<(f64, f64)>) -> &mut Self {
        let list = self.series_mut();
        let color = PALETTE[list.len() % PALETTE.len()];
        list.push(Series {
            label: label.into(),
            color,
            points,
        });
        self
    }

    /// Draws the chart on a white `width` × `height` figure.
    fn render(&self, width: u32, height: u32) -> Result<Figure, PlotError> {
        let mut fig = Figure::new(width, height);
        self.draw(&mut fig)?;
        Ok(fig)
    }
}

/// A chart on a figure, in data coordinates (both the line and the polar chart are drawn so).
type Chart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws a series as separate pieces (where its curve breaks), its legend entry on the first
/// piece; `s` is the figure's text scale.
fn draw_pieces(
    chart: &mut Chart,
    sr: &Series,
    pieces: Vec<Vec<(f64, f64)>>,
    s: f64,
) -> Result<(), PlotError> {
    let style = sr.color.stroke_width((2.0 * s) as u32);
    for (i, piece) in pieces.into_iter().enumerate() {
        let ann = chart.draw_series(LineSeries::new(piece, style))?;
        // One legend entry per series, on its first piece.
        if i == 0 && !sr.label.is_empty() {
            let w = (24.0 * s) as i32;
            ann.label(&sr.label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + w, y)], style));
        }
    }
    Ok(())
}

/// The legend of the labelled series in the upper right corner (none without labels).
fn draw_legend<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    series: &[Series],
    margin: f64,
    label: TextStyle,
    s: f64,
) -> Result<(), PlotError> {
    if series.iter().any(|s| !s.label.is_empty()) {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .margin(margin)
            .legend_area_size(30.0 * s)
            .label_font(label)
            .background_style(WHITE)
            .border_style(MID_GREY)
            .draw()?;
    }
    Ok(())
}

/// A picture being drawn: `width` × `height` pixels of 8-bit sRGB, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Figure {
    /// A white figure; each side is clamped to [1, 16384] pixels.
    pub fn new(width: u32, height: u32) -> Figure {
        let (w, h) = (width.clamp(1, MAX_SIDE), height.clamp(1, MAX_SIDE));
        Figure {
            width: w,
            height: h,
            rgb: vec![255; w as usize * h as usize * 3],
        }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// The sRGB colour at (x, y), or `None` outside the figure.
    pub fn pixel(&self, x: i64, y: i64) -> Option<[u8; 3]> {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return None;
        }
        let i = 3 * (y as usize * self.width as usize + x as usize);
        Some([self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]])
    }

    /// The figure as a linear-RGB image (exactly what `write_png` turns back into these bytes).
    pub(crate) fn to_image(&self) -> RgbImage {
        let lut: Vec<f32> = (0..256).map(|i| srgb_to_linear(i as f32 / 255.0)).collect();
        RgbImage {
            width: self.width as usize,
            height: self.height as usize,
            data: self
                .rgb
                .chunks_exact(3)
                .map(|p| [lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]])
                .collect(),
        }
    }

    /// Writes the figure as an 8-bit sRGB PNG through `image_io` (atomic, errors name the file).
    pub fn save_png(&self, path: impl AsRef<Path>) -> Result<(), ImageError> {
        write_png(path, &self.to_image())
    }

    /// A plotters drawing area over the whole figure, in pixel coordinates.
    pub(crate) fn area(&mut self) -> DrawingArea<BitMapBackend<'_>, plotters::coord::Shift> {
        BitMapBackend::with_buffer(&mut self.rgb, (self.width, self.height)).into_drawing_area()
    }
}

/// Registers DejaVu Sans as plotters' "sans-serif" once per process. If the font failed to
/// parse, drawing text reports `FontUnavailable` as a [`PlotError`] instead of panicking.
fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// Text scale for a figure of this size: 1 up to about 700 pixels, larger beyond, so that a big
/// figure is not all whitespace.
pub(crate) fn text_scale(width: u32, height: u32) -> f64 {
    (width.min(height) / 700 + 1).min(4) as f64
}

/// Black DejaVu Sans of `px` pixels. (Plotters looks the font up when the style is made, so
/// this is where it is registered.)
pub(crate) fn font(px: f64) -> TextStyle<'static> {
    register_font();
    ("sans-serif", px).into_font().color(&BLACK)
}

/// Width and height in pixels of `text` in `style`.
pub(crate) fn text_size(text: &str, style: &TextStyle) -> Result<(u32, u32), PlotError> {
    style
        .font
        .box_size(text)
        .map_err(|e| PlotError(e.to_string()))
}

/// The step between the ticks plotters puts on [lo, hi] when asked for at most `n` of them (it
/// picks 1, 2 or 5 × 10^k), for labelling them all with the same number of decimals.
pub(crate) fn tick_step(lo: f64, hi: f64, n: usize) -> f64 {
    let ticks = RangedCoordf64::from(lo..hi).key_points(n);
    match ticks.as_slice() {
        [a, b, ..] => b - a,
        _ => (hi - lo).abs(),
    }
}

/// A tick label with as many decimals as the step needs ("0.25", "400", never "-0.0").
pub(crate) fn tick_label(v: f64, step: f64) -> String {
    let a = step.abs();
    if a >= 1e6 || (a > 0.0 && a < 1e-4) {
        return format!("{v:e}");
    }
    let decimals = if a > 0.0 {
        (-(a.log10() + 1e-9).floor()).max(0.0) as usize
    } else {
        0
    };
    let s = format!("{v:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// `(lo, hi)` ordered, or `None` unless both are finite and distinct.
pub(crate) fn valid_range((a, b): (f64, f64)) -> Option<(f64, f64)> {
    (a.is_finite() && b.is_finite() && a != b).then(|| (a.min(b), a.max(b)))
}

/// `src` resized to `w` × `h` as 8-bit sRGB: each target pixel averages, in linear light, the
/// source pixels under it (a box filter; nearest-neighbour when enlarging).
pub(crate) fn resample(src: &RgbImage, w: u32, h: u32) -> Vec<u8> {
    let (sw, sh) = (src.width as u64, src.height as u64);
    let mut out = Vec::with_capacity(w as usize * h as usize * 3);
    if sw == 0 || sh == 0 || src.data.len() as u64 != sw * sh {
        out.resize(w as usize * h as usize * 3, 128);
        return out;
    }
    for ty in 0..h as u64 {
        let sy0 = ty * sh / h as u64;
        let sy1 = ((ty + 1) * sh).div_ceil(h as u64).max(sy0 + 1);
        for tx in 0..w as u64 {
            let sx0 = tx * sw / w as u64;
            let sx1 = ((tx + 1) * sw).div_ceil(w as u64).max(sx0 + 1);
            let mut acc = [0.0f32; 3];
            for sy in sy0..sy1 {
                for sx in sx0..sx1 {
                    let p = src.data[(sy * sw + sx) as usize];
                    for k in 0..3 {
                        acc[k] += p[k];
                    }
                }
            }
            let n = ((sy1 - sy0) * (sx1 - sx0)) as f32;
            out.extend(acc.map(|v| (linear_to_srgb(v / n) * 255.0).round() as u8));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figure_bytes_survive_the_png_writer() {
        // Every 8-bit value goes to linear and back unchanged, so `save_png` writes exactly
        // the pixels plotters drew.
        let mut f = Figure::new(256, 1);
        for (i, p) in f.rgb.chunks_exact_mut(3).enumerate() {
            p.copy_from_slice(&[i as u8, 255 - i as u8, (i * 7 % 256) as u8]);
        }
        let path = std::env::temp_dir().join(format!("ophis-plot-{}.png", std::process::id()));
        f.save_png(&path).unwrap();
        let back = crate::image_io::read_image(&path).unwrap();
        let _ = std::fs::remove_file(&path);
        assert_eq!(back, f.to_image());
        let img = f.to_image();
        for (i, p) in img.data.iter().enumerate() {
            let b = p.map(|v| (linear_to_srgb(v) * 255.0).round() as u8);
            assert_eq!(Some(b), f.pixel(i as i64, 0));
        }
        assert_eq!(f.pixel(256, 0), None);
        assert_eq!(f.pixel(0, -1), None);
    }

    #[test]
    fn figure_sizes_are_clamped() {
        let f = Figure::new(0, 0);
        assert_eq!((f.width(), f.height()), (1, 1));
        assert_eq!(f.pixel(0, 0), Some([255; 3]));
    }

    #[test]
    fn ticks_are_round_and_labels_tidy() {
        assert_eq!(tick_step(380.0, 780.0, 8), 50.0);
        assert_eq!(tick_step(0.0, 1.0, 6), 0.2);
        assert!((tick_step(0.0, 0.29, 6) - 0.05).abs() < 1e-12);
        assert_eq!(tick_label(0.6000000001, 0.2), "0.6");
        assert_eq!(tick_label(-1e-17, 0.2), "0.0");
        assert_eq!(tick_label(500.0, 50.0), "500");
        assert_eq!(tick_label(0.025, 0.005), "0.025");
        assert_eq!(tick_label(0.1, 0.05), "0.10");
        assert_eq!(valid_range((1.0, 0.0)), Some((0.0, 1.0)));
        assert_eq!(valid_range((1.0, 1.0)), None);
        assert_eq!(valid_range((f64::NAN, 1.0)), None);
    }

    #[test]
    fn resample_averages_when_shrinking_and_repeats_when_enlarging() {
        let mut img = RgbImage::new(2, 1);
        img.data = vec![[0.0; 3], [1.0; 3]];
        // Half-way in linear light is 188 in sRGB, not 128.
        assert_eq!(resample(&img, 1, 1), vec![188; 3]);
        assert_eq!(
            resample(&img, 4, 1),
            [0, 0, 0, 0, 0, 0, 255, 255, 255, 255, 255, 255]
        );
        let empty = RgbImage::new(0, 0);
        assert_eq!(resample(&empty, 2, 1).len(), 6);
    }
}
