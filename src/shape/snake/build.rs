//! Building the snake's mesh: rings of vertices along the centreline, split into the parts that
//! carry their own materials (body, belly, head, eyes), each with its own UVs.

use super::pose::{centreline, Centreline};
use super::profile::angle_at;
use super::{Part, SnakeParams};
use crate::math::{Vec2, Vec3};
use crate::shape::load::MeshData;
use glam::DVec3;
use std::f64::consts::PI;

/// Samples of the section's arc-length table.
const SECTION_SAMPLES: usize = 1024;
/// Dense samples along the body for v and ring placement.
const ALONG: usize = 8192;

/// The global ring mesh before it is split into parts.
struct Rings {
    /// t of every ring; ring 0 and the last are the tips (single points).
    t: Vec<f64>,
    /// Positions, `around` per interior ring, then the two tip points.
    positions: Vec<DVec3>,
    around: usize,
    /// Vertices on the dorsal arc (the rest, `around − dorsal`, are across the belly).
    dorsal: usize,
}

impl Rings {
    fn index(&self, k: usize, m: usize) -> usize {
        let interior = self.t.len() - 2;
        if k == 0 {
            interior * self.around
        } else if k == self.t.len() - 1 {
            interior * self.around + 1
        } else {
            (k - 1) * self.around + m % self.around
        }
    }
}

impl SnakeParams {
    /// t of the rings: spaced in proportion to the local half-width (so the quads near the tips
    /// are not long slivers), one exactly at the back of the head.
    fn ring_stations(&self) -> Vec<f64> {
        let n = self.segments_along.max(8) as usize;
        let h = self.head_length as f64;
        let density = |t: f64| 1.0 / (self.half_width(t) / self.radius as f64).clamp(0.12, 1.0);
        let cumulative = |a: f64, b: f64| -> Vec<f64> {
            let mut acc = vec![0.0];
            for i in 0..ALONG {
                let t = a + (b - a) * (i as f64 + 0.5) / ALONG as f64;
                acc.push(acc[i] + density(t) * (b - a) / ALONG as f64);
            }
            acc
        };
        let (head, body) = (cumulative(0.0, h), cumulative(h, 1.0));
        let share = head[ALONG] / (head[ALONG] + body[ALONG]);
        let n_head = ((n as f64 * share).round() as usize).max(6);
        let n_body = n.saturating_sub(n_head).max(6);
        let place = |acc: &[f64], a: f64, b: f64, count: usize, out: &mut Vec<f64>| {
            for i in 0..count {
                let target = acc[ALONG] * i as f64 / count as f64;
                let k = acc.partition_point(|&x| x < target).clamp(1, ALONG);
                let w = (target - acc[k - 1]) / (acc[k] - acc[k - 1]).max(1e-300);
                out.push(a + (b - a) * (k as f64 - 1.0 + w) / ALONG as f64);
            }
        };
        let mut t = Vec::with_capacity(n + 1);
        place(&head, 0.0, h, n_head, &mut t);
        place(&body, h, 1.0, n_body, &mut t);
        t.push(1.0);
        t
    }

    /// v along the body: ∫ dℓ / P_d from the snout, with dℓ the length along the back's
    /// midline (the centreline's, lengthened where the back rises or falls at the neck and the
    /// tail) and P_d the dorsal arc's length (floored at a fifth of its largest value so that
    /// v stays finite at the tail tip), on a dense table.
    fn v_table(&self) -> Vec<f64> {
        let dorsal_fraction = 1.0 - self.belly_width as f64;
        let coarse = 1024;
        let ts: Vec<f64> = (0..=coarse).map(|i| i as f64 / coarse as f64).collect();
        let arcs: Vec<f64> = ts
            .iter()
            .map(|&t| dorsal_fraction * self.perimeter_at(t))
            .collect();
        let top: Vec<f64> = ts
            .iter()
            .map(|&t| self.lift(t) + self.half_width(t) * self.height_ratios(t).0)
            .collect();
        let floor = 0.2 * arcs.iter().cloned().fold(0.0, f64::max);
        let ds = self.length as f64 / coarse as f64;
        let mut v = vec![0.0];
        for i in 0..coarse {
            let mean = 0.5 * (arcs[i] + arcs[i + 1]);
            let dl = (ds * ds + (top[i + 1] - top[i]).powi(2)).sqrt();
            v.push(v[i] + dl / mean.max(floor));
        }
        v
    }

    #[cfg(test)]
    /// Arc-length coordinate of the body's largest dorsal arc (for scale sizes in the docs).
    pub(crate) fn dorsal_arc(&self) -> f64 {
        (1.0 - self.belly_width as f64) * self.perimeter_at(0.5)
    }
}

/// Linear lookup in a table over t ∈ [0, 1].
fn lookup(table: &[f64], t: f64) -> f64 {
    let n = table.len() - 1;
    let f = (t.clamp(0.0, 1.0) * n as f64).min(n as f64 - 1e-9);
    let i = f.floor() as usize;
    table[i] + (f - i as f64) * (table[i + 1] - table[i])
}

/// A point on the surface: ring at t, arc fraction `frac` of the section from the belly
/// midline. Returns the position and the outward normal.
fn surface_point(p: &SnakeParams, line: &Centreline, t: f64, frac: f64) -> (DVec3, DVec3) {
    let (acc, r) = p.section_arc(t, SECTION_SAMPLES);
    let alpha = angle_at(&acc, frac.rem_euclid(1.0) * acc[SECTION_SAMPLES]);
    let a = p.half_width(t);
    let (c, d) = line.at(t);
    let side = DVec3::new(d[1], 0.0, -d[0]);
    let (sx, sy) = p.section(alpha, a, r);
    let (nx, ny) = p.section_normal(alpha, a, r);
    let pos = DVec3::new(c[0], p.lift(t), c[1]) + side * sx + DVec3::Y * sy;
    (pos, (side * nx + DVec3::Y * ny).normalize())
}

fn rings(p: &SnakeParams, line: &Centreline) -> Rings {
    let t = p.ring_stations();
    let around = p.segments_around.max(8) as usize;
    let beta = p.belly_width as f64;
    let belly = ((around as f64 * beta).round() as usize).clamp(2, around - 4);
    let dorsal = around - belly;
    let mut positions = Vec::with_capacity((t.len() - 2) * around + 2);
    for &tk in &t[1..t.len() - 1] {
        let (acc, r) = p.section_arc(tk, SECTION_SAMPLES);
        let total = acc[SECTION_SAMPLES];
        let a = p.half_width(tk);
        let (c, d) = line.at(tk);
        let side = DVec3::new(d[1], 0.0, -d[0]);
        let mut ring = Vec::with_capacity(around);
        for m in 0..around {
            // Dorsal vertices from the left belly edge over the back to the right one, then
            // across the belly: the parts' boundaries fall on vertices.
            let s = if m <= dorsal {
                0.5 * beta + (1.0 - beta) * m as f64 / dorsal as f64
            } else {
                1.0 - 0.5 * beta + beta * (m - dorsal) as f64 / belly as f64
            };
            let alpha = angle_at(&acc, s.rem_euclid(1.0) * total);
            ring.push(p.section(alpha, a, r));
        }
        // A rolled stretch turns its section about the centreline and drops it back onto the
        // ground: the lowest point moves, so does the centre.
        let psi = p.roll_angle(tk);
        let (sp, cp) = psi.sin_cos();
        let low = |pts: &mut dyn Iterator<Item = f64>| pts.fold(f64::MAX, f64::min);
        let before = low(&mut ring.iter().map(|q| q.1));
        let rolled: Vec<(f64, f64)> = ring
            .iter()
            .map(|&(x, y)| (x * cp - y * sp, x * sp + y * cp))
            .collect();
        let after = low(&mut rolled.iter().map(|q| q.1));
        let base = DVec3::new(c[0], p.lift(tk) + before - after, c[1]);
        for (sx, sy) in rolled {
            positions.push(base + side * sx + DVec3::Y * sy);
        }
    }
    for tk in [0.0, 1.0] {
        let (c, _) = line.at(tk);
        positions.push(DVec3::new(c[0], p.lift(tk), c[1]));
    }
    Rings {
        t,
        positions,
        around,
        dorsal,
    }
}

/// The mesh of each part (body, belly, head), and the eyes, in object space.
pub fn parts(p: &SnakeParams) -> Vec<(Part, MeshData)> {
    let line = centreline(p, 4 * p.segments_along.max(8) as usize);
    let r = rings(p, &line);
    let v_table = p.v_table();
    let h = p.head_length as f64;
    let v_head = lookup(&v_table, h);
    let (around, dorsal) = (r.around, r.dorsal);
    let nk = r.t.len();
    let k_head = r.t.iter().position(|&t| t >= h - 1e-12).unwrap_or(nk - 1);
    // Smooth normals over the whole closed surface, so they agree across the parts' borders.
    let mut all = Vec::new();
    for k in 0..nk - 1 {
        for m in 0..around {
            let (a, b) = (r.index(k, m), r.index(k, m + 1));
            let (c, d) = (r.index(k + 1, m + 1), r.index(k + 1, m));
            if k > 0 {
                all.push([a, b, c]);
            }
            if k < nk - 2 {
                all.push([a, c, d]);
            }
        }
    }
    let normals = smooth_normals(&r.positions, all.iter());
    let mut out = Vec::new();
    // Each part is a grid of rings × columns; the tips (rings 0 and nk − 1) get one vertex per
    // column so that each fan triangle carries its own u.
    let layout = [
        (Part::Body, k_head, nk - 1, 0, dorsal),
        (Part::Belly, 0, nk - 1, dorsal, around),
        (Part::Head, 0, k_head, 0, dorsal),
    ];
    for (part, k0, k1, m0, m1) in layout {
        let cols = m1 - m0;
        let mut mesh = MeshData {
            positions: Vec::new(),
            normals: Some(Vec::new()),
            uvs: Some(Vec::new()),
            indices: Vec::new(),
        };
        let id = |k: usize, m: usize| ((k - k0) * (cols + 1) + (m - m0)) as u32;
        for k in k0..=k1 {
            let t = r.t[k];
            let tip = k == 0 || k == nk - 1;
            for m in m0..=m1 {
                let g = r.index(k, m);
                mesh.positions.push(r.positions[g].as_vec3());
                mesh.normals.as_mut().unwrap().push(normals[g]);
                // At a tip the vertex serves the fan triangle of column m: its u is the centre.
                let mu = if tip {
                    (m - m0) as f64 + 0.5
                } else {
                    (m - m0) as f64
                };
                let u = mu / cols as f64;
                let v = match part {
                    Part::Head => t / h,
                    Part::Body => lookup(&v_table, t) - v_head,
                    _ => lookup(&v_table, t),
                };
                mesh.uvs
                    .as_mut()
                    .unwrap()
                    .push(Vec2::new(u as f32, v as f32));
            }
        }
        for k in k0..k1 {
            for m in m0..m1 {
                let (a, b) = (id(k, m), id(k, m + 1));
                let (c, d) = (id(k + 1, m + 1), id(k + 1, m));
                if k + 1 == nk - 1 {
                    // The tail's fan: column m's own tip vertex.
                    mesh.indices.push([a, b, d]);
                } else if k > 0 {
                    mesh.indices.push([a, b, c]);
                }
                if k + 1 < nk - 1 {
                    mesh.indices.push([a, c, d]);
                }
            }
        }
        out.push((part, mesh));
    }
    if p.eyes {
        out.push((Part::Eyes, eyes(p, &line)));
    }
    out
}

/// Area-weighted vertex normals.
fn smooth_normals<'a>(
    positions: &[DVec3],
    tris: impl Iterator<Item = &'a [usize; 3]>,
) -> Vec<Vec3> {
    let mut acc = vec![DVec3::ZERO; positions.len()];
    for t in tris {
        let [a, b, c] = t.map(|i| positions[i]);
        let n = (b - a).cross(c - a);
        for &i in t {
            acc[i] += n;
        }
    }
    acc.iter()
        .map(|n| n.normalize_or_zero().as_vec3())
        .collect()
}

/// Two small spheres set into the sides of the head, bulging out by 40 % of their radius, at
/// the head map's eye position.
fn eyes(p: &SnakeParams, line: &Centreline) -> MeshData {
    let h = p.head_length as f64;
    let t = super::EYE_V as f64 * h;
    let beta = p.belly_width as f64;
    let mut mesh = MeshData {
        positions: Vec::new(),
        normals: Some(Vec::new()),
        uvs: Some(Vec::new()),
        indices: Vec::new(),
    };
    let radius = p.eye_size as f64 * p.half_width(t);
    for side in [-1.0, 1.0] {
        let u = 0.5 + side * super::EYE_OFFSET as f64;
        let frac = 0.5 * beta + (1.0 - beta) * u;
        let (pos, n) = surface_point(p, line, t, frac);
        let centre = pos - n * (0.6 * radius);
        uv_sphere(&mut mesh, centre, radius, 16, 10);
    }
    mesh
}

/// Appends a UV sphere (outward winding) to a mesh.
fn uv_sphere(mesh: &mut MeshData, c: DVec3, r: f64, nu: usize, nv: usize) {
    let base = mesh.positions.len() as u32;
    for j in 0..=nv {
        let theta = PI * j as f64 / nv as f64;
        for i in 0..=nu {
            let phi = 2.0 * PI * i as f64 / nu as f64;
            let d = DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            mesh.positions.push((c + d * r).as_vec3());
            mesh.normals.as_mut().unwrap().push(d.as_vec3());
            mesh.uvs
                .as_mut()
                .unwrap()
                .push(Vec2::new(i as f32 / nu as f32, j as f32 / nv as f32));
        }
    }
    let at = |i: usize, j: usize| base + (j * (nu + 1) + i) as u32;
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if j > 0 {
                mesh.indices.push([a, b, c]);
            }
            if j < nv - 1 {
                mesh.indices.push([a, c, d]);
            }
        }
    }
}
