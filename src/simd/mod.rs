//! Lanes: `f32` arithmetic written once and run on one value ([`f32`]), on eight at once
//! ([`F8`], AVX2) or on sixteen ([`F16`], AVX-512), so that the wavefront integrator's kernels
//! and the scalar code they mirror share their arithmetic.
//!
//! [`Float`] is the lane type: IEEE single precision with the operations the renderer needs,
//! comparisons into a [`Mask`], blends, and bit-level access through the matching [`Int`]
//! (32-bit integer lanes). Every operation rounds exactly as the scalar one does — nothing is
//! fused (no FMA contraction), `sqrt` and division are correctly rounded, and `min`/`max` keep
//! Rust's NaN rule (a NaN operand yields the other one) — so a computation written against
//! `Float` gives the same bits in every lane as it gives on one `f32`. The transcendental
//! functions the kernels need are ours ([`fastmath`]) for the same reason: both the scalar code
//! and the lanes call them.
//!
//! The AVX2 and AVX-512 types are only sound to use inside functions compiled with their
//! target features (see [`crate::integrator::wave`], which dispatches at run time); its methods
//! are `#[inline(always)]` so that they compile into the caller's instruction set.

#[cfg(target_arch = "x86_64")]
#[macro_use]
mod macros;
pub mod fastmath;
mod scalar;
mod vec;
#[cfg(target_arch = "x86_64")]
mod x512;
#[cfg(target_arch = "x86_64")]
mod x86;

pub use vec::{V2, V3};

#[cfg(test)]
mod tests;
#[cfg(target_arch = "x86_64")]
pub use x512::{F16, I16, M16};
#[cfg(target_arch = "x86_64")]
pub use x86::{F8, I8, M8};

/// The indices of the set bits of a lane mask, lowest first.
#[inline(always)]
pub fn lanes(bits: u32) -> impl Iterator<Item = usize> {
    let mut b = bits;
    std::iter::from_fn(move || {
        (b != 0).then(|| {
            let i = b.trailing_zeros() as usize;
            b &= b - 1;
            i
        })
    })
}

use std::fmt::Debug;
use std::ops::{
    Add, AddAssign, BitAnd, BitOr, BitXor, Div, DivAssign, Mul, MulAssign, Neg, Not, Sub, SubAssign,
};

/// The memory operations of lanes stored as `$e`, declared in [`Int`] and [`Float`]: loads and
/// stores of whole lane sets (`load` and `store` are `load_at` and `store_at` at 0), a gather by
/// the integer lanes `$idx`, and one lane read out as `$lane`.
macro_rules! memory {
    ($e:ty, $idx:ty, $lane:ty) => {
        /// Loads lanes from `s[0..LANES]`.
        #[inline(always)]
        fn load(s: &[$e]) -> Self {
            Self::load_at(s, 0)
        }
        /// Stores lanes to `s[0..LANES]`.
        #[inline(always)]
        fn store(self, s: &mut [$e]) {
            self.store_at(s, 0)
        }
        /// Loads lanes from `s[i..i + LANES]` (one bounds check).
        fn load_at(s: &[$e], i: usize) -> Self;
        /// Stores lanes to `s[i..i + LANES]` (one bounds check).
        fn store_at(self, s: &mut [$e], i: usize);
        /// `s[idx[i]]` in lane i. Panics if an index is out of bounds (all lanes are
        /// checked at once: one compare and one branch beside the gather).
        fn gather(s: &[$e], idx: $idx) -> Self;
        /// Lane `i`.
        fn lane(self, i: usize) -> $lane;
    };
}

/// A set of lanes of booleans, the result of comparing [`Float`]s or [`Int`]s.
pub trait Mask:
    Copy + Debug + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self>
{
    /// Every lane set to `v`.
    fn splat(v: bool) -> Self;
    /// Whether any lane is set.
    fn any(self) -> bool;
    /// Whether every lane is set.
    fn all(self) -> bool;
    /// Lane i → bit i.
    fn bits(self) -> u32;
    /// A mask from bits (lane i set when bit i is).
    fn from_bits(bits: u32) -> Self;
    /// `self` and not `o`.
    #[inline(always)]
    fn and_not(self, o: Self) -> Self {
        self & !o
    }
}

/// Lanes of 32-bit integers (two's complement, wrapping arithmetic).
pub trait Int:
    Copy
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + BitXor<Output = Self>
{
    /// The matching mask type.
    type M: Mask;
    /// Every lane set to `v`.
    fn splat(v: i32) -> Self;
    /// Lane-wise multiplication (low 32 bits).
    fn mul_lo(self, o: Self) -> Self;
    /// Logical shift left by `n` bits.
    fn shl<const N: i32>(self) -> Self;
    /// Logical (unsigned) shift right by `n` bits.
    fn shr<const N: i32>(self) -> Self;
    /// Signed comparison.
    fn eq(self, o: Self) -> Self::M;
    /// Signed comparison.
    fn lt(self, o: Self) -> Self::M;
    /// Signed comparison.
    fn gt(self, o: Self) -> Self::M;
    /// `m ? a : b` lane by lane.
    fn select(m: Self::M, a: Self, b: Self) -> Self;
    memory!(u32, Self, i32);
}

/// Lanes of `f32`; see the module header.
pub trait Float:
    Copy
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
{
    /// The mask type of comparisons.
    type M: Mask;
    /// Integer lanes of the same width.
    type I: Int<M = Self::M>;
    /// Number of lanes.
    const LANES: usize;

    /// Every lane set to `v`.
    fn splat(v: f32) -> Self;
    /// `a < b` lane by lane (false with a NaN operand), and so on.
    fn lt(self, o: Self) -> Self::M;
    fn le(self, o: Self) -> Self::M;
    fn gt(self, o: Self) -> Self::M;
    fn ge(self, o: Self) -> Self::M;
    fn eq(self, o: Self) -> Self::M;
    fn ne(self, o: Self) -> Self::M;
    /// Lanes holding NaN.
    fn is_nan(self) -> Self::M;
    /// `m ? a : b` lane by lane.
    fn select(m: Self::M, a: Self, b: Self) -> Self;
    /// [`f32::min`] lane by lane (a NaN operand yields the other).
    fn min(self, o: Self) -> Self;
    /// [`f32::max`] lane by lane (a NaN operand yields the other).
    fn max(self, o: Self) -> Self;
    /// Absolute value (clears the sign bit).
    fn abs(self) -> Self;
    /// Correctly rounded square root.
    fn sqrt(self) -> Self;
    /// The magnitude of `self` with the sign of `sign`.
    fn copysign(self, sign: Self) -> Self;
    /// Round towards −∞.
    fn floor(self) -> Self;
    /// The bits of each lane.
    fn to_bits(self) -> Self::I;
    /// Lanes from bits.
    fn from_bits(i: Self::I) -> Self;
    /// Conversion to integers rounding towards zero (as `as i32` for values in range).
    fn to_int(self) -> Self::I;
    /// Conversion from signed integers (round to nearest).
    fn from_int(i: Self::I) -> Self;
    memory!(f32, Self::I, f32);
    /// Lanes from a function of the lane index.
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    /// PCG32 generators in lanes ([`crate::math::Pcg32::next_f32`]): for the lanes of `m`,
    /// advances `state[i]` (increment `inc[i]`) and returns the generator's next float in
    /// [0, 1); other lanes return 0 and keep their state.
    fn pcg_next_f32(state: &mut [u64], inc: &[u64], m: Self::M) -> Self;

    /// `x.max(0.0).sqrt()`: the square root of a value that rounding may have made slightly
    /// negative.
    #[inline(always)]
    fn safe_sqrt(self) -> Self {
        self.max(Self::splat(0.0)).sqrt()
    }
    /// Whether each lane is finite.
    #[inline(always)]
    fn is_finite(self) -> Self::M {
        self.abs().lt(Self::splat(f32::INFINITY))
    }
    /// [`f32::clamp`] lane by lane (a NaN stays NaN).
    #[inline(always)]
    fn clamp(self, lo: f32, hi: f32) -> Self {
        let (l, h) = (Self::splat(lo), Self::splat(hi));
        Self::select(self.lt(l), l, Self::select(self.gt(h), h, self))
    }
}
