//! The snake's body plan: half-width, half-heights and lift along the body, and the
//! cross-section — smooth (C¹) functions of the position t = s/`length` from the snout (0) to
//! the tail tip (1), so that the head flows into the body without a crease (see the formulas
//! in `snake.rs`).

use super::SnakeParams;
use std::f64::consts::PI;

/// Cubic Hermite segment between (x0, y0, slope m0) and (x1, y1, slope m1).
fn hermite(x: f64, (x0, y0, m0): (f64, f64, f64), (x1, y1, m1): (f64, f64, f64)) -> f64 {
    let h = x1 - x0;
    let s = ((x - x0) / h).clamp(0.0, 1.0);
    let (s2, s3) = (s * s, s * s * s);
    (2.0 * s3 - 3.0 * s2 + 1.0) * y0
        + (s3 - 2.0 * s2 + s) * h * m0
        + (-2.0 * s3 + 3.0 * s2) * y1
        + (s3 - s2) * h * m1
}

/// smoothstep with zero slope at both ends.
pub(super) fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Exponent of the pointed part of the tail's taper.
const TAIL_POWER: f64 = 0.75;
/// Slope of the taper at the vent, d(taper)/dx at x = 1: gentle enough that the body's
/// narrowing towards the vent meets it without overshooting (Fritsch–Carlson: a cubic from
/// mid-body to the vent stays monotone while this slope is below 3·0.2/0.28 ≈ 2 in t units).
const TAIL_SLOPE: f64 = 0.25;

/// The tail's taper over x = (1 − t)/`tail_length` ∈ [0, 1]: 0 at the tip, 1 at the vent,
/// concave; a mix of a pointed power law and a parabola with slope `TAIL_SLOPE` at the vent.
fn tail_taper(x: f64) -> f64 {
    let w = 1.0 - TAIL_SLOPE / TAIL_POWER;
    (1.0 - w) * x.powf(TAIL_POWER) + w * x * (2.0 - x)
}
/// Fraction of the tail over which its tip is rounded.
const TAIL_ROUND: f64 = 0.03;
/// Half-width at the vent, of the body's.
const VENT_WIDTH: f64 = 0.8;

impl SnakeParams {
    /// t of the vent, where the tail begins.
    pub(crate) fn vent(&self) -> f64 {
        1.0 - self.tail_length as f64
    }

    /// The half-width envelope over the radius, before the snout and tail tip are rounded: a
    /// piecewise cubic through the anatomy's landmarks (snout, jaw, neck, mid-body, vent), with
    /// slopes that keep it C¹, then the tail's power-law taper.
    fn envelope(&self, t: f64) -> f64 {
        let h = self.head_length as f64;
        let wh = self.head_width as f64;
        let wn = (self.neck as f64).min(wh);
        let tv = self.vent();
        let tail = self.tail_length as f64;
        if t >= tv {
            let x = ((1.0 - t) / tail).clamp(0.0, 1.0);
            return VENT_WIDTH * tail_taper(x);
        }
        // Landmarks (t, half-width, slope). The wedge: 55 % of the head's width at the snout,
        // widest at the jaw joint, then the neck; the body reaches full width by 30 % of the
        // length and narrows slightly to the vent, where the slope meets the tail's.
        let slope_vent = -TAIL_SLOPE * VENT_WIDTH / tail;
        let body_full = (0.3f64).max(3.0 * h).min(0.5 * tv);
        let body_end = (0.62f64).min(tv - 0.1).max(body_full + 0.05);
        let knots = [
            (0.0, 0.55 * wh, 0.6 * wh / h),
            (0.85 * h, wh, 0.0),
            (1.35 * h, wn, 0.0),
            (body_full, 1.0, 0.0),
            (body_end, 1.0, 0.0),
            (tv, VENT_WIDTH, slope_vent),
        ];
        let k = knots.windows(2).position(|w| t < w[1].0).unwrap_or(4);
        hermite(t, knots[k], knots[k + 1])
    }

    /// Body half-width at t (world units; 0 at both tips).
    pub(crate) fn half_width(&self, t: f64) -> f64 {
        let h = self.head_length as f64;
        // The snout is rounded over `snout` of the head's length, the tail tip over its last 3 %.
        let snout = (self.snout as f64 * h).max(1e-6);
        let c = 1.0 - (t / snout).min(1.0);
        let cap = (1.0 - c * c).max(0.0).sqrt();
        let x = (1.0 - t) / (self.tail_length as f64).max(1e-6);
        let e = 1.0 - (x / TAIL_ROUND).min(1.0);
        let tip = (1.0 - e * e).max(0.0).sqrt();
        self.radius as f64 * self.envelope(t.clamp(0.0, 1.0)) * cap * tip
    }

    /// How much of the body's roundness the head has: `head_height` on the head, 1 on the body.
    fn head_blend(&self, t: f64) -> f64 {
        let h = self.head_length as f64;
        smoothstep(0.8 * h, 2.6 * h, t)
    }

    /// Half-heights (above, below) of the section at t over its half-width: the head is
    /// depressed (`head_height` of its width, lower still towards the snout: a wedge in side
    /// view) with a flat lower jaw; the body is round.
    pub(crate) fn height_ratios(&self, t: f64) -> (f64, f64) {
        let h = self.head_length as f64;
        let b = self.head_blend(t);
        let wedge = 0.6 + 0.4 * smoothstep(0.0, 0.9 * h, t);
        let hh = self.head_height as f64;
        let up = hh * wedge + (1.0 - hh * wedge) * b;
        let down = 0.8 * hh + (1.0 - 0.8 * hh) * b;
        (up, down)
    }

    /// Cross-section offset (sideways, up) at angle `alpha` (−90° = belly midline) for
    /// half-width `a` and height ratios `(up, down)`: x = a·cos α, y = a·sin α·k(α)·(1 − f·sin²α
    /// on the belly half), with k blending from `down` at the belly to `up` at the back through
    /// (1 + sin α)/2, so the section is smooth all round.
    #[inline]
    pub fn section(&self, alpha: f64, a: f64, (up, down): (f64, f64)) -> (f64, f64) {
        let s = alpha.sin();
        let w = 0.5 * (1.0 + s);
        let k = down + (up - down) * w;
        let flat = if s < 0.0 {
            1.0 - self.flatten as f64 * s * s
        } else {
            1.0
        };
        (a * alpha.cos(), a * s * k * flat)
    }

    /// Outward unit normal of the section curve at `alpha` (in the section's plane).
    pub(crate) fn section_normal(&self, alpha: f64, a: f64, r: (f64, f64)) -> (f64, f64) {
        let e = 1e-5;
        let (x0, y0) = self.section(alpha - e, a, r);
        let (x1, y1) = self.section(alpha + e, a, r);
        let (dx, dy) = (x1 - x0, y1 - y0);
        let l = (dx * dx + dy * dy).sqrt().max(1e-300);
        // Counter-clockwise curve (α grows from the belly over the side to the back): the
        // outward normal is the tangent turned clockwise.
        (dy / l, -dx / l)
    }

    /// Height of the section's centre above the ground at t: the belly's lowest point rests on
    /// the ground, with the chin rising a little towards the snout.
    pub(crate) fn lift(&self, t: f64) -> f64 {
        let a = self.half_width(t);
        let (_, down) = self.height_ratios(t);
        let h = self.head_length as f64;
        let chin = 0.12 * self.radius as f64 * (1.0 - (t / (0.7 * h)).min(1.0)).powi(2);
        let clearance = 2e-3 * self.radius as f64;
        a * down * (1.0 - self.flatten as f64) + chin + clearance
    }

    /// How far the section at t is rolled about the centreline (radians): `roll` over the
    /// stretch of `roll_span` centred at `roll_at`, easing in and out over its outer quarters.
    pub(crate) fn roll_angle(&self, t: f64) -> f64 {
        if self.roll == 0.0 {
            return 0.0;
        }
        let (c, s) = (self.roll_at as f64, 0.5 * self.roll_span as f64);
        let w = smoothstep(c - s, c - 0.5 * s, t) * (1.0 - smoothstep(c + 0.5 * s, c + s, t));
        self.roll as f64 * w
    }

    /// Arc-length table of the section at t (unit half-width): `n + 1` cumulative lengths at
    /// α = −π/2 + 2π·i/n, and the ratios used.
    pub(crate) fn section_arc(&self, t: f64, n: usize) -> (Vec<f64>, (f64, f64)) {
        let r = self.height_ratios(t);
        let alpha = |i: usize| -PI / 2.0 + 2.0 * PI * i as f64 / n as f64;
        let mut acc = Vec::with_capacity(n + 1);
        acc.push(0.0);
        let mut prev = self.section(alpha(0), 1.0, r);
        for i in 1..=n {
            let q = self.section(alpha(i), 1.0, r);
            let d = ((q.0 - prev.0).powi(2) + (q.1 - prev.1).powi(2)).sqrt();
            acc.push(acc[i - 1] + d);
            prev = q;
        }
        (acc, r)
    }

    /// Perimeter of the section at t (world units).
    pub(crate) fn perimeter_at(&self, t: f64) -> f64 {
        let (acc, _) = self.section_arc(t, 720);
        acc[720] * self.half_width(t)
    }
}

/// The angle α at which a table from [`SnakeParams::section_arc`] reaches arc length `target`.
pub(super) fn angle_at(acc: &[f64], target: f64) -> f64 {
    let n = acc.len() - 1;
    let k = acc.partition_point(|&a| a < target).clamp(1, n);
    let (a0, a1) = (acc[k - 1], acc[k]);
    let w = ((target - a0) / (a1 - a0).max(1e-300)).clamp(0.0, 1.0);
    -PI / 2.0 + 2.0 * PI * (k as f64 - 1.0 + w) / n as f64
}
