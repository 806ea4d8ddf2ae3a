//! Ray-intersection acceleration over all primitives of all scene shapes.
//!
//! [`Bvh`] is the production structure; [`BruteForce`] tests every primitive and serves as the
//! oracle in tests.
use crate::math::Ray;
use crate::shape::{Hit, Shape};

pub mod brute;
pub mod bvh;
pub mod wide;

pub use brute::BruteForce;
pub use bvh::Bvh;

/// A structure answering ray queries against a shape list.
pub trait Accel {
    /// The closest hit with parameter in (0, ray.t_max), if any.
    fn intersect(&self, shapes: &[Shape], ray: &Ray) -> Option<Hit>;
    /// Whether any primitive is hit with parameter in (0, ray.t_max).
    fn occluded(&self, shapes: &[Shape], ray: &Ray) -> bool;
}

#[cfg(test)]
mod tests;
