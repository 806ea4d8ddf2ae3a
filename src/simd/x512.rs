//! Sixteen lanes in one AVX-512 register: [`F16`], [`M16`] (a mask register, one bit per lane)
//! and [`I16`]. See the module header of [`super`]: these are sound only where AVX-512 F, BW,
//! DQ and VL are enabled.
// The intrinsics are `unsafe` because they need AVX-512; every use below sits in an
// `#[inline(always)]` method that is only called from code compiled with those features.
#![allow(clippy::undocumented_unsafe_blocks)]

use super::{Float, Int, Mask};
use std::arch::x86_64::*;
use std::ops::{
    Add, AddAssign, BitAnd, BitOr, BitXor, Div, DivAssign, Mul, MulAssign, Neg, Not, Sub, SubAssign,
};

/// Sixteen `f32` lanes.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct F16(pub __m512);

/// Sixteen lanes of booleans, one bit each.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct M16(pub __mmask16);

/// Sixteen `i32` lanes.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct I16(pub __m512i);

binop!(F16, Add, add, _mm512_add_ps, AddAssign, add_assign);
binop!(F16, Sub, sub, _mm512_sub_ps, SubAssign, sub_assign);
binop!(F16, Mul, mul, _mm512_mul_ps, MulAssign, mul_assign);
binop!(F16, Div, div, _mm512_div_ps, DivAssign, div_assign);
binop!(I16, Add, add, _mm512_add_epi32);
binop!(I16, Sub, sub, _mm512_sub_epi32);
binop!(I16, BitAnd, bitand, _mm512_and_si512);
binop!(I16, BitOr, bitor, _mm512_or_si512);
binop!(I16, BitXor, bitxor, _mm512_xor_si512);

impl Neg for F16 {
    type Output = F16;
    #[inline(always)]
    fn neg(self) -> F16 {
        unsafe { F16(_mm512_xor_ps(self.0, _mm512_set1_ps(-0.0))) }
    }
}

impl BitAnd for M16 {
    type Output = M16;
    #[inline(always)]
    fn bitand(self, o: M16) -> M16 {
        M16(self.0 & o.0)
    }
}
impl BitOr for M16 {
    type Output = M16;
    #[inline(always)]
    fn bitor(self, o: M16) -> M16 {
        M16(self.0 | o.0)
    }
}
impl Not for M16 {
    type Output = M16;
    #[inline(always)]
    fn not(self) -> M16 {
        M16(!self.0)
    }
}

impl Mask for M16 {
    #[inline(always)]
    fn splat(v: bool) -> M16 {
        M16(if v { 0xffff } else { 0 })
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0 != 0
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.0 == 0xffff
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        self.0 as u32
    }
    #[inline(always)]
    fn from_bits(bits: u32) -> M16 {
        M16(bits as u16)
    }
}

/// Panics unless every lane of `idx` is an index below `len` (as an unsigned number, so a
/// negative index fails too; `len` is capped at `i32::MAX`, the gathers' signed range).
#[inline(always)]
fn check_gather(idx: I16, len: usize) {
    let len = len.min(i32::MAX as usize) as i32;
    // SAFETY: AVX-512 F is enabled wherever these lanes are used (see the module header).
    let ok = unsafe { _mm512_cmplt_epu32_mask(idx.0, _mm512_set1_epi32(len)) };
    if ok != u16::MAX {
        gather_out_of_bounds(len);
    }
}

#[cold]
#[inline(never)]
fn gather_out_of_bounds(len: i32) -> ! {
    panic!("gather: an index is out of bounds for a table of {len}")
}

impl Int for I16 {
    type M = M16;
    #[inline(always)]
    fn splat(v: i32) -> I16 {
        unsafe { I16(_mm512_set1_epi32(v)) }
    }
    intrinsics! {
        fn mul_lo(self, o: I16) -> I16 = _mm512_mullo_epi32;
        fn eq(self, o: I16) -> M16 = _mm512_cmpeq_epi32_mask;
        fn lt(self, o: I16) -> M16 = _mm512_cmplt_epi32_mask;
        fn gt(self, o: I16) -> M16 = _mm512_cmpgt_epi32_mask;
    }
    #[inline(always)]
    fn shl<const N: i32>(self) -> I16 {
        unsafe { I16(_mm512_sllv_epi32(self.0, _mm512_set1_epi32(N))) }
    }
    #[inline(always)]
    fn shr<const N: i32>(self) -> I16 {
        unsafe { I16(_mm512_srlv_epi32(self.0, _mm512_set1_epi32(N))) }
    }
    #[inline(always)]
    fn select(m: M16, a: I16, b: I16) -> I16 {
        unsafe { I16(_mm512_mask_blend_epi32(m.0, b.0, a.0)) }
    }
    #[inline(always)]
    fn load_at(s: &[u32], i: usize) -> I16 {
        assert!(i + 16 <= s.len());
        unsafe { I16(_mm512_loadu_si512(s.as_ptr().add(i) as *const _)) }
    }
    #[inline(always)]
    fn store_at(self, s: &mut [u32], i: usize) {
        assert!(i + 16 <= s.len());
        unsafe { _mm512_storeu_si512(s.as_mut_ptr().add(i) as *mut _, self.0) }
    }
    #[inline(always)]
    fn gather(s: &[u32], idx: I16) -> I16 {
        check_gather(idx, s.len());
        // SAFETY: every index is in bounds (checked above).
        unsafe { I16(_mm512_i32gather_epi32::<4>(idx.0, s.as_ptr() as *const i32)) }
    }
    #[inline(always)]
    fn lane(self, i: usize) -> i32 {
        let mut a = [0u32; 16];
        self.store(&mut a);
        a[i] as i32
    }
}

impl Float for F16 {
    type M = M16;
    type I = I16;
    const LANES: usize = 16;

    #[inline(always)]
    fn splat(v: f32) -> F16 {
        unsafe { F16(_mm512_set1_ps(v)) }
    }
    float_comparisons!(M16, _mm512_cmp_ps_mask);
    #[inline(always)]
    fn select(m: M16, a: F16, b: F16) -> F16 {
        unsafe { F16(_mm512_mask_blend_ps(m.0, b.0, a.0)) }
    }
    #[inline(always)]
    fn min(self, o: F16) -> F16 {
        // minps(o, self) is `o < self ? o : self`; Rust's min returns `o` when `self` is NaN.
        unsafe {
            let m = _mm512_min_ps(o.0, self.0);
            F16(_mm512_mask_blend_ps(self.is_nan().0, m, o.0))
        }
    }
    #[inline(always)]
    fn max(self, o: F16) -> F16 {
        unsafe {
            let m = _mm512_max_ps(o.0, self.0);
            F16(_mm512_mask_blend_ps(self.is_nan().0, m, o.0))
        }
    }
    intrinsics! {
        fn abs(self) -> F16 = _mm512_abs_ps;
        fn sqrt(self) -> F16 = _mm512_sqrt_ps;
        fn to_bits(self) -> I16 = _mm512_castps_si512;
        fn from_bits(i: I16) -> F16 = _mm512_castsi512_ps;
        fn to_int(self) -> I16 = _mm512_cvttps_epi32;
        fn from_int(i: I16) -> F16 = _mm512_cvtepi32_ps;
    }
    #[inline(always)]
    fn copysign(self, sign: F16) -> F16 {
        unsafe {
            let s = _mm512_set1_ps(-0.0);
            F16(_mm512_or_ps(
                _mm512_andnot_ps(s, self.0),
                _mm512_and_ps(s, sign.0),
            ))
        }
    }
    #[inline(always)]
    fn floor(self) -> F16 {
        // Round towards −∞ (mode 1), without precision exceptions (bit 3).
        unsafe { F16(_mm512_roundscale_ps::<0x09>(self.0)) }
    }
    #[inline(always)]
    fn load_at(s: &[f32], i: usize) -> F16 {
        assert!(i + 16 <= s.len());
        unsafe { F16(_mm512_loadu_ps(s.as_ptr().add(i))) }
    }
    #[inline(always)]
    fn store_at(self, s: &mut [f32], i: usize) {
        assert!(i + 16 <= s.len());
        unsafe { _mm512_storeu_ps(s.as_mut_ptr().add(i), self.0) }
    }
    #[inline(always)]
    fn gather(s: &[f32], idx: I16) -> F16 {
        check_gather(idx, s.len());
        // SAFETY: every index is in bounds (checked above).
        unsafe { F16(_mm512_i32gather_ps::<4>(idx.0, s.as_ptr())) }
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        let mut a = [0f32; 16];
        self.store(&mut a);
        a[i]
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f32) -> F16 {
        let a: [f32; 16] = std::array::from_fn(f);
        F16::load(&a)
    }
    #[inline(always)]
    fn pcg_next_f32(state: &mut [u64], inc: &[u64], m: M16) -> F16 {
        assert!(state.len() >= 16 && inc.len() >= 16);
        unsafe {
            let s0 = _mm512_loadu_si512(state.as_ptr() as *const _);
            let s1 = _mm512_loadu_si512(state.as_ptr().add(8) as *const _);
            let i0 = _mm512_loadu_si512(inc.as_ptr() as *const _);
            let i1 = _mm512_loadu_si512(inc.as_ptr().add(8) as *const _);
            let (n0, x0) = pcg_step8(s0, i0);
            let (n1, x1) = pcg_step8(s1, i1);
            let (m0, m1) = (m.0 as u8, (m.0 >> 8) as u8);
            _mm512_storeu_si512(
                state.as_mut_ptr() as *mut _,
                _mm512_mask_blend_epi64(m0, s0, n0),
            );
            _mm512_storeu_si512(
                state.as_mut_ptr().add(8) as *mut _,
                _mm512_mask_blend_epi64(m1, s1, n1),
            );
            // The outputs are the low halves of the 64-bit lanes, in order.
            let bits = _mm512_inserti64x4::<1>(
                _mm512_castsi256_si512(_mm512_cvtepi64_epi32(x0)),
                _mm512_cvtepi64_epi32(x1),
            );
            // 24 high bits, exactly representable: (u >> 8) · 2⁻²⁴.
            let v = _mm512_mul_ps(
                _mm512_cvtepi32_ps(_mm512_srli_epi32::<8>(bits)),
                _mm512_set1_ps(1.0 / 16_777_216.0),
            );
            F16(_mm512_maskz_mov_ps(m.0, v))
        }
    }
}

/// One PCG32 step of eight generators: the new states and the outputs (XSH-RR of the old
/// states, in the low 32 bits of each lane).
#[inline(always)]
unsafe fn pcg_step8(s: __m512i, inc: __m512i) -> (__m512i, __m512i) {
    const MULT: u64 = 0x5851_f42d_4c95_7f2d;
    let next = _mm512_add_epi64(_mm512_mullo_epi64(s, _mm512_set1_epi64(MULT as i64)), inc);
    let xorshifted = _mm512_srli_epi64::<27>(_mm512_xor_si512(_mm512_srli_epi64::<18>(s), s));
    let rot = _mm512_srli_epi64::<59>(s);
    // Rotating the low 32 bits by the low 32 bits of `rot` (the high halves are ignored).
    (next, _mm512_rorv_epi32(xorshifted, rot))
}
