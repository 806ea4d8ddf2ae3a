//! Poses: the snake's centreline on the ground, resampled by arc length from the snout, and the
//! check that the body does not pass through itself.

use super::{Pose, SnakeParams};
use std::f64::consts::TAU;

/// A planar curve in the ground plane: points (x, z) and unit tangents, `n + 1` samples evenly
/// spaced by arc length from the snout (index 0) to the tail tip.
pub(crate) struct Centreline {
    pub points: Vec<[f64; 2]>,
    pub tangents: Vec<[f64; 2]>,
}

impl Centreline {
    /// Point and unit tangent at t ∈ [0, 1] (linear between samples).
    pub fn at(&self, t: f64) -> ([f64; 2], [f64; 2]) {
        let n = self.points.len() - 1;
        let f = (t.clamp(0.0, 1.0) * n as f64).min(n as f64 - 1e-9);
        let i = f.floor() as usize;
        let w = f - i as f64;
        let mix = |a: [f64; 2], b: [f64; 2]| [a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1])];
        let c = mix(self.points[i], self.points[i + 1]);
        let d = mix(self.tangents[i], self.tangents[i + 1]);
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt().max(1e-300);
        (c, [d[0] / l, d[1] / l])
    }
}

/// Resamples a dense parametric curve `f(τ)`, τ ∈ [0, 1], by arc length into `n + 1` points,
/// with tangents by central differences of the resampled curve's parameter.
fn resample(f: impl Fn(f64) -> [f64; 2], n: usize) -> Centreline {
    let dense = 16384;
    let mut table = Vec::with_capacity(dense + 1);
    table.push(0.0);
    let mut prev = f(0.0);
    for i in 1..=dense {
        let q = f(i as f64 / dense as f64);
        table.push(table[i - 1] + ((q[0] - prev[0]).powi(2) + (q[1] - prev[1]).powi(2)).sqrt());
        prev = q;
    }
    let total = table[dense];
    let mut points = Vec::with_capacity(n + 1);
    let mut tangents = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let target = total * i as f64 / n as f64;
        let k = table.partition_point(|&a| a < target).clamp(1, dense);
        let seg = (table[k] - table[k - 1]).max(1e-300);
        let tau = (k as f64 - 1.0 + ((target - table[k - 1]) / seg).clamp(0.0, 1.0)) / dense as f64;
        points.push(f(tau));
        let e = 0.25 / dense as f64;
        let (a, b) = (f((tau - e).max(0.0)), f((tau + e).min(1.0)));
        let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
        let l = (dx * dx + dz * dz).sqrt().max(1e-300);
        tangents.push([dx / l, dz / l]);
    }
    Centreline { points, tangents }
}

/// Length of the curve τ ↦ f(τ), τ ∈ [0, 1] (polyline of `dense` pieces).
fn curve_length(f: &impl Fn(f64) -> [f64; 2], dense: usize) -> f64 {
    let mut prev = f(0.0);
    let mut total = 0.0;
    for i in 1..=dense {
        let q = f(i as f64 / dense as f64);
        total += ((q[0] - prev[0]).powi(2) + (q[1] - prev[1]).powi(2)).sqrt();
        prev = q;
    }
    total
}

/// The centreline of a pose, `n + 1` samples.
pub(crate) fn centreline(p: &SnakeParams, n: usize) -> Centreline {
    let len = p.length as f64;
    match p.pose {
        Pose::SCurve => {
            let (a, w, ph) = (p.amplitude as f64, p.waves as f64, p.phase as f64);
            let curve =
                |span: f64| move |tau: f64| [span * (tau - 0.5), a * (TAU * w * tau + ph).sin()];
            // Shrink the x span until the arc length is `length` (a fixed point; converges fast).
            let mut span = len;
            for _ in 0..30 {
                span *= len / curve_length(&curve(span), 8192);
            }
            resample(curve(span), n)
        }
        Pose::Coil => {
            // An Archimedean spiral r = r0 + g·φ, tail at the centre, head outside: successive
            // turns lie `spacing` apart, the body's width plus a gap.
            let r0 = p.coil_radius as f64 * p.radius as f64;
            let g = p.coil_spacing as f64 * 2.0 * p.radius as f64 / TAU;
            // Arc length from φ = 0 to Φ: ∫ √(r² + g²) dφ, found by bisection on Φ.
            let length_to = |phi: f64| {
                let m = 4096;
                (0..m)
                    .map(|i| {
                        let f = phi * (i as f64 + 0.5) / m as f64;
                        ((r0 + g * f).powi(2) + g * g).sqrt() * phi / m as f64
                    })
                    .sum::<f64>()
            };
            let mut hi = 1.0;
            while length_to(hi) < len {
                hi *= 2.0;
            }
            let (lo, hi) = crate::math::bisect_increasing(length_to, len, (0.0, hi), 60);
            let big_phi = 0.5 * (lo + hi);
            let turn = p.phase as f64;
            // τ = 0 is the snout (outside), τ = 1 the tail tip (centre).
            resample(
                move |tau: f64| {
                    let phi = big_phi * (1.0 - tau);
                    let r = r0 + g * phi;
                    [r * (phi + turn).cos(), r * (phi + turn).sin()]
                },
                n,
            )
        }
    }
}

/// Where the body passes through itself, if it does: its footprint at each of `n` stations is
/// the segment across the body (the section's width, perpendicular to the centreline, and a
/// margin of 5 %); two stations' segments crossing means two sections meet. Adjacent stations
/// are skipped, and instead a bend tighter than the half-width (which would fold the inside of
/// the curve) is reported. Returns the two arc positions t of the first collision found.
pub(crate) fn self_intersection(p: &SnakeParams, n: usize) -> Option<(f64, f64)> {
    let line = centreline(p, n);
    let seg: Vec<([f64; 2], [f64; 2])> = (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let (c, d) = (line.points[i], line.tangents[i]);
            let a = 1.05 * p.half_width(t);
            let side = [d[1] * a, -d[0] * a];
            (
                [c[0] - side[0], c[1] - side[1]],
                [c[0] + side[0], c[1] + side[1]],
            )
        })
        .collect();
    // Bends: turning angle between neighbours over their spacing is the curvature.
    let ds = p.length as f64 / n as f64;
    for i in 1..n {
        let (a, b) = (line.tangents[i - 1], line.tangents[i + 1]);
        let turn = (a[0] * b[1] - a[1] * b[0]).abs().min(1.0).asin();
        let curvature = turn / (2.0 * ds);
        if curvature * p.half_width(i as f64 / n as f64) >= 1.0 {
            return Some((i as f64 / n as f64, i as f64 / n as f64));
        }
    }
    let cross = |p1: [f64; 2], p2: [f64; 2], p3: [f64; 2]| {
        (p2[0] - p1[0]) * (p3[1] - p1[1]) - (p2[1] - p1[1]) * (p3[0] - p1[0])
    };
    for i in 0..=n {
        let (a0, a1) = seg[i];
        for (j, &(b0, b1)) in seg.iter().enumerate().skip(i + 2) {
            let d1 = cross(b0, b1, a0);
            let d2 = cross(b0, b1, a1);
            let d3 = cross(a0, a1, b0);
            let d4 = cross(a0, a1, b1);
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                return Some((i as f64 / n as f64, j as f64 / n as f64));
            }
        }
    }
    None
}
