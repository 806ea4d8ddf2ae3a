//! Where the cells of `scales` are: the lattice of jittered centres (offset rows, aligned rows
//! or the head's fixed seeds), the hashes that give each cell its random numbers, and the
//! search for the centre nearest a point (see the header of `scales.rs`).

use super::super::head_shields;
use super::{Layout, Scales};
use crate::math::Vec2;
use std::sync::OnceLock;

/// The head layout's seeds in map coordinates, computed once.
fn head_seeds() -> &'static [Vec2] {
    static SEEDS: OnceLock<Vec<Vec2>> = OnceLock::new();
    SEEDS.get_or_init(head_shields::seeds)
}

/// A 32-bit integer hash with good avalanche (xor-shift-multiply rounds).
#[inline]
pub(crate) fn mix(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Uniform [0, 1) from the top 24 bits.
#[inline]
pub(crate) fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Per-lookup constants of the lattice (see [`Scales::lattice`]).
#[derive(Clone, Copy)]
pub(super) struct Lattice {
    pu: i32,
    pv: i32,
    seed: u32,
}

/// A lattice index wrapped into [0, period) (unchanged for period 0); the division is skipped
/// when it is already in range.
#[inline]
fn wrap(i: i32, period: i32) -> i32 {
    if period > 0 && !(0..period).contains(&i) {
        i.rem_euclid(period)
    } else {
        i
    }
}

/// The period of an integer cell count (wrapping of lattice indices), or 0 for none.
fn period(scale: f32) -> i32 {
    let r = scale.round();
    if (scale - r).abs() < 1e-3 && (1.0..1e6).contains(&r) {
        r as i32
    } else {
        0
    }
}

impl Scales {
    /// What every lookup needs once: the periods that wrap lattice indices (0 for none; the
    /// head's shields do not wrap) and the seed's hash.
    #[inline]
    pub(super) fn lattice(&self) -> Lattice {
        let (pu, pv) = match self.layout {
            Layout::Head => (0, 0),
            _ => (period(self.scale_u), period(self.scale_v)),
        };
        Lattice {
            pu,
            pv,
            seed: mix(self.seed.wrapping_add(0x9e37_79b9)),
        }
    }

    /// The hash of row j, shared by the cells of the row.
    #[inline]
    pub(super) fn row_hash(&self, j: i32, lat: Lattice) -> u32 {
        mix(wrap(j, lat.pv) as u32 ^ lat.seed)
    }

    /// Centre of lattice cell (i, j) in cell space (unwrapped, near the query point), its hash
    /// and its wrapped index; `row` is [`Scales::row_hash`] of j.
    #[inline]
    pub(super) fn center(&self, i: i32, j: i32, row: u32, lat: Lattice) -> (Vec2, u32, (i32, i32)) {
        if self.layout == Layout::Head {
            // i indexes the seeds; unused indices lie far away and never win.
            let h = mix(i as u32 ^ row);
            let c = match head_seeds().get(i as usize) {
                Some(s) if i >= 0 => self.to_cell_space(*s),
                _ => Vec2::splat(1e6),
            };
            return (c, h, (i, 0));
        }
        let (wi, wj) = self.wrapped(i, j, lat);
        let h = mix(wi as u32 ^ row);
        let mut jx = unit(mix(h ^ 0x68e3_1da4)) - 0.5;
        let jy = unit(mix(h ^ 0xb529_7a4d)) - 0.5;
        if self.layout == Layout::Rows {
            // Plates stay aligned across the row (centred on half-integers, so that with
            // `scale_u` = 1 a plate spans u ∈ [0, 1]): only their length varies.
            jx = 0.0;
        }
        let c = Vec2::new(i as f32 + self.row_shift(j), j as f32)
            + self.irregularity * Vec2::new(jx, jy);
        (c, h, (wi, wj))
    }

    /// Lattice index (i, j) wrapped into the periods.
    #[inline(always)]
    pub(super) fn wrapped(&self, i: i32, j: i32, lat: Lattice) -> (i32, i32) {
        (wrap(i, lat.pu), wrap(j, lat.pv))
    }

    /// How far row j's unjittered centres sit from the integers: every other row is shifted
    /// by half a cell (hex), every row by half (rows, whose plates span [i, i + 1]).
    #[inline(always)]
    pub(super) fn row_shift(&self, j: i32) -> f32 {
        match self.layout {
            Layout::Rows => 0.5,
            _ if j.rem_euclid(2) == 1 => 0.5,
            _ => 0.0,
        }
    }

    /// How many rows and columns either side of a cell [`Scales::candidates`] visits.
    #[inline(always)]
    pub(super) fn reach(&self) -> i32 {
        if self.irregularity <= 0.35 {
            1
        } else {
            2
        }
    }

    /// Calls `f` with every cell that may be nearest to lattice cell (ci, cj) or border it. The
    /// unjittered lattice's cells reach 0.71 from their centres, so with jitter of at most
    /// `irregularity`/2 per axis the nearest centre lies within 0.71 + 1.42·`irregularity`:
    /// one row and column either side while `irregularity` ≤ 0.35 (where the Voronoi
    /// neighbours are also the lattice's), two beyond that. The head's few seeds are all
    /// candidates.
    #[inline]
    pub(super) fn candidates(
        &self,
        ci: i32,
        cj: i32,
        lat: Lattice,
        mut f: impl FnMut(i32, i32, u32),
    ) {
        if self.layout == Layout::Head {
            let row = self.row_hash(0, lat);
            for i in 0..head_seeds().len() as i32 {
                f(i, 0, row);
            }
            return;
        }
        let reach = self.reach();
        for j in cj - reach..=cj + reach {
            let row = self.row_hash(j, lat);
            for i in ci - reach..=ci + reach {
                f(i, j, row);
            }
        }
    }

    /// The cell under a UV point and its hash (the nearest centre only: what the per-cell
    /// values and tilts need, at a fraction of [`Scales::sample`]'s cost).
    #[inline]
    pub fn nearest(&self, uv: Vec2) -> ((i32, i32), u32) {
        let (cell, h, _) = self.nearest_center(uv);
        (cell, h)
    }

    /// As [`Scales::nearest`], with the cell's centre in cell space (unwrapped, near `uv`).
    #[inline]
    pub fn nearest_center(&self, uv: Vec2) -> ((i32, i32), u32, Vec2) {
        let f = self.search(self.to_cell_space(uv), false);
        (f.cell, f.h0, f.c0)
    }
}
