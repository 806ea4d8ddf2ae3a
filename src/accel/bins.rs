//! Binning for the SAH build ([`super::build`]): the cost model (box surface area times the
//! blocks of four a leaf needs), the bins a range's centroids fall in along each axis with
//! their counts and bounds, and the cheapest plane between them (Wald, "On fast Construction
//! of SAH-based Bounding Volume Hierarchies", 2007). The split itself, and the partition, are
//! in the build.
use super::build::Ref;
use glam::Vec4;

/// Bins per axis (fewer for small ranges).
pub(super) const BINS: usize = 16;

/// Surface area of the box `lo ..= hi` (xyz; 0 for an empty box). Without branches: an empty
/// box (no bounds grown yet: `lo` = +∞, `hi` = −∞) has negative extents, clamped to 0.
#[inline(always)]
pub(super) fn area(lo: Vec4, hi: Vec4) -> f32 {
    let e = (hi - lo).max(Vec4::ZERO);
    2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
}

/// Blocks of four a leaf of `n` primitives needs.
#[inline]
pub(super) fn blocks(n: u32) -> f32 {
    n.div_ceil(4) as f32
}

/// Per axis and bin: primitive count and bounds.
#[derive(Clone, Copy)]
pub(super) struct Bins {
    pub(super) n: [[u32; BINS]; 3],
    pub(super) lo: [[Vec4; BINS]; 3],
    pub(super) hi: [[Vec4; BINS]; 3],
}

impl Bins {
    pub(super) const EMPTY: Bins = Bins {
        n: [[0; BINS]; 3],
        lo: [[Vec4::INFINITY; BINS]; 3],
        hi: [[Vec4::NEG_INFINITY; BINS]; 3],
    };

    pub(super) fn merge(mut self, o: &Bins) -> Bins {
        for a in 0..3 {
            for b in 0..BINS {
                self.n[a][b] += o.n[a][b];
                self.lo[a][b] = self.lo[a][b].min(o.lo[a][b]);
                self.hi[a][b] = self.hi[a][b].max(o.hi[a][b]);
            }
        }
        self
    }
}

/// Maps twice-centroids to the `nb` bins of a span.
#[derive(Clone, Copy)]
pub(super) struct Binner {
    pub(super) clo: Vec4,
    pub(super) scale: Vec4,
    /// `nb − 1` in every lane.
    pub(super) last: Vec4,
}

impl Binner {
    /// The bins along the three axes (lanes x, y, z).
    #[inline(always)]
    pub(super) fn bins(&self, c2: Vec4) -> [usize; 3] {
        let x = (c2 - self.clo) * self.scale;
        // NaN (an overflowing centroid) goes to bin 0; the clamp makes the conversion exact.
        let x = Vec4::select(x.cmpgt(Vec4::ZERO), x, Vec4::ZERO).min(self.last);
        // Each value is finite and in [0, nb − 1]: one truncating conversion of all lanes.
        #[cfg(target_arch = "x86_64")]
        // SAFETY: SSE2 is part of the x86-64 baseline; the conversion reads and writes only
        // registers (a [i32; 4] and an __m128i have the same size).
        let [x, y, z, _]: [i32; 4] =
            unsafe { std::mem::transmute(std::arch::x86_64::_mm_cvttps_epi32(x.into())) };
        #[cfg(not(target_arch = "x86_64"))]
        // SAFETY: each value is finite and in [0, nb − 1].
        let [x, y, z, _] = x.to_array().map(|v| unsafe { v.to_int_unchecked::<i32>() });
        // In [0, nb − 1] already; the mask tells the compiler so (no bounds checks).
        [x, y, z].map(|b| b as usize & (BINS - 1))
    }

    /// Whether `c2` falls in a bin below `plane` along `axis`: the bin of
    /// [`Binner::bins`] compared with `plane` without computing it. For x = (c2 − clo)·scale,
    /// the bin is ⌊x⌋ clamped to [0, nb − 1] (NaN: 0), and for a plane in [1, nb − 1] that is
    /// below it exactly when x < plane (NaN: yes).
    #[inline(always)]
    pub(super) fn below(&self, c2: Vec4, axis: usize, plane: f32) -> bool {
        let x = (c2 - self.clo) * self.scale;
        x.cmpge(Vec4::splat(plane)).bitmask() & (1 << axis) == 0
    }

    /// Adds `refs` to `bins`. Pairs of refs from a long run go to two sets of bins that are
    /// merged at the end: neighbouring refs often fall in the same bin, and one set would make
    /// each wait for the other's update to that bin to be stored.
    pub(super) fn fill(&self, refs: &[Ref], bins: &mut Bins) {
        let add = |bins: &mut Bins, r: &Ref| {
            for (a, b) in self.bins(r.c2()).into_iter().enumerate() {
                bins.n[a][b] += 1;
                bins.lo[a][b] = bins.lo[a][b].min(r.lo);
                bins.hi[a][b] = bins.hi[a][b].max(r.hi);
            }
        };
        if refs.len() < 256 {
            refs.iter().for_each(|r| add(bins, r));
            return;
        }
        let mut other = Bins::EMPTY;
        let mut pairs = refs.chunks_exact(2);
        for p in &mut pairs {
            add(bins, &p[0]);
            add(&mut other, &p[1]);
        }
        for r in pairs.remainder() {
            add(bins, r);
        }
        *bins = bins.merge(&other);
    }
}

/// The cheapest plane along `axis` between the first `nb` bins (plane i: bins below i go left)
/// and its cost, area·blocks summed over both sides; infinite when no plane separates the `n`
/// refs.
pub(super) fn best_plane(bins: &Bins, axis: usize, nb: usize, n: usize) -> (f32, usize) {
    let inf = Vec4::splat(f32::INFINITY);
    let mut right = [0.0f32; BINS];
    let (mut lo, mut hi, mut cnt) = (inf, -inf, 0);
    for i in (1..nb).rev() {
        lo = lo.min(bins.lo[axis][i]);
        hi = hi.max(bins.hi[axis][i]);
        cnt += bins.n[axis][i];
        right[i] = area(lo, hi) * blocks(cnt);
    }
    let (mut lo, mut hi, mut cnt) = (inf, -inf, 0);
    let mut best = (f32::INFINITY, 0);
    for (i, right) in right.iter().enumerate().take(nb).skip(1) {
        lo = lo.min(bins.lo[axis][i - 1]);
        hi = hi.max(bins.hi[axis][i - 1]);
        cnt += bins.n[axis][i - 1];
        if cnt == 0 || cnt as usize == n {
            continue;
        }
        let cost = area(lo, hi) * blocks(cnt) + right;
        if cost < best.0 {
            best = (cost, i);
        }
    }
    best
}
