//! Charts drawn on a [`Canvas`]: line charts with "nice" ticks, colour maps of an image over two
//! labelled axes, and the shared pieces (tick choice, axes frame, legend, colour ramp, palette).
//! The polar lobe chart lives in `polar.rs` and the contact sheet in `sheet.rs`.

use super::canvas::{clip_segment, Canvas};
use crate::image_io::{srgb_to_linear, RgbImage};

pub use super::ticks::{format_tick, nice_range, nice_ticks};

pub use super::polar::PolarChart;
pub use super::sheet::contact_sheet;

/// Eight distinct series colours (linear RGB), chosen to stay apart on white and in print.
pub const PALETTE: [[f32; 3]; 8] = [
    [0.0000, 0.1005, 0.5225], // blue
    [0.8900, 0.2633, 0.0000], // orange
    [0.0100, 0.3185, 0.0331], // green
    [0.6921, 0.0100, 0.0509], // crimson
    [0.2633, 0.0732, 0.6038], // violet
    [0.0000, 0.3801, 0.4480], // teal
    [0.2633, 0.1005, 0.0196], // brown
    [0.1329, 0.1329, 0.1329], // grey
];

pub(crate) const WHITE: [f32; 3] = [1.0; 3];
pub(crate) const BLACK: [f32; 3] = [0.0; 3];
pub(crate) const GRID: [f32; 3] = [0.8; 3];

/// One named curve: `points` are (x, y) data pairs; NaN points break the curve.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub color: [f32; 3],
    pub points: Vec<(f64, f64)>,
}

/// A chart's plotting rectangle in pixels and the data ranges it shows. Data x runs left to
/// right, y bottom to top; the range ends fall on the outer edges of the rectangle's pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlotArea {
    pub left: i64,
    pub top: i64,
    pub width: i64,
    pub height: i64,
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
}

impl PlotArea {
    /// Pixel coordinates (centre convention of `Canvas`) of the data point (x, y).
    pub fn to_pixel(&self, x: f64, y: f64) -> (f64, f64) {
        let (x0, x1) = self.x_range;
        let (y0, y1) = self.y_range;
        let px = self.left as f64 - 0.5 + (x - x0) / (x1 - x0) * self.width as f64;
        let py = (self.top + self.height) as f64 - 0.5 - (y - y0) / (y1 - y0) * self.height as f64;
        (px, py)
    }

    fn pixel_bounds(&self) -> (f64, f64, f64, f64) {
        let (l, t) = (self.left as f64 - 0.5, self.top as f64 - 0.5);
        (l, t, l + self.width as f64, t + self.height as f64)
    }
}

/// Text scale for a figure of this size: 1 up to about 700 pixels, larger beyond.
pub(crate) fn text_scale(width: u32, height: u32) -> u32 {
    (width.min(height) / 700 + 1).min(4)
}

/// Axis texts and ranges shared by line charts and colour maps.
struct Axes<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    x_range: (f64, f64),
    y_range: (f64, f64),
}

impl Axes<'_> {
    fn ticks(&self) -> ((f64, Vec<f64>), (f64, Vec<f64>)) {
        (
            nice_ticks(self.x_range.0, self.x_range.1, 8),
            nice_ticks(self.y_range.0, self.y_range.1, 6),
        )
    }

    /// Where the plotting rectangle goes on a `width` × `height` figure.
    fn area(&self, width: u32, height: u32) -> PlotArea {
        let s = text_scale(width, height) as i64;
        let th = Canvas::text_height(s as u32) as i64;
        let (_, (ys, yt)) = self.ticks();
        let ylab_w = yt
            .iter()
            .map(|&v| Canvas::text_width(&format_tick(v, ys), s as u32) as i64)
            .max()
            .unwrap_or(0);
        let pad = 6 * s;
        let left = pad + if self.y_label.is_empty() { 0 } else { th + pad } + ylab_w + 2 * pad;
        let top = pad
            + if self.title.is_empty() {
                0
            } else {
                2 * th + pad
            };
        let bottom = 2 * pad + th + if self.x_label.is_empty() { 0 } else { th + pad } + pad;
        let right = pad + Canvas::text_width("000", s as u32) as i64 / 2;
        PlotArea {
            left,
            top,
            width: (width as i64 - left - right).max(1),
            height: (height as i64 - top - bottom).max(1),
            x_range: self.x_range,
            y_range: self.y_range,
        }
    }

    /// Title, axis labels, ticks with labels, optional grid, and the frame.
    fn draw(&self, c: &mut Canvas, a: &PlotArea, grid: bool) {
        let s = text_scale(c.width(), c.height());
        let si = s as i64;
        let th = Canvas::text_height(s) as i64;
        let pad = 6 * si;
        let ((xs, xt), (ys, yt)) = self.ticks();
        let bottom = a.top + a.height;
        for &x in &xt {
            let px = a.to_pixel(x, 0.0).0.round() as i64;
            if grid {
                c.fill_rect(px, a.top, 1, a.height, GRID);
            }
            c.fill_rect(px, bottom, 1, 4 * si, BLACK);
            c.text_centered(px, bottom + pad, &format_tick(x, xs), BLACK, s);
        }
        for &y in &yt {
            let py = a.to_pixel(0.0, y).1.round() as i64;
            if grid {
                c.fill_rect(a.left, py, a.width, 1, GRID);
            }
            c.fill_rect(a.left - 4 * si, py, 4 * si, 1, BLACK);
            c.text_right(
                a.left - pad,
                py - th / 2 + si,
                &format_tick(y, ys),
                BLACK,
                s,
            );
        }
        c.rect(a.left - 1, a.top - 1, a.width + 2, a.height + 2, BLACK);
        let cx = a.left + a.width / 2;
        c.text_centered(cx, pad, self.title, BLACK, 2 * s);
        c.text_centered(cx, bottom + 2 * pad + th, self.x_label, BLACK, s);
        c.text_vertical_centered(pad, a.top + a.height / 2, self.y_label, BLACK, s);
    }
}

/// Draws a legend box in the top-right corner of `a` for the series that have labels.
pub(crate) fn draw_legend(c: &mut Canvas, a: &PlotArea, series: &[Series], s: u32) {
    let items: Vec<&Series> = series.iter().filter(|x| !x.label.is_empty()).collect();
    if items.is_empty() {
        return;
    }
    let si = s as i64;
    let th = Canvas::text_height(s) as i64;
    let row = th + 3 * si;
    let swatch = 18 * si;
    let text_w = items
        .iter()
        .map(|x| Canvas::text_width(&x.label, s) as i64)
        .max()
        .unwrap_or(0);
    let (w, h) = (swatch + text_w + 12 * si, row * items.len() as i64 + 4 * si);
    let (x, y) = (a.left + a.width - w - 6 * si, a.top + 6 * si);
    c.fill_rect(x, y, w, h, WHITE);
    c.rect(x, y, w, h, [0.5; 3]);
    for (i, item) in items.iter().enumerate() {
        let ty = y + 3 * si + i as i64 * row;
        let ly = (ty + th / 2 - si) as f32;
        let lx = (x + 4 * si) as f32;
        c.line(
            lx,
            ly,
            lx + swatch as f32 - 4.0 * s as f32,
            ly,
            item.color,
            2.0 * s as f32,
        );
        c.text(x + 8 * si + swatch - 4 * si, ty, &item.label, BLACK, s);
    }
}

/// Draws the series as curves clipped to `a`; NaN points break a curve.
pub(crate) fn draw_series(c: &mut Canvas, a: &PlotArea, series: &[Series], width: f32) {
    let bounds = a.pixel_bounds();
    for sr in series {
        let mut prev: Option<(f64, f64)> = None;
        for &(x, y) in &sr.points {
            if x.is_nan() || y.is_nan() {
                prev = None;
                continue;
            }
            let p = a.to_pixel(x, y);
            let q = prev.unwrap_or(p);
            if let Some((u, v)) = clip_segment(q, p, bounds) {
                c.line(
                    u.0 as f32, u.1 as f32, v.0 as f32, v.1 as f32, sr.color, width,
                );
            }
            prev = Some(p);
        }
    }
}

/// Curves of y against x with axes, ticks, labels, a title and a legend.
#[derive(Clone, Debug, Default)]
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// Shown x interval; `None` fits the data (widened to whole ticks).
    pub x_range: Option<(f64, f64)>,
    /// Shown y interval; `None` fits the data (widened to whole ticks).
    pub y_range: Option<(f64, f64)>,
    pub series: Vec<Series>,
}

impl LineChart {
    /// An empty chart with these texts and automatic ranges.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> LineChart {
        LineChart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..LineChart::default()
        }
    }

    /// Adds a series coloured from `PALETTE` in turn.
    pub fn add(&mut self, label: &str, points: Vec<(f64, f64)>) -> &mut LineChart {
        let color = PALETTE[self.series.len() % PALETTE.len()];
        self.series.push(Series {
            label: label.into(),
            color,
            points,
        });
        self
    }

    /// The ranges shown: the given ones, or the data's extent widened to whole ticks.
    pub fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let pts = self.series.iter().flat_map(|s| s.points.iter());
        let finite = pts.filter(|p| p.0.is_finite() && p.1.is_finite());
        let (mut xl, mut xh, mut yl, mut yh) =
            (f64::INFINITY, -f64::INFINITY, f64::INFINITY, -f64::INFINITY);
        for &(x, y) in finite {
            (xl, xh, yl, yh) = (xl.min(x), xh.max(x), yl.min(y), yh.max(y));
        }
        let valid = |r: (f64, f64)| r.0.is_finite() && r.1.is_finite() && r.0 != r.1;
        let xr = self
            .x_range
            .filter(|&r| valid(r))
            .unwrap_or_else(|| nice_range(xl, xh, 8));
        let yr = self
            .y_range
            .filter(|&r| valid(r))
            .unwrap_or_else(|| nice_range(yl, yh, 6));
        (xr, yr)
    }

    fn axes(&self) -> Axes<'_> {
        let (x_range, y_range) = self.ranges();
        Axes {
            title: &self.title,
            x_label: &self.x_label,
            y_label: &self.y_label,
            x_range,
            y_range,
        }
    }

    /// Where `render(width, height)` puts the plotting rectangle.
    pub fn area(&self, width: u32, height: u32) -> PlotArea {
        self.axes().area(width, height)
    }

    /// Draws the chart on a white `width` × `height` canvas.
    pub fn render(&self, width: u32, height: u32) -> Canvas {
        let mut c = Canvas::new(width, height, WHITE);
        let axes = self.axes();
        let a = axes.area(width, height);
        axes.draw(&mut c, &a, true);
        let s = text_scale(width, height);
        draw_series(&mut c, &a, &self.series, 1.5 * s as f32);
        draw_legend(&mut c, &a, &self.series, s);
        c
    }
}

/// Draws `image` (already in colour) stretched over a chart body with labelled axes: its columns
/// span `x_range` left to right and its rows `y_range` from the bottom row (y_range.0) to the top
/// row (y_range.1). Used for colour-versus-(thickness, angle) charts and heat maps.
#[allow(clippy::too_many_arguments)]
pub fn color_map(
    image: &RgbImage,
    x_range: (f64, f64),
    y_range: (f64, f64),
    title: &str,
    x_label: &str,
    y_label: &str,
    width: u32,
    height: u32,
) -> Canvas {
    let mut c = Canvas::new(width, height, WHITE);
    let axes = Axes {
        title,
        x_label,
        y_label,
        x_range,
        y_range,
    };
    let a = axes.area(width, height);
    c.blit_scaled(image, a.left, a.top, a.width as u32, a.height as u32);
    axes.draw(&mut c, &a, false);
    c
}

/// A colour ramp of ophis's own for heat maps, in linear RGB: value/max in [0, 1] runs from dark
/// violet through blue, teal and green to yellow, interpolated in sRGB between five hand-picked
/// stops so that lightness rises steadily (readable in grey too). NaN, negative values and a
/// non-positive max give the darkest colour; values above max the brightest.
pub fn heat(value: f32, max: f32) -> [f32; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [0.26, 0.02, 0.33],
        [0.24, 0.30, 0.56],
        [0.15, 0.55, 0.55],
        [0.40, 0.77, 0.36],
        [0.98, 0.90, 0.16],
    ];
    let t = if max > 0.0 && value.is_finite() {
        (value / max).clamp(0.0, 1.0)
    } else if value.is_infinite() && value > 0.0 {
        1.0
    } else {
        0.0
    };
    let f = t * (STOPS.len() - 1) as f32;
    let i = (f as usize).min(STOPS.len() - 2);
    let u = f - i as f32;
    std::array::from_fn(|k| srgb_to_linear(STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * u))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_known_line_passes_through_its_pixels() {
        let mut ch = LineChart::new("R(λ)", "wavelength λ (nm)", "reflectance");
        ch.x_range = Some((400.0, 800.0));
        ch.y_range = Some((0.0, 1.0));
        ch.add(
            "y = (x - 400) / 400",
            vec![(400.0, 0.0), (600.0, f64::NAN), (800.0, 1.0)],
        );
        ch.add(
            "flat",
            (0..=40).map(|i| (400.0 + 10.0 * i as f64, 0.25)).collect(),
        );
        let (w, h) = (500, 320);
        let c = ch.render(w, h);
        let a = ch.area(w, h);
        let (x, y) = a.to_pixel(500.0, 0.25);
        let p = c.get(x.round() as i64, y.round() as i64).unwrap();
        assert!(
            p[1] < 0.5 && p[2] < 0.5,
            "the flat series (orange) is drawn at y = 0.25: {p:?}"
        );
        // The first series is broken at the NaN point: nothing blue on its diagonal at x = 600.
        let (x, y) = a.to_pixel(725.0, 0.8125);
        let q = c.get(x.round() as i64, y.round() as i64).unwrap();
        assert!(q[2] > 0.9, "a NaN point breaks the curve: {q:?}");
        // The plot area sits inside the figure with room for labels on the left and below.
        assert!(a.left > 20 && a.top > 10 && a.left + a.width < w as i64);
        assert!(a.top + a.height < h as i64 - 20);
    }

    #[test]
    fn a_connected_line_is_drawn_through_the_middle() {
        let mut ch = LineChart::new("", "", "");
        ch.add("", vec![(0.0, 0.0), (1.0, 1.0)]);
        let c = ch.render(300, 300);
        let a = ch.area(300, 300);
        assert_eq!(ch.ranges(), ((0.0, 1.0), (0.0, 1.0)));
        let (x, y) = a.to_pixel(0.5, 0.5);
        let near = |p: Option<[f32; 3]>| {
            p.is_some_and(|p| (0..3).all(|k| (p[k] - PALETTE[0][k]).abs() < 1e-3))
        };
        assert!(near(c.get(x.round() as i64, y.round() as i64)));
        // Points outside the ranges are clipped to the plot area, never drawn in the margins.
        let mut out = LineChart::new("", "", "");
        out.x_range = Some((0.0, 1.0));
        out.y_range = Some((0.0, 1.0));
        out.add("", vec![(-5.0, 0.5), (5.0, 0.5)]);
        let c = out.render(300, 300);
        let a = out.area(300, 300);
        let y = a.to_pixel(0.0, 0.5).1.round() as i64;
        assert_eq!(c.get(a.left - 3, y), Some(WHITE));
        assert!(near(c.get(a.left + 5, y)));
    }

    #[test]
    fn heat_ramp_rises_in_lightness() {
        assert_ne!(heat(0.0, 1.0), heat(1.0, 1.0));
        let lum = |c: [f32; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        let mut prev = -1.0;
        for i in 0..=20 {
            let l = lum(heat(i as f32, 20.0));
            assert!(l > prev, "lightness must rise monotonically");
            prev = l;
        }
        assert_eq!(heat(f32::NAN, 1.0), heat(0.0, 1.0));
        assert_eq!(heat(5.0, 0.0), heat(0.0, 1.0));
        assert_eq!(heat(7.0, 1.0), heat(1.0, 1.0));
    }

    #[test]
    fn palette_colours_are_distinct() {
        for (i, a) in PALETTE.iter().enumerate() {
            for (j, b) in PALETTE.iter().enumerate().take(i) {
                let d: f32 = (0..3).map(|k| (a[k] - b[k]).abs()).sum();
                assert!(d > 0.15, "{i} vs {j}");
            }
        }
    }

    /// Writes example figures to the temporary directory, for a person to look at.
    #[test]
    fn example_pngs() {
        let dir = std::env::temp_dir();
        let mut ch = LineChart::new(
            "Soap film, d = 400 nm",
            "wavelength λ (nm)",
            "reflectance R",
        );
        for (k, th) in [0.0f64, 30.0, 60.0].iter().enumerate() {
            let pts = (360..=830)
                .step_by(5)
                .map(|l| {
                    let l = l as f64;
                    (
                        l,
                        0.08 + 0.06 * (l / (40.0 + 10.0 * k as f64)).cos() * th.to_radians().cos(),
                    )
                })
                .collect();
            ch.add(&format!("θ = {th}°"), pts);
        }
        ch.render(640, 400)
            .save_png(dir.join("ophis_plot_line.png"))
            .unwrap();

        let mut img = RgbImage::new(64, 32);
        for y in 0..32 {
            for x in 0..64 {
                img.data[y * 64 + x] = heat(x as f32 * (32 - y) as f32, 64.0 * 32.0);
            }
        }
        let c = color_map(
            &img,
            (0.0, 1000.0),
            (0.0, 90.0),
            "colour",
            "d (nm)",
            "θ (°)",
            600,
            360,
        );
        c.save_png(dir.join("ophis_plot_map.png")).unwrap();

        let mut p = PolarChart::new("BSDF lobe, θi = 45°", "f·cos θ");
        p.incident_deg = Some(-45.0);
        for (i, e) in [8.0, 40.0].iter().enumerate() {
            let pts = (-90..=90)
                .map(|d| {
                    let t = (d as f64 - 45.0).to_radians();
                    (
                        d as f64,
                        (0.3 + 0.7 * i as f64) * t.cos().max(0.0).powf(*e) + 0.1,
                    )
                })
                .collect();
            p.add(&format!("exponent {e}"), pts);
        }
        p.render(560, 340)
            .save_png(dir.join("ophis_plot_polar.png"))
            .unwrap();
    }
}
