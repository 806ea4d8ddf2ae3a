//! A polar chart for BSDF lobes in the plane of incidence: the upper half plane, angle 0 (the
//! normal) pointing up, −90° on the left and +90° on the right, radius proportional to the value.
//! Plotters has no polar coordinates, so the chart is a Cartesian one with equal pixel scales
//! on both axes and the rings, spokes and lobes are drawn as curves in it.

use super::{
    draw_legend, draw_pieces, font, tick_label, tick_step, Figure, Plot, PlotError, Series, GRID,
    MID_GREY,
};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Lobes as (angle in degrees, value) series over a half disc, with grid rings and a legend.
#[derive(Clone, Debug, Default)]
pub(crate) struct PolarChart {
    pub title: String,
    /// What the radius shows, written under the chart (e.g. "f·cos θ").
    pub r_label: String,
    /// Value at the outer ring; `None` fits the data (rounded up to a whole tick).
    pub r_max: Option<f64>,
    /// Direction of incidence in degrees, drawn as a grey ray, if any.
    pub incident_deg: Option<f64>,
    /// Points are (angle in degrees from the normal, value); NaN points break a curve.
    pub series: Vec<Series>,
}

/// Where the half disc landed on a figure: centre and radius in pixels, value at the rim.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PolarArea {
    pub cx: f64,
    pub cy: f64,
    pub radius: f64,
    pub r_max: f64,
}

impl PolarArea {
    #[cfg(test)]
    /// Pixel position of the value `r` at `angle_deg` (the value clamped to [0, r_max]).
    pub(crate) fn to_pixel(self, angle_deg: f64, r: f64) -> (f64, f64) {
        let rp = r.clamp(0.0, self.r_max) / self.r_max * self.radius;
        let t = angle_deg.to_radians();
        (self.cx + rp * t.sin(), self.cy - rp * t.cos())
    }
}

/// The point of value `r` at `deg` in the chart's data coordinates (x right, y up).
fn polar(deg: f64, r: f64) -> (f64, f64) {
    let t = deg.to_radians();
    (r * t.sin(), r * t.cos())
}

impl PolarChart {
    /// An empty chart with a title and a radius label.
    pub fn new(title: &str, r_label: &str) -> PolarChart {
        PolarChart {
            title: title.into(),
            r_label: r_label.into(),
            ..PolarChart::default()
        }
    }

    /// The value at the rim and the ring spacing: the given rim value, or the largest finite
    /// value rounded up to a whole ring.
    fn rim_and_step(&self) -> (f64, f64) {
        if let Some(r) = self.r_max.filter(|r| r.is_finite() && *r > 0.0) {
            return (r, tick_step(0.0, r, 4));
        }
        let values = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1));
        let m = values.filter(|v| v.is_finite()).fold(0.0f64, f64::max);
        if m > 0.0 {
            let step = tick_step(0.0, m, 4);
            ((m / step - 1e-9).ceil() * step, step)
        } else {
            (1.0, 0.25)
        }
    }
}

impl Plot for PolarChart {
    type Area = PolarArea;

    fn series_mut(&mut self) -> &mut Vec<Series> {
        &mut self.series
    }

    /// Draws the chart; returns where the half disc went.
    fn draw_scaled(&self, fig: &mut Figure, s: f64) -> Result<PolarArea, PlotError> {
        let (label, pad) = (font(14.0 * s), (6.0 * s) as i32);
        let th = (16.0 * s) as i32;
        let (r_max, step) = self.rim_and_step();
        let root = fig.area();
        let body = if self.title.is_empty() {
            root.clone()
        } else {
            root.titled(&self.title, font(22.0 * s))?
        };
        let (bw, bh) = body.dim_in_pixel();
        let foot = if self.r_label.is_empty() { 0 } else { th + pad };
        let (body, foot_area) = body.split_vertically(bh.saturating_sub(foot as u32));
        if foot > 0 {
            let (fw, _) = foot_area.dim_in_pixel();
            let centre = label.pos(Pos::new(HPos::Center, VPos::Top));
            foot_area.draw_text(&self.r_label, &centre, (fw as i32 / 2, 0))?;
        }
        let bh = bh as i32 - foot;
        // Room above the 0° label, beside the ±90° labels and below for the ring values.
        let side = body.estimate_text_size("-90°", &label)?.0 as i32 + 2 * pad;
        let (top, bottom) = (th + pad, th + pad);
        let radius = ((bw as i32 - 2 * side) / 2).min(bh - top - bottom).max(1);
        let k = r_max / radius as f64; // data units per pixel, the same on both axes
        let half_w = (bw as f64 - 1.0) / 2.0 * k;
        let (y0, y1) = (-bottom as f64 * k, (bh - 1 - bottom) as f64 * k);
        let mut chart = ChartBuilder::on(&body).build_cartesian_2d(-half_w..half_w, y0..y1)?;
        let (xs, ys) = body.get_pixel_range();
        let area = PolarArea {
            cx: xs.start as f64 + (bw as f64 - 1.0) / 2.0,
            cy: (ys.start + bh - 1 - bottom) as f64,
            radius: radius as f64,
            r_max,
        };
        let arc = |r: f64| (0..=180).map(move |i| polar(i as f64 - 90.0, r));
        let below = label.pos(Pos::new(HPos::Center, VPos::Top));
        let mut labelled: Vec<f64> = (1..=8)
            .map(|i| i as f64 * step)
            .take_while(|&r| r <= r_max * (1.0 + 1e-9))
            .collect();
        if labelled.last().is_none_or(|&r| r < r_max * (1.0 - 1e-9)) {
            labelled.push(r_max); // a given rim value that is not a tick is labelled too
        }
        for &r in &labelled {
            chart.draw_series(LineSeries::new(arc(r), GRID))?;
            let text = Text::new(tick_label(r, step), (0, pad / 2), below.clone());
            chart.draw_series(std::iter::once(EmptyElement::at((r, 0.0)) + text))?;
        }
        for deg in (-90i32..=90).step_by(30) {
            let d = deg as f64;
            chart.draw_series(LineSeries::new([(0.0, 0.0), polar(d, r_max)], GRID))?;
            // Side labels sit beside the rim above the baseline, the others outside the rim.
            let (anchor, off) = match deg {
                -90 => (Pos::new(HPos::Right, VPos::Bottom), (-pad, -pad / 2)),
                90 => (Pos::new(HPos::Left, VPos::Bottom), (pad, -pad / 2)),
                _ => (Pos::new(HPos::Center, VPos::Center), (0, 0)),
            };
            let at = polar(d, r_max + (pad as f64 + th as f64 / 2.0) * k);
            let at = if deg.abs() == 90 { polar(d, r_max) } else { at };
            let text = Text::new(format!("{deg}°"), off, label.pos(anchor));
            chart.draw_series(std::iter::once(EmptyElement::at(at) + text))?;
        }
        chart.draw_series(LineSeries::new(arc(r_max), BLACK))?;
        chart.draw_series(LineSeries::new(
            [polar(-90.0, r_max), polar(90.0, r_max)],
            BLACK,
        ))?;
        if let Some(inc) = self.incident_deg.filter(|v| v.is_finite()) {
            let ray = MID_GREY.stroke_width((2.0 * s) as u32);
            chart.draw_series(LineSeries::new([(0.0, 0.0), polar(inc, r_max)], ray))?;
        }
        for sr in &self.series {
            let mut pieces: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for &(ang, v) in &sr.points {
                if ang.is_nan() || v.is_nan() {
                    pieces.push(Vec::new());
                } else if let Some(last) = pieces.last_mut() {
                    last.push(polar(ang, v.clamp(0.0, r_max)));
                }
            }
            draw_pieces(&mut chart, sr, pieces, s)?;
        }
        draw_legend(&mut chart, &self.series, 4.0 * s, label.clone(), s)?;
        root.present()?;
        Ok(area)
    }
}

#[cfg(test)]
mod tests {
    use super::super::PALETTE;
    use super::*;

    #[test]
    fn lobe_points_land_where_the_mapping_says() {
        let mut p = PolarChart::new("lobe", "f");
        p.r_max = Some(2.0);
        p.incident_deg = Some(-45.0);
        // A circle of radius 1 through every angle.
        p.add("r = 1", (-90..=90).map(|d| (d as f64, 1.0)).collect());
        let mut fig = Figure::new(400, 260);
        let a = p.draw(&mut fig).unwrap();
        assert!(a.radius > 80.0, "{a:?}");
        let blue = [PALETTE[0].0, PALETTE[0].1, PALETTE[0].2];
        for deg in [-60.0, 0.0, 45.0] {
            let (x, y) = a.to_pixel(deg, 1.0);
            let (x, y) = (x.round() as i64, y.round() as i64);
            let hit = (-1..=1).any(|d| (-1..=1).any(|e| fig.pixel(x + d, y + e) == Some(blue)));
            assert!(hit, "{deg}° at ({x}, {y})");
        }
        // The incident ray is grey, at −45° outside the lobe.
        let (x, y) = a.to_pixel(-45.0, 1.6);
        let grey = [MID_GREY.0, MID_GREY.1, MID_GREY.2];
        let (x, y) = (x.round() as i64, y.round() as i64);
        assert!((-1..=1).any(|d| fig.pixel(x + d, y) == Some(grey)));
        // Straight up at half the outer radius.
        let (x, y) = a.to_pixel(0.0, 1.0);
        assert!((x - a.cx).abs() < 1e-9 && (a.cy - y - a.radius / 2.0).abs() < 1e-9);
        // The bottom-left corner stays white.
        assert_eq!(fig.pixel(3, 259), Some([255; 3]));
    }

    #[test]
    fn automatic_radius_covers_the_data_and_empty_charts_render() {
        let mut p = PolarChart::new("", "");
        p.add("", vec![(0.0, 3.7), (f64::NAN, 1.0), (10.0, f64::INFINITY)]);
        assert_eq!(p.rim_and_step(), (4.0, 1.0));
        p.r_max = Some(0.3);
        assert_eq!(p.rim_and_step(), (0.3, 0.1));
        for (w, h) in [(50, 20), (1, 1), (720, 460)] {
            let f = PolarChart::default().render(w, h).unwrap();
            assert_eq!((f.width(), f.height()), (w, h));
            let _ = p.render(w, h).unwrap();
        }
    }
}
