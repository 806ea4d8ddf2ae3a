//! The lattice search of `scales` with the candidate cells hashed and placed in SIMD lanes.
//!
//! [`Scales::evaluate`] visits every candidate cell twice — once to find the nearest centre,
//! once to find the two nearest edges around it — and each visit hashes the cell three times
//! (its id and its two jitters). With an `irregularity` above 0.35 that is 25 cells a pass
//! (the soil crumbs of the flagship), and the hashing, not the search, is what costs. Here a
//! pass computes all its candidates' centres (and, for the second, their bisector distances)
//! eight at a time, then picks the winners with the same sequential comparisons as the scalar
//! loop, in the same order. Every lane operation rounds as the scalar one does
//! ([`crate::simd`]), so the result is the scalar result bit for bit; `tests` check it over
//! layouts, irregularities and lattice wraps, and on every instruction set.
//!
//! The head's shields are fixed seeds, not a lattice, and keep the scalar path.

use super::lattice::Lattice;
use super::{Layout, Scales};
use crate::math::Vec2;
use crate::simd::{Float, Int};

/// The most candidates a pass has: 5 × 5, rounded up to whole lane sets.
const MAX: usize = 32;

/// The candidates of one pass, in [`Scales::candidates`] order: lattice cell (ci − r + k mod w,
/// cj − r + k div w) for k < `n`, with w = 2r + 1.
pub(super) struct Pass {
    pub n: usize,
    pub w: i32,
    pub reach: i32,
    /// Per candidate: centre (x, y) in cell space, and its hash.
    pub cx: [f32; MAX],
    pub cy: [f32; MAX],
    pub hash: [u32; MAX],
}

/// Per candidate of a [`Pass`], what [`Pass::bisectors`] finds: the distance `e` from the
/// point to the bisector with the nearest centre, the bisector's unit normal (`nx`, `ny`) and
/// the distance `len` between the two centres.
pub(super) struct Bisectors {
    pub e: [f32; MAX],
    pub nx: [f32; MAX],
    pub ny: [f32; MAX],
    pub len: [f32; MAX],
}

/// [`super::lattice::mix`] in lanes.
#[inline(always)]
fn mix_lanes<I: Int>(mut x: I) -> I {
    x = x ^ x.shr::<16>();
    x = x.mul_lo(I::splat(0x7feb_352d));
    x = x ^ x.shr::<15>();
    x = x.mul_lo(I::splat(0x846c_a68b_u32 as i32));
    x ^ x.shr::<16>()
}

/// [`super::lattice::unit`] in lanes.
#[inline(always)]
fn unit_lanes<F: Float>(h: F::I) -> F {
    F::from_int(h.shr::<8>()) * F::splat(1.0 / 16_777_216.0)
}

impl Pass {
    /// The centres of the candidates around lattice cell (ci, cj), computed `F::LANES` at a
    /// time as [`Scales::center`] computes each.
    #[inline(always)]
    pub fn centres<F: Float>(s: &Scales, ci: i32, cj: i32, lat: Lattice) -> Pass {
        debug_assert!(s.layout != Layout::Head);
        let reach = s.reach();
        let w = 2 * reach + 1;
        let n = (w * w) as usize;
        let mut p = Pass {
            n,
            w,
            reach,
            cx: [0.0; MAX],
            cy: [0.0; MAX],
            hash: [0; MAX],
        };
        // What a candidate takes from its column and its row, laid out per candidate.
        let mut col_key = [0u32; MAX];
        let mut row_key = [0u32; MAX];
        let mut base_x = [0.0f32; MAX];
        let mut base_y = [0.0f32; MAX];
        for dj in 0..w {
            let j = cj - reach + dj;
            let row = s.row_hash(j, lat);
            let shift = s.row_shift(j);
            for di in 0..w {
                let i = ci - reach + di;
                let k = (dj * w + di) as usize;
                col_key[k] = s.wrapped(i, j, lat).0 as u32;
                row_key[k] = row;
                base_x[k] = i as f32 + shift;
                base_y[k] = j as f32;
            }
        }
        let irr = F::splat(s.irregularity);
        let half = F::splat(0.5);
        let rows = s.layout == Layout::Rows;
        for k in (0..n).step_by(F::LANES) {
            let h = mix_lanes(F::I::load_at(&col_key, k) ^ F::I::load_at(&row_key, k));
            let jx = if rows {
                F::splat(0.0)
            } else {
                unit_lanes::<F>(mix_lanes(h ^ F::I::splat(0x68e3_1da4))) - half
            };
            let jy = unit_lanes::<F>(mix_lanes(h ^ F::I::splat(0xb529_7a4d_u32 as i32))) - half;
            (F::load_at(&base_x, k) + irr * jx).store_at(&mut p.cx, k);
            (F::load_at(&base_y, k) + irr * jy).store_at(&mut p.cy, k);
            h.store_at(&mut p.hash, k);
        }
        p
    }

    /// Candidate `k`'s centre.
    #[inline(always)]
    pub fn center(&self, k: usize) -> Vec2 {
        Vec2::new(self.cx[k], self.cy[k])
    }

    /// Candidate `k`'s lattice index (unwrapped) for a pass around (ci, cj).
    #[inline(always)]
    pub fn index(&self, k: usize, ci: i32, cj: i32) -> (i32, i32) {
        let k = k as i32;
        (ci - self.reach + k % self.w, cj - self.reach + k / self.w)
    }

    /// The first candidate nearest `p`, as the scalar loop finds it.
    #[inline(always)]
    pub fn nearest<F: Float>(&self, p: Vec2) -> usize {
        let mut d2 = [0.0f32; MAX];
        let (px, py) = (F::splat(p.x), F::splat(p.y));
        for k in (0..self.n).step_by(F::LANES) {
            let dx = px - F::load_at(&self.cx, k);
            let dy = py - F::load_at(&self.cy, k);
            (dx * dx + dy * dy).store_at(&mut d2, k);
        }
        let mut best = (f32::INFINITY, 0);
        for (k, &d) in d2[..self.n].iter().enumerate() {
            if d < best.0 {
                best = (d, k);
            }
        }
        best.1
    }

    /// For every candidate: the unit vector `n` from `c0` to its centre, the centre's distance
    /// `len`, and the distance from `p` to their bisector, (½(c0 + c) − p)·n.
    #[inline(always)]
    pub fn bisectors<F: Float>(&self, c0: Vec2, p: Vec2) -> Bisectors {
        let mut b = Bisectors {
            e: [0.0; MAX],
            nx: [0.0; MAX],
            ny: [0.0; MAX],
            len: [0.0; MAX],
        };
        let (c0x, c0y) = (F::splat(c0.x), F::splat(c0.y));
        let (px, py) = (F::splat(p.x), F::splat(p.y));
        let half = F::splat(0.5);
        for k in (0..self.n).step_by(F::LANES) {
            let (cx, cy) = (F::load_at(&self.cx, k), F::load_at(&self.cy, k));
            let (dx, dy) = (cx - c0x, cy - c0y);
            let len = (dx * dx + dy * dy).sqrt();
            let (nx, ny) = (dx / len, dy / len);
            let (mx, my) = (half * (c0x + cx) - px, half * (c0y + cy) - py);
            (mx * nx + my * ny).store_at(&mut b.e, k);
            nx.store_at(&mut b.nx, k);
            ny.store_at(&mut b.ny, k);
            len.store_at(&mut b.len, k);
        }
        b
    }
}
