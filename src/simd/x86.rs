//! Eight lanes in one AVX register: [`F8`], [`M8`] (a mask of all-ones or all-zero lanes) and
//! [`I8`]. See the module header of [`super`]: these are sound only where AVX2 is enabled.
// The intrinsics are `unsafe` because they need AVX/AVX2; every use below sits in an
// `#[inline(always)]` method that is only called from code compiled with those features.
#![allow(clippy::undocumented_unsafe_blocks)]

use super::{Float, Int, Mask};
use std::arch::x86_64::*;
use std::ops::{
    Add, AddAssign, BitAnd, BitOr, BitXor, Div, DivAssign, Mul, MulAssign, Neg, Not, Sub, SubAssign,
};

/// Eight `f32` lanes.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct F8(pub __m256);

/// Eight lanes of booleans (each all ones or all zeros).
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct M8(pub __m256);

/// Eight `i32` lanes.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct I8(pub __m256i);

binop!(F8, Add, add, _mm256_add_ps, AddAssign, add_assign);
binop!(F8, Sub, sub, _mm256_sub_ps, SubAssign, sub_assign);
binop!(F8, Mul, mul, _mm256_mul_ps, MulAssign, mul_assign);
binop!(F8, Div, div, _mm256_div_ps, DivAssign, div_assign);

impl Neg for F8 {
    type Output = F8;
    #[inline(always)]
    fn neg(self) -> F8 {
        unsafe { F8(_mm256_xor_ps(self.0, _mm256_set1_ps(-0.0))) }
    }
}

binop!(M8, BitAnd, bitand, _mm256_and_ps);
binop!(M8, BitOr, bitor, _mm256_or_ps);

impl Not for M8 {
    type Output = M8;
    #[inline(always)]
    fn not(self) -> M8 {
        unsafe {
            M8(_mm256_xor_ps(
                self.0,
                _mm256_castsi256_ps(_mm256_set1_epi32(-1)),
            ))
        }
    }
}

impl Mask for M8 {
    #[inline(always)]
    fn splat(v: bool) -> M8 {
        unsafe { M8(_mm256_castsi256_ps(_mm256_set1_epi32(-(v as i32)))) }
    }
    #[inline(always)]
    fn any(self) -> bool {
        unsafe { _mm256_movemask_ps(self.0) != 0 }
    }
    #[inline(always)]
    fn all(self) -> bool {
        unsafe { _mm256_movemask_ps(self.0) == 0xff }
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        unsafe { _mm256_movemask_ps(self.0) as u32 }
    }
    #[inline(always)]
    fn from_bits(bits: u32) -> M8 {
        unsafe {
            let lanes = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let b = _mm256_and_si256(_mm256_set1_epi32(bits as i32), lanes);
            M8(_mm256_castsi256_ps(_mm256_cmpeq_epi32(b, lanes)))
        }
    }
    #[inline(always)]
    fn and_not(self, o: M8) -> M8 {
        unsafe { M8(_mm256_andnot_ps(o.0, self.0)) }
    }
}

binop!(I8, Add, add, _mm256_add_epi32);
binop!(I8, Sub, sub, _mm256_sub_epi32);
binop!(I8, BitAnd, bitand, _mm256_and_si256);
binop!(I8, BitOr, bitor, _mm256_or_si256);
binop!(I8, BitXor, bitxor, _mm256_xor_si256);

/// Panics unless every lane of `idx` is an index below `len` (as an unsigned number, so a
/// negative index fails too; `len` is capped at `i32::MAX`, the gathers' signed range).
#[inline(always)]
fn check_gather(idx: I8, len: usize) {
    let len = len.min(i32::MAX as usize) as i32;
    // idx < len, unsigned: min(idx, len − 1) = idx in every lane (and no lane when len is 0).
    // SAFETY: AVX2 is enabled wherever these lanes are used (see the module header).
    let ok = unsafe {
        let last = _mm256_set1_epi32(len.wrapping_sub(1));
        let same = _mm256_cmpeq_epi32(_mm256_min_epu32(idx.0, last), idx.0);
        _mm256_movemask_ps(_mm256_castsi256_ps(same))
    };
    if ok != 0xff || len == 0 {
        gather_out_of_bounds(len);
    }
}

#[cold]
#[inline(never)]
fn gather_out_of_bounds(len: i32) -> ! {
    panic!("gather: an index is out of bounds for a table of {len}")
}

impl Int for I8 {
    type M = M8;
    #[inline(always)]
    fn splat(v: i32) -> I8 {
        unsafe { I8(_mm256_set1_epi32(v)) }
    }
    intrinsics! {
        fn mul_lo(self, o: I8) -> I8 = _mm256_mullo_epi32;
    }
    #[inline(always)]
    fn shl<const N: i32>(self) -> I8 {
        unsafe { I8(_mm256_slli_epi32::<N>(self.0)) }
    }
    #[inline(always)]
    fn shr<const N: i32>(self) -> I8 {
        unsafe { I8(_mm256_srli_epi32::<N>(self.0)) }
    }
    #[inline(always)]
    fn eq(self, o: I8) -> M8 {
        unsafe { M8(_mm256_castsi256_ps(_mm256_cmpeq_epi32(self.0, o.0))) }
    }
    #[inline(always)]
    fn lt(self, o: I8) -> M8 {
        unsafe { M8(_mm256_castsi256_ps(_mm256_cmpgt_epi32(o.0, self.0))) }
    }
    #[inline(always)]
    fn gt(self, o: I8) -> M8 {
        unsafe { M8(_mm256_castsi256_ps(_mm256_cmpgt_epi32(self.0, o.0))) }
    }
    #[inline(always)]
    fn select(m: M8, a: I8, b: I8) -> I8 {
        unsafe {
            I8(_mm256_castps_si256(_mm256_blendv_ps(
                _mm256_castsi256_ps(b.0),
                _mm256_castsi256_ps(a.0),
                m.0,
            )))
        }
    }
    #[inline(always)]
    fn load(s: &[u32]) -> I8 {
        assert!(s.len() >= 8);
        unsafe { I8(_mm256_loadu_si256(s.as_ptr() as *const __m256i)) }
    }
    #[inline(always)]
    fn store(self, s: &mut [u32]) {
        assert!(s.len() >= 8);
        unsafe { _mm256_storeu_si256(s.as_mut_ptr() as *mut __m256i, self.0) }
    }
    #[inline(always)]
    fn load_at(s: &[u32], i: usize) -> I8 {
        assert!(i + 8 <= s.len());
        unsafe { I8(_mm256_loadu_si256(s.as_ptr().add(i) as *const __m256i)) }
    }
    #[inline(always)]
    fn store_at(self, s: &mut [u32], i: usize) {
        assert!(i + 8 <= s.len());
        unsafe { _mm256_storeu_si256(s.as_mut_ptr().add(i) as *mut __m256i, self.0) }
    }
    #[inline(always)]
    fn gather(s: &[u32], idx: I8) -> I8 {
        check_gather(idx, s.len());
        // SAFETY: every index is in bounds (checked above).
        unsafe { I8(_mm256_i32gather_epi32::<4>(s.as_ptr() as *const i32, idx.0)) }
    }
    #[inline(always)]
    fn lane(self, i: usize) -> i32 {
        let mut a = [0i32; 8];
        unsafe { _mm256_storeu_si256(a.as_mut_ptr() as *mut __m256i, self.0) };
        a[i]
    }
}

impl Float for F8 {
    type M = M8;
    type I = I8;
    const LANES: usize = 8;

    #[inline(always)]
    fn splat(v: f32) -> F8 {
        unsafe { F8(_mm256_set1_ps(v)) }
    }
    float_comparisons!(M8, _mm256_cmp_ps);
    #[inline(always)]
    fn select(m: M8, a: F8, b: F8) -> F8 {
        unsafe { F8(_mm256_blendv_ps(b.0, a.0, m.0)) }
    }
    #[inline(always)]
    fn min(self, o: F8) -> F8 {
        // minps(o, self) is `o < self ? o : self`, which returns `self` when either is NaN;
        // Rust's min returns the other operand when `self` is NaN.
        unsafe {
            let m = _mm256_min_ps(o.0, self.0);
            F8(_mm256_blendv_ps(m, o.0, self.is_nan().0))
        }
    }
    #[inline(always)]
    fn max(self, o: F8) -> F8 {
        unsafe {
            let m = _mm256_max_ps(o.0, self.0);
            F8(_mm256_blendv_ps(m, o.0, self.is_nan().0))
        }
    }
    #[inline(always)]
    fn abs(self) -> F8 {
        unsafe { F8(_mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0)) }
    }
    intrinsics! {
        fn sqrt(self) -> F8 = _mm256_sqrt_ps;
        fn floor(self) -> F8 = _mm256_floor_ps;
        fn to_bits(self) -> I8 = _mm256_castps_si256;
        fn from_bits(i: I8) -> F8 = _mm256_castsi256_ps;
        fn to_int(self) -> I8 = _mm256_cvttps_epi32;
        fn from_int(i: I8) -> F8 = _mm256_cvtepi32_ps;
    }
    #[inline(always)]
    fn copysign(self, sign: F8) -> F8 {
        unsafe {
            let s = _mm256_set1_ps(-0.0);
            F8(_mm256_or_ps(
                _mm256_andnot_ps(s, self.0),
                _mm256_and_ps(s, sign.0),
            ))
        }
    }
    #[inline(always)]
    fn load(s: &[f32]) -> F8 {
        assert!(s.len() >= 8);
        unsafe { F8(_mm256_loadu_ps(s.as_ptr())) }
    }
    #[inline(always)]
    fn store(self, s: &mut [f32]) {
        assert!(s.len() >= 8);
        unsafe { _mm256_storeu_ps(s.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn load_at(s: &[f32], i: usize) -> F8 {
        assert!(i + 8 <= s.len());
        unsafe { F8(_mm256_loadu_ps(s.as_ptr().add(i))) }
    }
    #[inline(always)]
    fn store_at(self, s: &mut [f32], i: usize) {
        assert!(i + 8 <= s.len());
        unsafe { _mm256_storeu_ps(s.as_mut_ptr().add(i), self.0) }
    }
    #[inline(always)]
    fn gather(s: &[f32], idx: I8) -> F8 {
        check_gather(idx, s.len());
        // SAFETY: every index is in bounds (checked above).
        unsafe { F8(_mm256_i32gather_ps::<4>(s.as_ptr(), idx.0)) }
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        let mut a = [0f32; 8];
        unsafe { _mm256_storeu_ps(a.as_mut_ptr(), self.0) };
        a[i]
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f32) -> F8 {
        let a: [f32; 8] = std::array::from_fn(f);
        F8::load(&a)
    }
    #[inline(always)]
    fn pcg_next_f32(state: &mut [u64], inc: &[u64], m: M8) -> F8 {
        assert!(state.len() >= 8 && inc.len() >= 8);
        unsafe {
            // Two registers of four 64-bit states.
            let s0 = _mm256_loadu_si256(state.as_ptr() as *const __m256i);
            let s1 = _mm256_loadu_si256(state.as_ptr().add(4) as *const __m256i);
            let i0 = _mm256_loadu_si256(inc.as_ptr() as *const __m256i);
            let i1 = _mm256_loadu_si256(inc.as_ptr().add(4) as *const __m256i);
            let mask = _mm256_castps_si256(m.0);
            let m0 = _mm256_cvtepi32_epi64(_mm256_castsi256_si128(mask));
            let m1 = _mm256_cvtepi32_epi64(_mm256_extracti128_si256::<1>(mask));
            let (n0, x0) = pcg_step4(s0, i0);
            let (n1, x1) = pcg_step4(s1, i1);
            _mm256_storeu_si256(
                state.as_mut_ptr() as *mut __m256i,
                _mm256_blendv_epi8(s0, n0, m0),
            );
            _mm256_storeu_si256(
                state.as_mut_ptr().add(4) as *mut __m256i,
                _mm256_blendv_epi8(s1, n1, m1),
            );
            // The outputs sit in the low halves of the 64-bit lanes: gather them in order.
            let even = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
            let lo = _mm256_permutevar8x32_epi32(x0, even);
            let hi = _mm256_permutevar8x32_epi32(x1, even);
            let bits = _mm256_blend_epi32::<0b1111_0000>(lo, hi);
            // 24 high bits, exactly representable: (u >> 8) · 2⁻²⁴.
            let v = _mm256_mul_ps(
                _mm256_cvtepi32_ps(_mm256_srli_epi32::<8>(bits)),
                _mm256_set1_ps(1.0 / 16_777_216.0),
            );
            F8(_mm256_and_ps(v, m.0))
        }
    }
}

/// One PCG32 step of four generators: the new states and the outputs (XSH-RR of the old
/// states, in the low 32 bits of each lane).
#[inline(always)]
unsafe fn pcg_step4(s: __m256i, inc: __m256i) -> (__m256i, __m256i) {
    const MULT: u64 = 0x5851_f42d_4c95_7f2d;
    // s · MULT mod 2⁶⁴ from 32-bit halves: lo·lo + ((hi·lo + lo·hi) << 32).
    let m = _mm256_set1_epi64x(MULT as i64);
    let m_hi = _mm256_set1_epi64x((MULT >> 32) as i64);
    let lo = _mm256_mul_epu32(s, m);
    let cross = _mm256_add_epi64(
        _mm256_mul_epu32(_mm256_srli_epi64::<32>(s), m),
        _mm256_mul_epu32(s, m_hi),
    );
    let next = _mm256_add_epi64(_mm256_add_epi64(lo, _mm256_slli_epi64::<32>(cross)), inc);
    let xorshifted = _mm256_srli_epi64::<27>(_mm256_xor_si256(_mm256_srli_epi64::<18>(s), s));
    let rot = _mm256_srli_epi64::<59>(s);
    // Rotate the low 32 bits right by `rot` (a shift by 32 gives 0, as a rotation by 0 needs).
    let left = _mm256_sub_epi32(_mm256_set1_epi64x(32), rot);
    let out = _mm256_or_si256(
        _mm256_srlv_epi32(xorshifted, rot),
        _mm256_sllv_epi32(xorshifted, left),
    );
    (next, out)
}
