//! Wave optics used by the materials: coherent thin-film interference (one film by the Airy sum,
//! stacks of layers by the characteristic-matrix method, a fast four-wavelength evaluator for
//! rendering), refractive indices, and the film tool behind `ophis thinfilm`.
//!
//! Layering: nothing here imports `bsdf`, `scene`, `plot` or the renderer (the figures of
//! `ophis thinfilm` are drawn by the binary).

/// `pow`: a 4-lane transfer matrix to the power n by repeated squaring, renormalised after
/// every product (for a type with `I`, `mul` and `renormalise`; the complex and the real
/// matrices share it).
macro_rules! pow_by_squaring {
    ($($vis:tt)*) => {
        /// self^n by repeated squaring.
        #[inline(always)]
        $($vis)* fn pow(&self, mut n: u32) -> Self {
            let (mut base, mut acc) = (*self, Self::I);
            while n > 0 {
                if n & 1 == 1 {
                    acc = acc.mul(&base);
                    acc.renormalise();
                }
                n >>= 1;
                if n > 0 {
                    base = base.mul(&base);
                    base.renormalise();
                }
            }
            acc
        }
    };
}
use pow_by_squaring;

pub(crate) mod charmatrix;
mod cplxmat4;
pub mod filmstack;
#[cfg(test)]
mod filmstack_tests;
pub mod filmtool;
pub mod ior;
mod realmat4;
pub(crate) mod simd4;
pub mod stackeval;
pub mod stackspec;
pub mod thinfilm;
mod thinfilm_lanes;
