//! Wave optics used by the materials: coherent thin-film interference (one film by the Airy sum,
//! stacks of layers by the characteristic-matrix method, a fast four-wavelength evaluator for
//! rendering), refractive indices, and the film tool behind `ophis thinfilm`.
//!
//! Layering: nothing here imports `bsdf`, `scene`, `plot` or the renderer (the figures of
//! `ophis thinfilm` are drawn by the binary).

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
