//! Line charts: curves of y against x with a title, axis labels, round ticks, a light grid, a
//! frame and a legend (the R(λ) curves of `ophis thinfilm --plot`).

use super::{
    draw_legend, draw_pieces, font, tick_label, tick_step, valid_range, Figure, Plot, PlotError,
    Series, GRID,
};
use plotters::prelude::*;

/// Where a chart's plotting rectangle landed on its figure, in pixels, and the data ranges it
/// shows (x left to right, y bottom to top).
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
    #[cfg(test)]
    /// The pixel the data point (x, y) is drawn at: the ranges' ends fall on the first and
    /// last pixel of the rectangle, rounded as plotters rounds.
    pub(crate) fn to_pixel(self, x: f64, y: f64) -> (i64, i64) {
        let (x0, x1) = self.x_range;
        let (y0, y1) = self.y_range;
        let u = (x - x0) / (x1 - x0) * (self.width - 1) as f64;
        let v = (y - y0) / (y1 - y0) * (self.height - 1) as f64;
        let bottom = self.top + self.height - 1;
        (
            self.left + (u + 1e-3).floor() as i64,
            bottom + (-v - 1e-3).ceil() as i64,
        )
    }

    /// The rectangle of a chart's plotting area.
    pub(crate) fn of<C: CoordTranslate>(
        area: &DrawingArea<BitMapBackend<'_>, C>,
        x: (f64, f64),
        y: (f64, f64),
    ) -> PlotArea {
        let (xs, ys) = area.get_pixel_range();
        PlotArea {
            left: xs.start as i64,
            top: ys.start as i64,
            width: (xs.end - xs.start) as i64,
            height: (ys.end - ys.start) as i64,
            x_range: x,
            y_range: y,
        }
    }
}

/// Curves of y against x.
#[derive(Clone, Debug, Default)]
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// Shown x interval; `None` spans the data.
    pub x_range: Option<(f64, f64)>,
    /// Shown y interval; `None` spans the data.
    pub y_range: Option<(f64, f64)>,
    pub series: Vec<Series>,
}

/// The segment a–b clipped to the box [x0, x1] × [y0, y1] (Liang–Barsky), or `None` when none of
/// it is inside. Plotters does not clip lines to the plotting area, so curves are cut here.
fn clip(
    a: (f64, f64),
    b: (f64, f64),
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Option<[(f64, f64); 2]> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x0),
        (dx, x1 - a.0),
        (-dy, a.1 - y0),
        (dy, y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    if t0 > t1 {
        return None;
    }
    // Unclipped ends are returned exactly, so that consecutive segments still join.
    let p = |t: f64| (a.0 + t * dx, a.1 + t * dy);
    Some([
        if t0 == 0.0 { a } else { p(t0) },
        if t1 == 1.0 { b } else { p(t1) },
    ])
}

/// The visible pieces of a curve: runs of consecutive finite points, cut where the curve leaves
/// the box or meets a NaN.
fn runs(points: &[(f64, f64)], xr: (f64, f64), yr: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    fn flush(run: &mut Vec<(f64, f64)>, out: &mut Vec<Vec<(f64, f64)>>) {
        if run.len() > 1 {
            out.push(std::mem::take(run));
        }
        run.clear();
    }
    let (mut out, mut run) = (Vec::new(), Vec::new());
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    for w in points.windows(2) {
        let piece = if finite(&w[0]) && finite(&w[1]) {
            clip(w[0], w[1], xr, yr)
        } else {
            None
        };
        match piece {
            Some([a, b]) => {
                if run.last() != Some(&a) {
                    flush(&mut run, &mut out);
                    run.push(a);
                }
                run.push(b);
            }
            None => flush(&mut run, &mut out),
        }
    }
    flush(&mut run, &mut out);
    out
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

    /// The ranges shown: the given ones when valid, else the finite data's extent (a unit
    /// interval around it when it is a single value, (0, 1) when there is none).
    pub(crate) fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let pts = self.series.iter().flat_map(|s| s.points.iter());
        let finite = pts.filter(|p| p.0.is_finite() && p.1.is_finite());
        let (mut xl, mut xh, mut yl, mut yh) =
            (f64::INFINITY, -f64::INFINITY, f64::INFINITY, -f64::INFINITY);
        for &(x, y) in finite {
            (xl, xh, yl, yh) = (xl.min(x), xh.max(x), yl.min(y), yh.max(y));
        }
        let fit = |lo: f64, hi: f64| match (lo.is_finite(), lo == hi) {
            (false, _) => (0.0, 1.0),
            (true, true) => (lo - 0.5, hi + 0.5),
            (true, false) => (lo, hi),
        };
        let xr = self
            .x_range
            .and_then(valid_range)
            .unwrap_or_else(|| fit(xl, xh));
        let yr = self
            .y_range
            .and_then(valid_range)
            .unwrap_or_else(|| fit(yl, yh));
        (xr, yr)
    }
}

impl Plot for LineChart {
    type Area = PlotArea;

    fn series_mut(&mut self) -> &mut Vec<Series> {
        &mut self.series
    }

    /// Draws the chart; returns where the plotting rectangle went.
    fn draw_scaled(&self, fig: &mut Figure, s: f64) -> Result<PlotArea, PlotError> {
        let (xr, yr) = self.ranges();
        let root = fig.area();
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, font(22.0 * s))
            .margin(12.0 * s)
            .x_label_area_size(44.0 * s)
            .y_label_area_size(56.0 * s)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
        let (xs, ys) = (tick_step(xr.0, xr.1, 8), tick_step(yr.0, yr.1, 6));
        let (fx, fy) = (|v: &f64| tick_label(*v, xs), |v: &f64| tick_label(*v, ys));
        chart
            .configure_mesh()
            .x_labels(8)
            .y_labels(6)
            .max_light_lines(0)
            .bold_line_style(GRID)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style(font(14.0 * s))
            .axis_desc_style(font(15.0 * s))
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .draw()?;
        let area = PlotArea::of(chart.plotting_area(), xr, yr);
        for sr in &self.series {
            let mut pieces = runs(&sr.points, xr, yr);
            if pieces.is_empty() {
                // Nothing visible: an empty piece still carries the legend entry.
                pieces.push(Vec::new());
            }
            draw_pieces(&mut chart, sr, pieces, s)?;
        }
        let frame = [(xr.0, yr.0), (xr.1, yr.1)];
        chart.draw_series(std::iter::once(Rectangle::new(frame, BLACK)))?;
        draw_legend(&mut chart, &self.series, 8.0 * s, font(14.0 * s), s)?;
        root.present()?;
        Ok(area)
    }
}

#[cfg(test)]
mod tests {
    use super::super::PALETTE;
    use super::*;

    fn rgb(c: RGBColor) -> [u8; 3] {
        [c.0, c.1, c.2]
    }

    #[test]
    fn clipping_keeps_the_inside_and_breaks_at_nan() {
        let b = ((0.0, 1.0), (0.0, 1.0));
        assert_eq!(
            clip((-1.0, 0.5), (2.0, 0.5), b.0, b.1),
            Some([(0.0, 0.5), (1.0, 0.5)])
        );
        assert_eq!(clip((-1.0, 2.0), (-0.5, 3.0), b.0, b.1), None);
        let r = runs(
            &[
                (0.0, 0.0),
                (0.5, 0.5),
                (f64::NAN, 0.0),
                (0.6, 0.6),
                (0.9, 0.9),
            ],
            b.0,
            b.1,
        );
        assert_eq!(
            r,
            vec![vec![(0.0, 0.0), (0.5, 0.5)], vec![(0.6, 0.6), (0.9, 0.9)]]
        );
        // Leaving and re-entering the box starts a new piece.
        let r = runs(&[(0.0, 0.5), (0.5, 2.0), (1.0, 0.5)], b.0, b.1);
        assert_eq!(r.len(), 2);
        assert!(runs(&[(0.5, 0.5)], b.0, b.1).is_empty());
    }

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
        let mut fig = Figure::new(500, 320);
        let a = ch.draw(&mut fig).unwrap();
        let (x, y) = a.to_pixel(500.0, 0.25);
        assert_eq!(
            fig.pixel(x, y),
            Some(rgb(PALETTE[1])),
            "the flat series at y = 0.25"
        );
        // The first series is broken at its NaN point: nothing of it anywhere in the chart.
        let blue = rgb(PALETTE[0]);
        // (The legend, with its blue swatch, sits in the top third.)
        let found = (a.top + a.height / 3..a.top + a.height)
            .flat_map(|y| (a.left..a.left + a.width).map(move |x| (x, y)))
            .any(|(x, y)| fig.pixel(x, y) == Some(blue));
        assert!(!found, "a NaN point breaks the curve");
        // Room for the labels on the left and below, inside the figure.
        assert!(a.left > 40 && a.top > 20 && a.left + a.width < 500);
        assert!(a.top + a.height < 320 - 30);
        // The title is drawn: dark pixels in the top band.
        let dark = (0..a.top).any(|y| (0..500).any(|x| fig.pixel(x, y).is_some_and(|p| p[0] < 80)));
        assert!(dark);
    }

    #[test]
    fn a_connected_line_is_drawn_and_outside_points_are_clipped() {
        let mut ch = LineChart::new("", "", "");
        ch.add("", vec![(0.0, 0.0), (1.0, 1.0)]);
        assert_eq!(ch.ranges(), ((0.0, 1.0), (0.0, 1.0)));
        let mut fig = Figure::new(300, 300);
        let a = ch.draw(&mut fig).unwrap();
        let (x, y) = a.to_pixel(0.5, 0.5);
        let near = (-2..=2).any(|d| fig.pixel(x + d, y) == Some(rgb(PALETTE[0])));
        assert!(near, "the diagonal passes through the middle");
        let mut out = LineChart::new("", "", "");
        out.x_range = Some((0.0, 1.0));
        out.y_range = Some((0.0, 1.0));
        out.add("", vec![(-5.0, 0.5), (5.0, 0.5)]);
        let mut fig = Figure::new(300, 300);
        let a = out.draw(&mut fig).unwrap();
        let y = a.to_pixel(0.0, 0.5).1;
        assert_eq!(
            fig.pixel(a.left - 4, y),
            Some([255; 3]),
            "nothing in the margin"
        );
        assert_eq!(fig.pixel(a.left + 5, y), Some(rgb(PALETTE[0])));
    }

    #[test]
    fn degenerate_charts_render() {
        let mut ch = LineChart::new("", "", "");
        ch.add("x", vec![(f64::NAN, 1.0), (2.0, f64::INFINITY)]);
        ch.x_range = Some((3.0, 3.0));
        assert_eq!(ch.ranges(), ((0.0, 1.0), (0.0, 1.0)));
        for (w, h) in [(1, 1), (40, 20), (2000, 90)] {
            let f = ch.render(w, h).unwrap();
            assert_eq!((f.width(), f.height()), (w, h));
        }
        let mut one = LineChart::new("", "", "");
        one.add("", vec![(2.0, 5.0)]);
        assert_eq!(one.ranges(), ((1.5, 2.5), (4.5, 5.5)));
    }
}
