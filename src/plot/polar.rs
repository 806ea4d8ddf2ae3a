//! A polar chart for BSDF lobes in the plane of incidence: the upper half plane, angle 0 (the
//! normal) pointing up, −90° on the left and +90° on the right, radius proportional to the value.

use super::canvas::Canvas;
use super::chart::{
    draw_legend, format_tick, nice_range, nice_ticks, text_scale, PlotArea, Series, BLACK, GRID,
    PALETTE, WHITE,
};

/// Lobes as (angle in degrees, value) series over a half disc, with grid rings and a legend.
#[derive(Clone, Debug, Default)]
pub struct PolarChart {
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

/// Where the half disc lies on a figure: centre and radius in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolarArea {
    pub cx: f64,
    pub cy: f64,
    pub radius: f64,
    pub r_max: f64,
}

impl PolarArea {
    /// Pixel position of the value `r` at `angle_deg` (the value clamped to [0, r_max]).
    pub fn to_pixel(&self, angle_deg: f64, r: f64) -> (f64, f64) {
        let rp = r.clamp(0.0, self.r_max) / self.r_max * self.radius;
        let t = angle_deg.to_radians();
        (self.cx + rp * t.sin(), self.cy - rp * t.cos())
    }
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

    /// Adds a series coloured from `PALETTE` in turn.
    pub fn add(&mut self, label: &str, points: Vec<(f64, f64)>) -> &mut PolarChart {
        let color = PALETTE[self.series.len() % PALETTE.len()];
        self.series.push(Series {
            label: label.into(),
            color,
            points,
        });
        self
    }

    fn r_max(&self) -> f64 {
        if let Some(r) = self.r_max.filter(|r| r.is_finite() && *r > 0.0) {
            return r;
        }
        let m = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1))
            .filter(|v| v.is_finite())
            .fold(0.0f64, f64::max);
        if m > 0.0 {
            nice_range(0.0, m, 4).1
        } else {
            1.0
        }
    }

    /// Where `render(width, height)` puts the half disc.
    pub fn area(&self, width: u32, height: u32) -> PolarArea {
        let s = text_scale(width, height) as f64;
        let th = 9.0 * s;
        let pad = 6.0 * s;
        let label_w = Canvas::text_width("-90°", s as u32) as f64;
        let top =
            pad + if self.title.is_empty() {
                0.0
            } else {
                2.0 * th + pad
            } + th
                + pad;
        let bottom = pad
            + th
            + pad
            + if self.r_label.is_empty() {
                0.0
            } else {
                th + pad
            };
        let side = pad + label_w + pad;
        let radius = ((width as f64 - 2.0 * side) / 2.0)
            .min(height as f64 - top - bottom)
            .max(1.0);
        PolarArea {
            cx: width as f64 / 2.0,
            cy: top + radius,
            radius,
            r_max: self.r_max(),
        }
    }

    /// Draws the chart on a white `width` × `height` canvas.
    pub fn render(&self, width: u32, height: u32) -> Canvas {
        let mut c = Canvas::new(width, height, WHITE);
        let a = self.area(width, height);
        let s = text_scale(width, height);
        let si = s as i64;
        let th = Canvas::text_height(s) as i64;
        let pad = 6 * si;
        let arc = |r: f64| -> Vec<(f32, f32)> {
            (0..=180)
                .map(|i| {
                    let (x, y) = a.to_pixel(i as f64 - 90.0, r);
                    (x as f32, y as f32)
                })
                .collect()
        };
        let (step, ticks) = nice_ticks(0.0, a.r_max, 4);
        for &r in ticks.iter().filter(|&&r| r > 0.0) {
            c.polyline(&arc(r), GRID, 1.0);
            let (x, y) = a.to_pixel(90.0, r);
            c.text_centered(
                x as i64,
                y as i64 + pad / 2,
                &format_tick(r, step),
                BLACK,
                s,
            );
        }
        for deg in (-90i32..=90).step_by(30) {
            let (x, y) = a.to_pixel(deg as f64, a.r_max);
            c.line(a.cx as f32, a.cy as f32, x as f32, y as f32, GRID, 1.0);
            let t = (deg as f64).to_radians();
            let d = a.radius + pad as f64 + th as f64 / 2.0;
            let (lx, ly) = (a.cx + d * t.sin(), a.cy - d * t.cos());
            let label = format!("{deg}°");
            let lw = Canvas::text_width(&label, s) as i64;
            // Side labels sit beside the rim, the others centred on their spoke.
            let left = match deg {
                -90 => (a.cx - a.radius) as i64 - pad - lw,
                90 => (a.cx + a.radius) as i64 + pad,
                _ => lx as i64 - lw / 2,
            };
            // The ±90° labels sit above the baseline, clear of the ring values below it.
            let top = if deg.abs() == 90 {
                a.cy as i64 - th
            } else {
                ly as i64 - th / 2
            };
            c.text(left, top, &label, BLACK, s);
        }
        c.polyline(&arc(a.r_max), BLACK, 1.0);
        let (l, r) = (a.to_pixel(-90.0, a.r_max), a.to_pixel(90.0, a.r_max));
        c.line(l.0 as f32, l.1 as f32, r.0 as f32, r.1 as f32, BLACK, 1.0);
        if let Some(inc) = self.incident_deg.filter(|v| v.is_finite()) {
            let (x, y) = a.to_pixel(inc, a.r_max);
            c.line(
                a.cx as f32,
                a.cy as f32,
                x as f32,
                y as f32,
                [0.45; 3],
                2.0 * s as f32,
            );
        }
        for sr in &self.series {
            let mut run: Vec<(f32, f32)> = Vec::new();
            for &(ang, v) in &sr.points {
                if ang.is_nan() || v.is_nan() {
                    c.polyline(&run, sr.color, 1.5 * s as f32);
                    run.clear();
                    continue;
                }
                let (x, y) = a.to_pixel(ang, v);
                run.push((x as f32, y as f32));
            }
            c.polyline(&run, sr.color, 1.5 * s as f32);
        }
        let cx = a.cx as i64;
        c.text_centered(cx, pad, &self.title, BLACK, 2 * s);
        c.text_centered(cx, a.cy as i64 + 2 * pad + th, &self.r_label, BLACK, s);
        let legend_area = PlotArea {
            left: 0,
            top: (a.cy - a.radius) as i64 - th - pad,
            width: width as i64,
            height: a.radius as i64,
            x_range: (0.0, 1.0),
            y_range: (0.0, 1.0),
        };
        draw_legend(&mut c, &legend_area, &self.series, s);
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lobe_points_land_where_the_mapping_says() {
        let mut p = PolarChart::new("lobe", "f");
        p.r_max = Some(2.0);
        p.incident_deg = Some(-45.0);
        // A circle of radius 1 through every angle.
        p.add("r = 1", (-90..=90).map(|d| (d as f64, 1.0)).collect());
        let c = p.render(400, 260);
        let a = p.area(400, 260);
        assert!(a.radius > 100.0);
        for deg in [-60.0, 0.0, 45.0] {
            let (x, y) = a.to_pixel(deg, 1.0);
            let px = c.get(x.round() as i64, y.round() as i64).unwrap();
            assert!(
                (px[0] - PALETTE[0][0]).abs() < 0.1 && px[2] > 0.3,
                "{deg}: {px:?}"
            );
        }
        // Straight up at half the outer radius.
        let (x, y) = a.to_pixel(0.0, 1.0);
        assert!((x - a.cx).abs() < 1e-9 && (a.cy - y - a.radius / 2.0).abs() < 1e-9);
        // Far outside the disc stays white.
        assert_eq!(c.get(3, 259), Some(WHITE));
    }

    #[test]
    fn automatic_radius_covers_the_data_and_empty_charts_render() {
        let mut p = PolarChart::new("", "");
        p.add("", vec![(0.0, 3.7), (f64::NAN, 1.0), (10.0, f64::INFINITY)]);
        assert_eq!(p.r_max(), 4.0);
        let _ = PolarChart::default().render(50, 20);
        let _ = PolarChart::default().render(1, 1);
    }
}
