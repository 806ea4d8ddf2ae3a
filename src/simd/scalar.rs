//! One lane: [`Float`] for `f32`, [`Int`] for `i32`, [`Mask`] for `bool`. These are the
//! operations the scalar code performs anyway, so code written against the traits compiles
//! to the same scalar instructions.
use super::{Float, Int, Mask};

/// Comparison methods by the operators of `$t`.
macro_rules! comparisons {
    ($t:ty, $($f:ident $op:tt),*) => {
        $(
            #[inline(always)]
            fn $f(self, o: $t) -> bool {
                self $op o
            }
        )*
    };
}

/// Methods that are `f32`'s own, with the same arguments.
macro_rules! own {
    ($($f:ident($($a:ident),*)),*) => {
        $(
            #[inline(always)]
            fn $f(self $(, $a: f32)*) -> f32 {
                f32::$f(self $(, $a)*)
            }
        )*
    };
}

impl Mask for bool {
    #[inline(always)]
    fn splat(v: bool) -> bool {
        v
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        self as u32
    }
    #[inline(always)]
    fn from_bits(bits: u32) -> bool {
        bits & 1 != 0
    }
}

impl Int for i32 {
    type M = bool;
    comparisons!(i32, eq ==, lt <, gt >);
    #[inline(always)]
    fn splat(v: i32) -> i32 {
        v
    }
    #[inline(always)]
    fn mul_lo(self, o: i32) -> i32 {
        self.wrapping_mul(o)
    }
    #[inline(always)]
    fn shl<const N: i32>(self) -> i32 {
        ((self as u32) << N) as i32
    }
    #[inline(always)]
    fn shr<const N: i32>(self) -> i32 {
        ((self as u32) >> N) as i32
    }
    #[inline(always)]
    fn select(m: bool, a: i32, b: i32) -> i32 {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn load_at(s: &[u32], i: usize) -> i32 {
        s[i] as i32
    }
    #[inline(always)]
    fn store_at(self, s: &mut [u32], i: usize) {
        s[i] = self as u32;
    }
    #[inline(always)]
    fn gather(s: &[u32], idx: i32) -> i32 {
        s[idx as usize] as i32
    }
    #[inline(always)]
    fn lane(self, _: usize) -> i32 {
        self
    }
}

impl Float for f32 {
    type M = bool;
    type I = i32;
    const LANES: usize = 1;
    comparisons!(f32, lt <, le <=, gt >, ge >=, eq ==, ne !=);
    own!(min(o), max(o), abs(), sqrt(), copysign(sign), floor());

    #[inline(always)]
    fn splat(v: f32) -> f32 {
        v
    }
    #[inline(always)]
    fn is_nan(self) -> bool {
        f32::is_nan(self)
    }
    #[inline(always)]
    fn select(m: bool, a: f32, b: f32) -> f32 {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn to_bits(self) -> i32 {
        f32::to_bits(self) as i32
    }
    #[inline(always)]
    fn from_bits(i: i32) -> f32 {
        f32::from_bits(i as u32)
    }
    #[inline(always)]
    fn to_int(self) -> i32 {
        self as i32
    }
    #[inline(always)]
    fn from_int(i: i32) -> f32 {
        i as f32
    }
    #[inline(always)]
    fn load_at(s: &[f32], i: usize) -> f32 {
        s[i]
    }
    #[inline(always)]
    fn store_at(self, s: &mut [f32], i: usize) {
        s[i] = self;
    }
    #[inline(always)]
    fn gather(s: &[f32], idx: i32) -> f32 {
        s[idx as usize]
    }
    #[inline(always)]
    fn lane(self, _: usize) -> f32 {
        self
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> f32 {
        f(0)
    }
    #[inline(always)]
    fn pcg_next_f32(state: &mut [u64], inc: &[u64], m: bool) -> f32 {
        if !m {
            return 0.0;
        }
        let mut r = crate::math::Pcg32::from_raw(state[0], inc[0]);
        let v = r.next_f32();
        state[0] = r.raw().0;
        v
    }
}
