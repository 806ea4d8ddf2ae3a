//! Fixed-width `f32` lanes for the box and triangle tests.
//!
//! [`F4`] (four lanes, with its mask [`M4`]) is SSE on x86-64, which every x86-64 CPU has, and
//! plain arrays elsewhere. Eight lanes come in two implementations of [`Vec8`]: [`Avx8`] (one
//! AVX register) and [`Pair8`] (two `F4`s), and a third in `order.rs`
//! ([`super::order::Avx8k`]: `Avx8` whose children are ordered by an AVX-512 sorting
//! network). The traversal is generic over `Vec8` and [`super::isa`] instantiates it with
//! `Avx8` only inside functions compiled for AVX2, `Avx8k` only inside those compiled for
//! AVX-512, and with `Pair8` for the baseline.
//!
//! Every variant computes the same IEEE operations, so results are bit-identical: no operation
//! is fused or reassociated. `min`/`max` are `a < b ? a : b` and `a > b ? a : b` (the semantics
//! of `minps`/`maxps`): when either operand is NaN the second one is returned, which the box
//! test uses to stay conservative. Masks are lanes of all-ones / zero, turned into a bit mask
//! (lane i → bit i) by `bits`.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;
use std::mem::MaybeUninit;

/// Four `f32` lanes.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct F4(__m128);

/// A four-lane mask.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct M4(__m128);

// SAFETY (whole block): SSE and SSE2 are part of the x86-64 baseline.
#[cfg(target_arch = "x86_64")]
impl F4 {
    #[inline(always)]
    pub fn splat(x: f32) -> F4 {
        unsafe { F4(_mm_set1_ps(x)) }
    }
    #[inline(always)]
    pub fn load(a: &[f32; 4]) -> F4 {
        unsafe { F4(_mm_loadu_ps(a.as_ptr())) }
    }
    #[inline(always)]
    pub fn to_array(self) -> [f32; 4] {
        let mut a = [0.0; 4];
        unsafe { _mm_storeu_ps(a.as_mut_ptr(), self.0) };
        a
    }
    #[inline(always)]
    pub fn from_array(a: [f32; 4]) -> F4 {
        F4::load(&a)
    }
    #[inline(always)]
    pub fn min(self, o: F4) -> F4 {
        unsafe { F4(_mm_min_ps(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn max(self, o: F4) -> F4 {
        unsafe { F4(_mm_max_ps(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn abs(self) -> F4 {
        unsafe { F4(_mm_andnot_ps(_mm_set1_ps(-0.0), self.0)) }
    }
    #[inline(always)]
    pub fn lt(self, o: F4) -> M4 {
        unsafe { M4(_mm_cmplt_ps(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn le(self, o: F4) -> M4 {
        unsafe { M4(_mm_cmple_ps(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn gt(self, o: F4) -> M4 {
        unsafe { M4(_mm_cmpgt_ps(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn eq(self, o: F4) -> M4 {
        unsafe { M4(_mm_cmpeq_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn add_(self, o: F4) -> F4 {
        unsafe { F4(_mm_add_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn sub_(self, o: F4) -> F4 {
        unsafe { F4(_mm_sub_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn mul_(self, o: F4) -> F4 {
        unsafe { F4(_mm_mul_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn div_(self, o: F4) -> F4 {
        unsafe { F4(_mm_div_ps(self.0, o.0)) }
    }
}

#[cfg(target_arch = "x86_64")]
impl M4 {
    /// Bit i set when lane i is true.
    #[inline(always)]
    pub fn bits(self) -> u32 {
        unsafe { _mm_movemask_ps(self.0) as u32 }
    }
    #[inline(always)]
    fn and_(self, o: M4) -> M4 {
        unsafe { M4(_mm_and_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn or_(self, o: M4) -> M4 {
        unsafe { M4(_mm_or_ps(self.0, o.0)) }
    }
}

/// Four `f32` lanes.
#[cfg(not(target_arch = "x86_64"))]
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct F4([f32; 4]);

/// A four-lane mask.
#[cfg(not(target_arch = "x86_64"))]
#[derive(Clone, Copy, Debug)]
pub struct M4([bool; 4]);

#[cfg(not(target_arch = "x86_64"))]
impl F4 {
    #[inline(always)]
    fn map(self, o: F4, f: impl Fn(f32, f32) -> f32) -> F4 {
        F4([0, 1, 2, 3].map(|i| f(self.0[i], o.0[i])))
    }
    #[inline(always)]
    fn cmp(self, o: F4, f: impl Fn(f32, f32) -> bool) -> M4 {
        M4([0, 1, 2, 3].map(|i| f(self.0[i], o.0[i])))
    }
    #[inline(always)]
    pub fn splat(x: f32) -> F4 {
        F4([x; 4])
    }
    #[inline(always)]
    pub fn load(a: &[f32; 4]) -> F4 {
        F4(*a)
    }
    #[inline(always)]
    pub fn to_array(self) -> [f32; 4] {
        self.0
    }
    #[inline(always)]
    pub fn from_array(a: [f32; 4]) -> F4 {
        F4(a)
    }
    #[inline(always)]
    pub fn min(self, o: F4) -> F4 {
        self.map(o, |a, b| if a < b { a } else { b })
    }
    #[inline(always)]
    pub fn max(self, o: F4) -> F4 {
        self.map(o, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    pub fn abs(self) -> F4 {
        F4(self.0.map(f32::abs))
    }
    #[inline(always)]
    pub fn lt(self, o: F4) -> M4 {
        self.cmp(o, |a, b| a < b)
    }
    #[inline(always)]
    pub fn le(self, o: F4) -> M4 {
        self.cmp(o, |a, b| a <= b)
    }
    #[inline(always)]
    pub fn gt(self, o: F4) -> M4 {
        self.cmp(o, |a, b| a > b)
    }
    #[inline(always)]
    pub fn eq(self, o: F4) -> M4 {
        self.cmp(o, |a, b| a == b)
    }
    #[inline(always)]
    fn add_(self, o: F4) -> F4 {
        self.map(o, |a, b| a + b)
    }
    #[inline(always)]
    fn sub_(self, o: F4) -> F4 {
        self.map(o, |a, b| a - b)
    }
    #[inline(always)]
    fn mul_(self, o: F4) -> F4 {
        self.map(o, |a, b| a * b)
    }
    #[inline(always)]
    fn div_(self, o: F4) -> F4 {
        self.map(o, |a, b| a / b)
    }
}

#[cfg(not(target_arch = "x86_64"))]
impl M4 {
    /// Bit i set when lane i is true.
    #[inline(always)]
    pub fn bits(self) -> u32 {
        (0..4).map(|i| (self.0[i] as u32) << i).sum()
    }
    #[inline(always)]
    fn and_(self, o: M4) -> M4 {
        M4([0, 1, 2, 3].map(|i| self.0[i] & o.0[i]))
    }
    #[inline(always)]
    fn or_(self, o: M4) -> M4 {
        M4([0, 1, 2, 3].map(|i| self.0[i] | o.0[i]))
    }
}

macro_rules! binop {
    ($t:ty, $tr:ident, $f:ident, $imp:ident) => {
        impl std::ops::$tr for $t {
            type Output = $t;
            #[inline(always)]
            fn $f(self, o: $t) -> $t {
                self.$imp(o)
            }
        }
    };
}
binop!(F4, Add, add, add_);
binop!(F4, Sub, sub, sub_);
binop!(F4, Mul, mul, mul_);
binop!(F4, Div, div, div_);
binop!(M4, BitAnd, bitand, and_);
binop!(M4, BitOr, bitor, or_);

/// Asks the CPU to bring every cache line holding `count` values from `p` on into the cache
/// (a hint: no effect on results, and none at all off x86-64). Lines are counted from the
/// address, not the length: a 160-byte block that starts mid-line spans four lines, not three.
#[inline(always)]
pub fn prefetch<T>(p: *const T, count: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        let first = p as usize & !63;
        let last = (p as usize + std::mem::size_of::<T>() * count - 1) & !63;
        let mut line = first;
        while line <= last {
            // SAFETY: prefetching never faults, whatever the address.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(line as *const i8) };
            line += 64;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (p, count);
}

/// Bits of the lanes of `a` with the top bit set.
#[inline(always)]
pub fn sign_bits(a: &[u32; 4]) -> u32 {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE2 is part of the x86-64 baseline; the load reads `a`.
    unsafe {
        _mm_movemask_ps(_mm_loadu_ps(a.as_ptr().cast())) as u32
    }
    #[cfg(not(target_arch = "x86_64"))]
    (0..4).map(|i| (a[i] >> 31) << i).sum()
}

/// Bits of the lanes of `a` equal to `u32::MAX`.
#[inline(always)]
pub fn max_bits(a: &[u32; 4]) -> u32 {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: as in `sign_bits`.
    unsafe {
        let e = _mm_cmpeq_epi32(_mm_loadu_si128(a.as_ptr().cast()), _mm_set1_epi32(-1));
        _mm_movemask_ps(_mm_castsi128_ps(e)) as u32
    }
    #[cfg(not(target_arch = "x86_64"))]
    (0..4).map(|i| ((a[i] == u32::MAX) as u32) << i).sum()
}

/// Eight `f32` lanes: the operations the box test needs.
pub trait Vec8: Copy {
    fn splat(x: f32) -> Self;
    /// Loads eight lanes (32-byte aligned).
    fn load(a: &[f32; 8]) -> Self;
    fn to_array(self) -> [f32; 8];
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    /// `a < b ? a : b`.
    fn min(self, o: Self) -> Self;
    /// `a > b ? a : b`.
    fn max(self, o: Self) -> Self;
    /// Bits of the lanes where `self <= o`.
    fn le_bits(self, o: Self) -> u32;
    /// Bits of the lanes of `a` that differ from `u32::MAX`.
    fn used_bits(a: &[u32; 8]) -> u32;

    /// The children `mask` (nonzero) of `child` with entry distances `self` (lanes ≥ 0), as
    /// keys `distance bits << 32 | child`: all but the nearest written to `out[..n - 1]`
    /// farthest first (the rest of `out` may be written too); returns the nearest's key.
    #[inline(always)]
    fn far_first(self, child: &[u32; 8], mask: u32, out: &mut [MaybeUninit<u64>; 8]) -> u64 {
        let near = self.to_array();
        let mut keys = [0u64; 8];
        let mut m = mask;
        let mut n = 0;
        while m != 0 {
            let lane = m.trailing_zeros() as usize;
            m &= m - 1;
            let key = ((near[lane].to_bits() as u64) << 32) | child[lane] as u64;
            super::traverse::insert_far_first(&mut keys, n, key);
            n += 1;
        }
        for (o, k) in out.iter_mut().zip(keys) {
            o.write(k);
        }
        keys[n - 1]
    }

    /// The children `mask` (nonzero) of `child`: all but the first written to `out[..n - 1]`
    /// in lane order (the rest of `out` may be written too); returns the first.
    #[inline(always)]
    fn first_and_rest(child: &[u32; 8], mask: u32, out: &mut [MaybeUninit<u32>; 8]) -> u32 {
        let first = child[mask.trailing_zeros() as usize];
        let mut m = mask & (mask - 1);
        let mut n = 0;
        while m != 0 {
            out[n].write(child[m.trailing_zeros() as usize]);
            n += 1;
            m &= m - 1;
        }
        first
    }
}

/// Eight lanes as two [`F4`]s (the baseline).
#[derive(Clone, Copy, Debug)]
pub struct Pair8(F4, F4);

impl Vec8 for Pair8 {
    #[inline(always)]
    fn splat(x: f32) -> Pair8 {
        Pair8(F4::splat(x), F4::splat(x))
    }
    #[inline(always)]
    fn load(a: &[f32; 8]) -> Pair8 {
        let (l, h) = a.split_at(4);
        Pair8(
            F4::load(l.try_into().unwrap()),
            F4::load(h.try_into().unwrap()),
        )
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        let (l, h) = (self.0.to_array(), self.1.to_array());
        [l[0], l[1], l[2], l[3], h[0], h[1], h[2], h[3]]
    }
    #[inline(always)]
    fn sub(self, o: Pair8) -> Pair8 {
        Pair8(self.0 - o.0, self.1 - o.1)
    }
    #[inline(always)]
    fn mul(self, o: Pair8) -> Pair8 {
        Pair8(self.0 * o.0, self.1 * o.1)
    }
    #[inline(always)]
    fn min(self, o: Pair8) -> Pair8 {
        Pair8(self.0.min(o.0), self.1.min(o.1))
    }
    #[inline(always)]
    fn max(self, o: Pair8) -> Pair8 {
        Pair8(self.0.max(o.0), self.1.max(o.1))
    }
    #[inline(always)]
    fn le_bits(self, o: Pair8) -> u32 {
        self.0.le(o.0).bits() | (self.1.le(o.1).bits() << 4)
    }
    #[inline(always)]
    fn used_bits(a: &[u32; 8]) -> u32 {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: SSE2 is part of the x86-64 baseline; the loads read within `a`.
        unsafe {
            let all = _mm_set1_epi32(-1);
            let l = _mm_cmpeq_epi32(_mm_loadu_si128(a.as_ptr().cast()), all);
            let h = _mm_cmpeq_epi32(_mm_loadu_si128(a.as_ptr().add(4).cast()), all);
            let m =
                _mm_movemask_ps(_mm_castsi128_ps(l)) | (_mm_movemask_ps(_mm_castsi128_ps(h)) << 4);
            !(m as u32) & 0xff
        }
        #[cfg(not(target_arch = "x86_64"))]
        (0..8).map(|i| ((a[i] != u32::MAX) as u32) << i).sum()
    }
}

/// Eight lanes in one AVX register.
///
/// Only for code compiled with AVX enabled (the AVX2 and AVX-512 variants of
/// [`super::isa`]): its methods use AVX instructions unconditionally.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct Avx8(pub(super) __m256);

// SAFETY (whole block): only instantiated inside `#[target_feature(enable = "avx2", ...)]`
// functions, which run only after `Isa::supported` confirmed AVX2.
#[cfg(target_arch = "x86_64")]
impl Vec8 for Avx8 {
    #[inline(always)]
    fn splat(x: f32) -> Avx8 {
        unsafe { Avx8(_mm256_set1_ps(x)) }
    }
    #[inline(always)]
    fn load(a: &[f32; 8]) -> Avx8 {
        unsafe { Avx8(_mm256_loadu_ps(a.as_ptr())) }
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        let mut a = [0.0; 8];
        unsafe { _mm256_storeu_ps(a.as_mut_ptr(), self.0) };
        a
    }
    #[inline(always)]
    fn sub(self, o: Avx8) -> Avx8 {
        unsafe { Avx8(_mm256_sub_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn mul(self, o: Avx8) -> Avx8 {
        unsafe { Avx8(_mm256_mul_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn min(self, o: Avx8) -> Avx8 {
        unsafe { Avx8(_mm256_min_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn max(self, o: Avx8) -> Avx8 {
        unsafe { Avx8(_mm256_max_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn le_bits(self, o: Avx8) -> u32 {
        unsafe { _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0)) as u32 }
    }
    #[inline(always)]
    fn used_bits(a: &[u32; 8]) -> u32 {
        unsafe {
            let e =
                _mm256_cmpeq_epi32(_mm256_loadu_si256(a.as_ptr().cast()), _mm256_set1_epi32(-1));
            !(_mm256_movemask_ps(_mm256_castsi256_ps(e)) as u32) & 0xff
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check8<V: Vec8>() {
        let a = V::load(&[1.0, f32::NAN, 3.0, -0.0, 5.0, 6.0, 7.0, 8.0]);
        let b = V::load(&[2.0, 5.0, f32::NAN, 0.0, 1.0, 6.0, 9.0, -8.0]);
        let min = a.min(b).to_array();
        assert_eq!(min[..2], [1.0, 5.0]);
        assert!(min[2].is_nan());
        assert_eq!(min[4..], [1.0, 6.0, 7.0, -8.0]);
        assert_eq!(a.max(b).to_array()[1], 5.0);
        assert_eq!(a.le_bits(b), 0b0110_1001);
        assert_eq!(a.sub(b).mul(V::splat(2.0)).to_array()[7], 32.0);
        let mut c = [u32::MAX; 8];
        (c[1], c[6]) = (0, 7);
        assert_eq!(V::used_bits(&c), 0b0100_0010);
    }

    #[test]
    fn lanes_follow_minps_semantics_and_mask_bits() {
        let a = F4::from_array([1.0, f32::NAN, 3.0, -0.0]);
        let b = F4::from_array([2.0, 5.0, f32::NAN, 0.0]);
        // NaN in either operand returns the second operand, as minps / maxps do.
        assert_eq!(a.min(b).to_array()[..2], [1.0, 5.0]);
        assert!(a.min(b).to_array()[2].is_nan());
        assert_eq!(a.max(b).to_array()[1], 5.0);
        assert_eq!(a.lt(b).bits(), 0b0001);
        assert_eq!(a.le(b).bits(), 0b1001);
        assert_eq!((a.lt(b) | a.eq(b)).bits(), 0b1001);
        assert_eq!((a.le(b) & b.gt(F4::splat(1.0))).bits(), 0b0001);
        assert_eq!((a - b).abs().to_array()[0], 1.0);
        assert_eq!((a * a / F4::splat(2.0) + a).to_array()[0], 1.5);
        let ids = [7, u32::MAX, 1 << 31, (1 << 31) | 5];
        assert_eq!((sign_bits(&ids), max_bits(&ids)), (0b1110, 0b0010));
        check8::<Pair8>();
        #[cfg(target_arch = "x86_64")]
        if is_x86_feature_detected!("avx2") {
            check8::<Avx8>();
        }
    }
}
