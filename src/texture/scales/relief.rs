//! The relief of `scales`: the height of a cell — groove shoulder, domed top, roof-tile rise
//! — and its gradient in closed form, faded to a mean where cells shrink below the footprint
//! (see the header of `scales.rs`).

use super::lanes::Pass;
use super::lattice::unit;
use super::{Layout, ScaleSample, Scales};
use crate::accel::Isa;
use crate::math::Vec2;
use crate::simd::Float;
use std::cell::Cell;
use std::sync::OnceLock;

/// Circumradius of the regular cell, the unit of the dome profile.
pub(super) const CELL_RADIUS: f32 = 0.65;
/// Mean height of the relief, what it fades to at a distance (measured over regular cells with
/// the default dome; exact values matter little since only the relief's slope is seen).
pub(super) const FADE_LEVEL: f32 = 0.6;

/// Polynomial smooth minimum: min(a, b) with the corner rounded over a width `k`.
#[inline]
fn smooth_min(a: f32, b: f32, k: f32) -> f32 {
    let m = a.min(b);
    if k <= 0.0 || !m.is_finite() {
        return m;
    }
    let h = (k - (a - b).abs()).max(0.0) / k;
    m - 0.25 * k * h * h
}

/// The weights (∂/∂a, ∂/∂b) of [`smooth_min`]: the smaller argument counts 1 − h/2, the other
/// h/2, with h = max(k − |a − b|, 0)/k.
#[inline]
fn smooth_min_weights(a: f32, b: f32, k: f32) -> (f32, f32) {
    let h = if k > 0.0 && a.is_finite() && b.is_finite() {
        (k - (a - b).abs()).max(0.0) / k
    } else {
        0.0
    };
    if a <= b {
        (1.0 - 0.5 * h, 0.5 * h)
    } else {
        (0.5 * h, 1.0 - 0.5 * h)
    }
}

/// smoothstep and its derivative with respect to x.
#[inline]
fn smoothstep_d(e0: f32, e1: f32, x: f32) -> (f32, f32) {
    if e1 <= e0 {
        return (if x < e0 { 0.0 } else { 1.0 }, 0.0);
    }
    let t = (x - e0) / (e1 - e0);
    if !(0.0..=1.0).contains(&t) {
        return (t.clamp(0.0, 1.0), 0.0);
    }
    (t * t * (3.0 - 2.0 * t), 6.0 * t * (1.0 - t) / (e1 - e0))
}

#[inline]
fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    if e1 <= e0 {
        return if x < e0 { 0.0 } else { 1.0 };
    }
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl Scales {
    /// The pattern and the gradient of its height with respect to cell space, in one pass: the
    /// relief is a product of smooth functions of the distances to the cell's centre and to
    /// its two nearest edges, each differentiated in closed form.
    pub(super) fn evaluate(&self, uv: Vec2, width: f32) -> (ScaleSample, Vec2) {
        let p = self.to_cell_space(uv);
        let Found {
            c0,
            h0,
            cell,
            e: [e1, e2],
            n: [n1, n2],
        } = self.search(p, true);
        let round = 0.5 * self.gap;
        // Only the two nearest edges meet at a corner of the cell; taking just those keeps the
        // result independent of the order the neighbours were visited in.
        let raw = smooth_min(e1, e2, round);
        let edge = raw.max(0.0);
        let d_edge = if raw > 0.0 {
            let (w1, w2) = smooth_min_weights(e1, e2, round);
            -(n1 * w1 + n2 * w2)
        } else {
            Vec2::ZERO
        };
        let gap = self.gap.max((0.25 * width).min(0.5));
        let (shoulder, d_shoulder) = smoothstep_d(0.0, gap, edge);
        let q = (p - c0) / CELL_RADIUS;
        // x(2 − x) and r(3 − r²)/2 saturate with zero slope, so the relief stays C¹.
        let q2 = q.length_squared();
        let x = q2.min(1.0);
        let top = 1.0 - self.dome * x * (2.0 - x);
        let d_top = if q2 < 1.0 {
            q * (-self.dome * (2.0 - 2.0 * x) * 2.0 / CELL_RADIUS)
        } else {
            Vec2::ZERO
        };
        let r0 = q.dot(self.overlap_dir);
        let rc = r0.clamp(-1.0, 1.0);
        let r = 0.5 * rc * (3.0 - rc * rc);
        let tile = 1.0 - self.overlap * 0.5 * (1.0 - r);
        let d_tile = if r0.abs() < 1.0 {
            self.overlap_dir * (self.overlap * 0.75 * (1.0 - rc * rc) / CELL_RADIUS)
        } else {
            Vec2::ZERO
        };
        let relief = shoulder * top * tile;
        let d_relief = d_edge * (d_shoulder * top * tile)
            + d_top * (shoulder * tile)
            + d_tile * (shoulder * top);
        let fade = smoothstep(0.5, 2.0, width);
        let sample = ScaleSample {
            height: relief + fade * (FADE_LEVEL - relief),
            edge_distance: edge,
            id: unit(h0),
            cell,
            center: c0,
            groove: (1.0 - shoulder) * (1.0 - fade),
        };
        (sample, d_relief * (1.0 - fade))
    }

    /// The lattice search for cell-space point `p`, in lanes where the CPU has them (see
    /// `lanes.rs`; the head's seeds always take [`Scales::search_scalar`]); without `edges`,
    /// the nearest centre only (the edges are left at ∞).
    ///
    /// A shading point asks the same pattern at the same point several times — the bump map's
    /// relief, the cell's tilt, a `per_scale` film thickness, a groove colour — so each thread
    /// keeps its last answer with everything it depends on (the point's bits and the pattern's
    /// layout, scales, irregularity and seed) and gives it again for the same question.
    #[inline]
    pub(super) fn search(&self, p: Vec2, edges: bool) -> Found {
        static ISA: OnceLock<Isa> = OnceLock::new();
        thread_local! {
            static LAST: Cell<Option<(SearchKey, bool, Found)>> = const { Cell::new(None) };
        }
        let key = SearchKey {
            p: [p.x.to_bits(), p.y.to_bits()],
            scale: [self.scale_u.to_bits(), self.scale_v.to_bits()],
            irregularity: self.irregularity.to_bits(),
            seed: self.seed,
            layout: self.layout,
        };
        if let Some((k, with_edges, found)) = LAST.get() {
            if k == key && (with_edges || !edges) {
                return if edges { found } else { found.without_edges() };
            }
        }
        let found = self.search_on(*ISA.get_or_init(Isa::best), p, edges);
        LAST.set(Some((key, edges, found)));
        found
    }

    /// [`Scales::search`] with the lanes of instruction set `isa`; every choice gives the same
    /// bits. The caller guarantees that the CPU supports `isa` (as [`Isa::best`] and the tests'
    /// `Isa::supported` filter do); this is checked in debug builds only, since it runs at
    /// every shading point.
    pub(super) fn search_on(&self, isa: Isa, p: Vec2, edges: bool) -> Found {
        if self.layout == Layout::Head {
            return self.search_scalar(p, edges);
        }
        #[cfg(target_arch = "x86_64")]
        if isa != Isa::Baseline {
            #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
            fn avx2(s: &Scales, p: Vec2, edges: bool) -> Found {
                s.search_lanes::<crate::simd::F8>(p, edges)
            }
            debug_assert!(isa.supported());
            // SAFETY: the CPU supports `isa` (the caller's guarantee), and every variant
            // beyond the baseline includes AVX2 and the rest of this set.
            return unsafe { avx2(self, p, edges) };
        }
        let _ = isa;
        self.search_lanes::<f32>(p, edges)
    }

    /// The search with the candidates in lanes of type `F` (see `lanes.rs`).
    #[inline(always)]
    fn search_lanes<F: Float>(&self, p: Vec2, edges: bool) -> Found {
        let lat = self.lattice();
        let (j0, i0) = (p.y.round() as i32, p.x.floor() as i32);
        let first = Pass::centres::<F>(self, i0, j0, lat);
        let k0 = first.nearest::<F>(p);
        let (bi, bj) = first.index(k0, i0, j0);
        let c0 = first.center(k0);
        let h0 = first.hash[k0];
        let cell = self.wrapped(bi, bj, lat);
        let mut near = TwoNearest::NONE;
        if edges {
            let second = Pass::centres::<F>(self, bi, bj, lat);
            let b = second.bisectors::<F>(c0, p);
            let own = (second.n - 1) / 2;
            for k in 0..second.n {
                if k != own && b.len[k] > 1e-6 {
                    near.offer(b.e[k], Vec2::new(b.nx[k], b.ny[k]));
                }
            }
        }
        near.found(c0, h0, cell)
    }

    /// The search one candidate at a time: the nearest centre, then (with `edges`) the two
    /// nearest bisectors between it and its neighbours — the distance to the cell's edge,
    /// whose corners [`Scales::evaluate`] rounds.
    pub(super) fn search_scalar(&self, p: Vec2, edges: bool) -> Found {
        let lat = self.lattice();
        let (j0, i0) = (p.y.round() as i32, p.x.floor() as i32);
        let mut best = (f32::INFINITY, Vec2::ZERO, 0u32, (0, 0), (0, 0));
        self.candidates(i0, j0, lat, |i, j, row| {
            let (c, h, cell) = self.center(i, j, row, lat);
            let d2 = (p - c).length_squared();
            if d2 < best.0 {
                best = (d2, c, h, cell, (i, j));
            }
        });
        let (_, c0, h0, cell, (bi, bj)) = best;
        let mut near = TwoNearest::NONE;
        self.candidates(bi, bj, lat, |i, j, row| {
            if !edges || (i, j) == (bi, bj) {
                return;
            }
            let (c, _, _) = self.center(i, j, row, lat);
            let d = c - c0;
            let len = d.length();
            if len > 1e-6 {
                let n = d / len;
                near.offer((0.5 * (c0 + c) - p).dot(n), n);
            }
        });
        near.found(c0, h0, cell)
    }
}

/// The two nearest cell edges offered so far, nearest first; one at the same distance as a
/// kept one does not displace it (so the first offered wins ties, as the visiting order decides).
#[derive(Clone, Copy)]
struct TwoNearest {
    e: [f32; 2],
    n: [Vec2; 2],
}

impl TwoNearest {
    /// None yet: both at ∞.
    const NONE: TwoNearest = TwoNearest {
        e: [f32::INFINITY; 2],
        n: [Vec2::ZERO; 2],
    };

    /// Keeps the edge at distance `e` with normal `n` if it is among the two nearest.
    #[inline(always)]
    fn offer(&mut self, e: f32, n: Vec2) {
        if e < self.e[0] {
            self.e = [e, self.e[0]];
            self.n = [n, self.n[0]];
        } else if e < self.e[1] {
            (self.e[1], self.n[1]) = (e, n);
        }
    }

    /// The search's answer with these edges.
    #[inline(always)]
    fn found(self, c0: Vec2, h0: u32, cell: (i32, i32)) -> Found {
        Found {
            c0,
            h0,
            cell,
            e: self.e,
            n: self.n,
        }
    }
}

/// Everything a search's answer depends on (see [`Scales::search`]).
#[derive(Clone, Copy, PartialEq, Eq)]
struct SearchKey {
    p: [u32; 2],
    scale: [u32; 2],
    irregularity: u32,
    seed: u32,
    layout: Layout,
}

/// What the lattice search finds for a point: the nearest centre (cell space), its hash and
/// wrapped lattice index, and the two nearest cell edges — each a distance from the point to
/// the bisector with a neighbour and the bisector's unit normal, pointing to the neighbour —
/// nearest first (∞ and zero where a cell has fewer neighbours).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Found {
    pub c0: Vec2,
    pub h0: u32,
    pub cell: (i32, i32),
    pub e: [f32; 2],
    pub n: [Vec2; 2],
}

impl Found {
    /// The nearest centre alone, as a search without edges gives it.
    #[inline]
    fn without_edges(self) -> Found {
        TwoNearest::NONE.found(self.c0, self.h0, self.cell)
    }
}
