//! `snake`: a procedural snake body — a tube around a smooth S-shaped centreline, with a rounded
//! head, a neck, a long tapering tail and a slightly flattened belly, lying on the ground plane.
//! Built as a closed triangle mesh with smooth normals and UVs made for the `scales` texture.
//!
//! Object space is y-up: the snake lies on y = 0 (its belly touches it along the body; the
//! centre of the section stays at least half a radius up towards the tips), head towards −x. The
//! centreline is x = X·τ − X/2, z = `amplitude`·sin(2π·`waves`·τ + `phase`), τ ∈ [0, 1], with X
//! chosen so that its arc length is `length`; it is resampled by arc length s.
//!
//! Radius along the body, t = s/`length` from the snout (0) to the tail tip (1):
//! r(t) = `radius` · cap(t) · neck(t) · tail(t), with cap = √(1 − (1 − t/h)²) for t < h =
//! `head_length` (a rounded snout), neck = 1 − (1 − `neck`)·exp(−((t − 1.4h)/(0.4h))²) (a
//! narrowing just behind the head), tail = (x(2 − x))^0.8·√(1 − (1 − min(x/0.03, 1))²) with
//! x = (1 − t)/`tail_length` for the last `tail_length` of the body (a taper ending in a point
//! rounded over its last 3 %).
//! Cross-section at angle α (α = −90° is the belly midline): (cos α, sin α·k(α)) in the plane of
//! the sideways and up directions, scaled by r, with k = 1 − `flatten`·sin²α on the belly half and 1
//! on the back: an ellipse-like belly whose height is (1 − `flatten`) of its width, joined to the
//! round back without a crease.
//!
//! UV: u ∈ [0, 1] around the body in proportion to arc length around the cross-section,
//! starting and ending on the belly midline
//! (the seam, where u jumps from 1 to 0, is under the snake); v = s/P along the body, with P the
//! perimeter of the thickest cross-section, so v runs from 0 at the snout to `length`/P at the
//! tail and a `scales` texture with `scale_u` = `scale_v` gives scales as long as they are wide
//! where the body is thickest (they narrow with the body towards head and tail, as real
//! scale rows do). Each tip is a fan of triangles around a single point.
//!
//! | XML name          | type      | default | unit        | meaning                                  |
//! |-------------------|-----------|---------|-------------|------------------------------------------|
//! | `length`          | float     | 4       | world units | length along the centreline              |
//! | `radius`          | float     | 0.12    | world units | largest body radius                      |
//! | `waves`           | float     | 1.25    | —           | periods of the S-curve along the body    |
//! | `amplitude`       | float     | 0.45    | world units | sideways swing of the centreline         |
//! | `phase`           | float     | 0       | degrees     | phase of the swing at the snout          |
//! | `head_length`     | float     | 0.07    | of length   | snout to the back of the head            |
//! | `neck`            | float     | 0.8     | of radius   | neck radius                              |
//! | `tail_length`     | float     | 0.35    | of length   | tapering tail                            |
//! | `flatten`         | float     | 0.25    | —           | belly height deficit (0 = round)         |
//! | `segments_along`  | integer   | 600     | —           | rings along the body                     |
//! | `segments_around` | integer   | 64      | —           | vertices around a ring                   |
//! | `to_world`        | transform | identity| —           | placement                                |
//! | `flip_normals`    | boolean   | false   | —           | normals inwards                          |
//!
//! A picture of the default snake is `docs/snake-shape.png` (`scenes/snake-shape.xml`). Users
//! can still load their own snake with `obj`/`ply`.
//!
//! Limits: planar centreline (no coils stacked in height); the body may intersect itself if
//! `amplitude` is large against the wavelength `length`/`waves`; no separate jaw or eyes.

use super::load::MeshData;
use super::mesh::{MeshError, TriangleMesh};
use crate::math::{Transform, Vec2, Vec3};
use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

/// Shape parameters (see the module header).
#[derive(Clone, Debug, PartialEq)]
pub struct SnakeParams {
    pub length: f32,
    pub radius: f32,
    pub waves: f32,
    pub amplitude: f32,
    /// Radians.
    pub phase: f32,
    pub head_length: f32,
    pub neck: f32,
    pub tail_length: f32,
    pub flatten: f32,
    pub segments_along: u32,
    pub segments_around: u32,
}

impl Default for SnakeParams {
    fn default() -> SnakeParams {
        SnakeParams {
            length: 4.0,
            radius: 0.12,
            waves: 1.25,
            amplitude: 0.45,
            phase: 0.0,
            head_length: 0.07,
            neck: 0.8,
            tail_length: 0.35,
            flatten: 0.25,
            segments_along: 600,
            segments_around: 64,
        }
    }
}

impl SnakeParams {
    /// Body radius at t = s/length (0 at both tips).
    pub fn radius_at(&self, t: f64) -> f64 {
        let h = self.head_length.max(1e-3) as f64;
        let c = 1.0 - (t / h).min(1.0);
        let cap = (1.0 - c * c).max(0.0).sqrt();
        let w = 0.4 * h;
        let neck = 1.0 - (1.0 - self.neck as f64) * (-((t - 1.4 * h) / w).powi(2)).exp();
        let x = ((1.0 - t) / self.tail_length.max(1e-3) as f64).clamp(0.0, 1.0);
        // A taper, rounded off over the last 3 % of the tail so the tip has a normal.
        let e = 1.0 - (x / 0.03).min(1.0);
        let tail = (x * (2.0 - x)).powf(0.8) * (1.0 - e * e).sqrt();
        self.radius as f64 * cap * neck * tail
    }

    /// Cross-section offset (sideways, up) at angle `alpha` for radius `r`.
    fn section(&self, alpha: f64, r: f64) -> (f64, f64) {
        let s = alpha.sin();
        let k = if s < 0.0 {
            1.0 - self.flatten as f64 * s * s
        } else {
            1.0
        };
        (r * alpha.cos(), r * s * k)
    }

    /// Perimeter of the cross-section of radius `radius` (numerically).
    pub fn perimeter(&self) -> f64 {
        let n = 720;
        let pt = |i: usize| self.section(TAU * i as f64 / n as f64, self.radius as f64);
        (0..n)
            .map(|i| {
                let (a, b) = (pt(i), pt(i + 1));
                ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt()
            })
            .sum()
    }
}

/// The centreline resampled by arc length: `n + 1` points (x, z) and unit tangents, s = k·L/n.
fn centreline(p: &SnakeParams, n: usize) -> (Vec<[f64; 2]>, Vec<[f64; 2]>) {
    let (a, w, ph, len) = (
        p.amplitude as f64,
        p.waves as f64,
        p.phase as f64,
        p.length as f64,
    );
    let dense = 8192;
    let curve = |x_span: f64, tau: f64| [x_span * (tau - 0.5), a * (TAU * w * tau + ph).sin()];
    let arc = |x_span: f64| -> Vec<f64> {
        let mut acc = vec![0.0];
        let mut prev = curve(x_span, 0.0);
        for i in 1..=dense {
            let q = curve(x_span, i as f64 / dense as f64);
            let d = ((q[0] - prev[0]).powi(2) + (q[1] - prev[1]).powi(2)).sqrt();
            acc.push(acc[i - 1] + d);
            prev = q;
        }
        acc
    };
    // Shrink the x span until the arc length is `length` (a fixed point; converges fast).
    let mut x_span = len;
    let mut table = arc(x_span);
    for _ in 0..30 {
        x_span *= len / table[dense];
        table = arc(x_span);
    }
    let total = table[dense];
    let mut pts = Vec::with_capacity(n + 1);
    let mut tangents = Vec::with_capacity(n + 1);
    let mut k = 0;
    for i in 0..=n {
        let target = total * i as f64 / n as f64;
        while k + 1 < dense && table[k + 1] < target {
            k += 1;
        }
        let seg = (table[k + 1] - table[k]).max(1e-300);
        let tau = (k as f64 + ((target - table[k]) / seg).clamp(0.0, 1.0)) / dense as f64;
        pts.push(curve(x_span, tau));
        let dx = x_span;
        let dz = a * TAU * w * (TAU * w * tau + ph).cos();
        let l = (dx * dx + dz * dz).sqrt();
        tangents.push([dx / l, dz / l]);
    }
    (pts, tangents)
}

/// Angles α of `n` points evenly spaced by arc length around the cross-section, from the belly
/// midline (α = −90°).
fn section_angles(p: &SnakeParams, n: usize) -> Vec<f64> {
    let dense = 64 * n;
    let alpha = |i: usize| -PI / 2.0 + TAU * i as f64 / dense as f64;
    let mut acc = vec![0.0];
    for i in 0..dense {
        let (a, b) = (p.section(alpha(i), 1.0), p.section(alpha(i + 1), 1.0));
        acc.push(acc[i] + ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt());
    }
    let total = acc[dense];
    let mut out = Vec::with_capacity(n);
    let mut k = 0;
    for m in 0..n {
        let target = total * m as f64 / n as f64;
        while acc[k + 1] < target {
            k += 1;
        }
        let w = (target - acc[k]) / (acc[k + 1] - acc[k]).max(1e-300);
        out.push(alpha(k) + w * (alpha(k + 1) - alpha(k)));
    }
    out
}

/// Vertices, smooth normals, UVs and triangles of the snake (object space).
pub fn snake_geometry(p: &SnakeParams) -> MeshData {
    let na = p.segments_around.max(3) as usize;
    let ns = p.segments_along.max(4) as usize;
    // Rings crowd towards the tips, where the radius changes fastest: s = L·(τ − 0.8·sin(2πτ)/2π).
    let fine = 4 * ns;
    let (line, tan) = centreline(p, fine);
    let ring_t = |k: usize| {
        let tau = k as f64 / ns as f64;
        (tau - 0.8 * (TAU * tau).sin() / TAU).clamp(0.0, 1.0)
    };
    let perimeter = p.perimeter();
    let len = p.length as f64;
    // Arc length around the thickest section, for u proportional to distance around.
    let around = section_angles(p, na);
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    let mut key = Vec::new(); // welded vertex id (seams and tips share one)
    let sample = |t: f64| {
        let f = t * fine as f64;
        let i = (f.floor() as usize).min(fine - 1);
        let w = f - i as f64;
        let mix = |a: [f64; 2], b: [f64; 2]| [a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1])];
        let c = mix(line[i], line[i + 1]);
        let d = mix(tan[i], tan[i + 1]);
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        (c, [d[0] / l, d[1] / l])
    };
    // Rings 1..ns−1; the tips (k = 0, ns) are single points.
    for k in 1..ns {
        let t = ring_t(k);
        let (c, d) = sample(t);
        let r = p.radius_at(t);
        // The belly rests on the ground along the body; towards the tips, where r → 0, the
        // centre stays at least half a body radius up, so the snout and tail tip are round
        // rather than wedged against the ground.
        let big = p.radius as f64;
        let lift = (1.0 - p.flatten as f64) * (r + 0.5 * (big - r) * (1.0 - r / big).powi(2));
        // Sideways unit vector in the ground plane: (−dz, dx) rotated so that (side, up, along)
        // is right-handed and the surface winds outwards.
        let side = [d[1], -d[0]];
        for m in 0..=na {
            let alpha = around[m % na];
            let (sx, sy) = p.section(alpha, r);
            positions.push(
                glam::DVec3::new(c[0] + sx * side[0], lift + sy, c[1] + sx * side[1]).as_vec3(),
            );
            uvs.push(Vec2::new(
                m as f32 / na as f32,
                (t * len / perimeter) as f32,
            ));
            key.push(((k - 1) * na + m % na) as u32);
        }
    }
    let ring = |k: usize, m: usize| ((k - 1) * (na + 1) + m) as u32;
    let mut indices = Vec::with_capacity(2 * na * ns);
    for k in 1..ns - 1 {
        for m in 0..na {
            indices.push([ring(k, m), ring(k, m + 1), ring(k + 1, m + 1)]);
            indices.push([ring(k, m), ring(k + 1, m + 1), ring(k + 1, m)]);
        }
    }
    // Tips: one apex vertex per fan triangle (same position) so that each carries its own u.
    let tip_key_base = ((ns - 1) * na) as u32;
    let tip_lift = 0.5 * (1.0 - p.flatten as f64) * p.radius as f64;
    for (tip, t, k) in [(0u32, 0.0, 1usize), (1, 1.0, ns - 1)] {
        let (c, _) = sample(t);
        let apex = glam::DVec3::new(c[0], tip_lift, c[1]).as_vec3();
        for m in 0..na {
            let a = positions.len() as u32;
            positions.push(apex);
            uvs.push(Vec2::new(
                (m as f32 + 0.5) / na as f32,
                (t * len / perimeter) as f32,
            ));
            key.push(tip_key_base + tip);
            if tip == 0 {
                indices.push([a, ring(k, m + 1), ring(k, m)]);
            } else {
                indices.push([a, ring(k, m), ring(k, m + 1)]);
            }
        }
    }
    let normals = smooth_normals(&positions, &indices, &key);
    MeshData {
        positions,
        normals: Some(normals),
        uvs: Some(uvs),
        indices,
    }
}

/// Area-weighted vertex normals, shared by all vertices with the same `key`.
fn smooth_normals(positions: &[Vec3], indices: &[[u32; 3]], key: &[u32]) -> Vec<Vec3> {
    let n_keys = key.iter().max().map_or(0, |k| *k as usize + 1);
    let mut acc = vec![glam::DVec3::ZERO; n_keys];
    for tri in indices {
        let [a, b, c] = tri.map(|i| positions[i as usize].as_dvec3());
        let n = (b - a).cross(c - a);
        for &i in tri {
            acc[key[i as usize] as usize] += n;
        }
    }
    key.iter()
        .map(|&k| acc[k as usize].normalize_or_zero().as_vec3())
        .collect()
}

impl TriangleMesh {
    /// The `snake` shape.
    pub fn snake(
        p: &SnakeParams,
        to_world: &Transform,
        flip_normals: bool,
    ) -> Result<TriangleMesh, MeshError> {
        let g = snake_geometry(p);
        TriangleMesh::new(
            g.positions,
            g.normals,
            g.uvs,
            g.indices,
            to_world,
            flip_normals,
            false,
        )
    }
}

/// Checks that a mesh is closed and consistently wound: vertices welded by exact position, every
/// edge is used by exactly two triangles, once in each direction, and no triangle has zero area.
pub fn check_closed_mesh(g: &MeshData) -> Result<(), String> {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let weld: Vec<u32> = g
        .positions
        .iter()
        .map(|p| {
            let n = ids.len() as u32;
            *ids.entry(p.to_array().map(f32::to_bits)).or_insert(n)
        })
        .collect();
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    for (i, tri) in g.indices.iter().enumerate() {
        let [a, b, c] = tri.map(|k| g.positions[k as usize]);
        if (b - a).cross(c - a).length() <= 0.0 {
            return Err(format!("triangle {i} is degenerate"));
        }
        let w = tri.map(|k| weld[k as usize]);
        for (x, y) in [(w[0], w[1]), (w[1], w[2]), (w[2], w[0])] {
            if x == y {
                return Err(format!("triangle {i} has a collapsed edge"));
            }
            *edges.entry((x, y)).or_default() += 1;
        }
    }
    for (&(x, y), &n) in &edges {
        if n != 1 || edges.get(&(y, x)) != Some(&1) {
            return Err(format!(
                "edge {x}–{y} is used {n} times this way and {:?} the other",
                edges.get(&(y, x))
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
#[path = "snake_tests.rs"]
mod tests;
