//! Table lookups by a per-lane index that takes few distinct values in a chunk — a shape, a
//! material, a light or a spectrum entry: each distinct value is read once and broadcast to
//! its lanes with a blend. A gather reads a cache line per lane and costs tens of cycles on
//! the CPUs ophis runs on; a chunk's lanes usually hit a handful of shapes. Indices beyond
//! [`GROUPS`] distinct values fall back to a gather for the remaining lanes.

use crate::simd::{Float, Int, Mask};

/// Distinct values handled by broadcast before the gather fallback.
pub(super) const GROUPS: usize = 4;

/// The distinct indices of the active lanes of a chunk.
pub(super) struct Groups<F: Float> {
    n: usize,
    value: [u32; GROUPS],
    mask: [F::M; GROUPS],
    /// Active lanes whose index is beyond the first `GROUPS` distinct ones.
    rest: F::M,
    idx: F::I,
}

impl<F: Float> Groups<F> {
    /// The groups of `idx` over the lanes of `active` (other lanes read entry 0).
    #[inline(always)]
    pub fn new(idx: F::I, active: F::M) -> Self {
        let mut lanes = [0u32; 16];
        idx.store(&mut lanes);
        let mut todo = active.bits();
        let mut g = Groups {
            n: 0,
            value: [0; GROUPS],
            mask: [F::M::splat(false); GROUPS],
            rest: F::M::splat(false),
            idx,
        };
        while todo != 0 {
            if g.n == GROUPS {
                g.rest = F::M::from_bits(todo);
                break;
            }
            let v = lanes[todo.trailing_zeros() as usize];
            let m = idx.eq(F::I::splat(v as i32)) & active;
            g.value[g.n] = v;
            g.mask[g.n] = m;
            g.n += 1;
            todo &= !m.bits();
        }
        g
    }

    /// `table[idx]` in each active lane (0 elsewhere).
    #[inline(always)]
    pub fn f(&self, table: &[f32]) -> F {
        let mut out = F::splat(0.0);
        for k in 0..self.n {
            out = F::select(self.mask[k], F::splat(table[self.value[k] as usize]), out);
        }
        if self.rest.any() {
            let idx = F::I::select(self.rest, self.idx, F::I::splat(0));
            out = F::select(self.rest, F::gather(table, idx), out);
        }
        out
    }

    /// `table[idx]` in each active lane (0 elsewhere).
    #[inline(always)]
    pub fn i(&self, table: &[u32]) -> F::I {
        let mut out = F::I::splat(0);
        for k in 0..self.n {
            out = F::I::select(
                self.mask[k],
                F::I::splat(table[self.value[k] as usize] as i32),
                out,
            );
        }
        if self.rest.any() {
            let idx = F::I::select(self.rest, self.idx, F::I::splat(0));
            out = F::I::select(self.rest, F::I::gather(table, idx), out);
        }
        out
    }
}
