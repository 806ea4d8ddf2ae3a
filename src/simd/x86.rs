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

macro_rules! binop {
    ($t:ident, $tr:ident, $f:ident, $atr:ident, $af:ident, $intr:ident) => {
        impl $tr for $t {
            type Output = $t;
            #[inline(always)]
            fn $f(self, o: $t) -> $t {
                unsafe { $t($intr(self.0, o.0)) }
            }
        }
        impl $atr for $t {
            #[inline(always)]
            fn $af(&mut self, o: $t) {
                *self = $tr::$f(*self, o);
            }
        }
    };
}
binop!(F8, Add, add, AddAssign, add_assign, _mm256_add_ps);
binop!(F8, Sub, sub, SubAssign, sub_assign, _mm256_sub_ps);
binop!(F8, Mul, mul, MulAssign, mul_assign, _mm256_mul_ps);
binop!(F8, Div, div, DivAssign, div_assign, _mm256_div_ps);

impl Neg for F8 {
    type Output = F8;
    #[inline(always)]
    fn neg(self) -> F8 {
        unsafe { F8(_mm256_xor_ps(self.0, _mm256_set1_ps(-0.0))) }
    }
}

macro_rules! maskop {
    ($tr:ident, $f:ident, $intr:ident) => {
        impl $tr for M8 {
            type Output = M8;
            #[inline(always)]
            fn $f(self, o: M8) -> M8 {
                unsafe { M8($intr(self.0, o.0)) }
            }
        }
    };
}
maskop!(BitAnd, bitand, _mm256_and_ps);
maskop!(BitOr, bitor, _mm256_or_ps);

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

macro_rules! intop {
    ($tr:ident, $f:ident, $intr:ident) => {
        impl $tr for I8 {
            type Output = I8;
            #[inline(always)]
            fn $f(self, o: I8) -> I8 {
                unsafe { I8($intr(self.0, o.0)) }
            }
        }
    };
}
intop!(Add, add, _mm256_add_epi32);
intop!(Sub, sub, _mm256_sub_epi32);
intop!(BitAnd, bitand, _mm256_and_si256);
intop!(BitOr, bitor, _mm256_or_si256);
intop!(BitXor, bitxor, _mm256_xor_si256);

impl Int for I8 {
    type M = M8;
    #[inline(always)]
    fn splat(v: i32) -> I8 {
        unsafe { I8(_mm256_set1_epi32(v)) }
    }
    #[inline(always)]
    fn mul_lo(self, o: I8) -> I8 {
        unsafe { I8(_mm256_mullo_epi32(self.0, o.0)) }
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
    fn gather(s: &[u32], idx: I8) -> I8 {
        debug_assert!((0..8).all(|i| (idx.lane(i) as u32 as usize) < s.len()));
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
    #[inline(always)]
    fn lt(self, o: F8) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_LT_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn le(self, o: F8) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn gt(self, o: F8) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_GT_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn ge(self, o: F8) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_GE_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn eq(self, o: F8) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_EQ_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn ne(self, o: F8) -> M8 {
        // Unordered or unequal, as `!=` on f32 (true with a NaN operand).
        unsafe { M8(_mm256_cmp_ps::<_CMP_NEQ_UQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn is_nan(self) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_UNORD_Q>(self.0, self.0)) }
    }
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
    #[inline(always)]
    fn sqrt(self) -> F8 {
        unsafe { F8(_mm256_sqrt_ps(self.0)) }
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
    fn floor(self) -> F8 {
        unsafe { F8(_mm256_floor_ps(self.0)) }
    }
    #[inline(always)]
    fn to_bits(self) -> I8 {
        unsafe { I8(_mm256_castps_si256(self.0)) }
    }
    #[inline(always)]
    fn from_bits(i: I8) -> F8 {
        unsafe { F8(_mm256_castsi256_ps(i.0)) }
    }
    #[inline(always)]
    fn to_int(self) -> I8 {
        unsafe { I8(_mm256_cvttps_epi32(self.0)) }
    }
    #[inline(always)]
    fn from_int(i: I8) -> F8 {
        unsafe { F8(_mm256_cvtepi32_ps(i.0)) }
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
    fn gather(s: &[f32], idx: I8) -> F8 {
        debug_assert!((0..8).all(|i| (idx.lane(i) as u32 as usize) < s.len()));
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
}
