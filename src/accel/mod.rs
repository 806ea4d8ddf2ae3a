//! Ray-intersection acceleration over all primitives of all scene shapes.
//!
//! # How the data flows
//!
//! **Build** ([`build`]). Every primitive with finite bounds becomes a 32-byte ref (bounds and
//! a lane id: a triangle's global index, or a flagged shape index for a sphere or disk). A
//! top-down binned-SAH build reorders the refs and groups them straight into 8-wide nodes,
//! splitting the child with the largest surface area until a node has eight; leaves hold at
//! most sixteen primitives, and the cost model counts them in blocks of four (the bins and the
//! cost model are in `bins.rs`). Large ranges bin in parallel chunks and subtrees build in
//! parallel, deterministically.
//!
//! **Layout** ([`layout`]). The tree becomes two flat arrays: [`wide::Node8`] (child boxes in
//! structure-of-arrays form, 224 bytes) and [`block::Block`] (the leaves: four slots with
//! copies of their triangles' corners and ids, 160 bytes), leaves in depth-first order. The
//! refs and the build's own nodes are freed as soon as they are consumed, so the peak stays
//! near the final size. The blocks are allocated on huge pages where Linux gives them
//! (`pages.rs`).
//!
//! **Traversal** ([`traverse`]). One ray against eight boxes at once, nearest child first (with
//! AVX-512 the children hit are ordered by a sorting network in one register, `order.rs`,
//! [`crate::accel::simd::Vec8::far_first`]), stack entries beyond the closest hit skipped;
//! leaves test four triangles at once with the watertight test, bit-identical to the scalar one
//! ([`crate::shape::mesh`]); shadow rays stop at the first hit. The closest hit is defined
//! independently of the visiting order: among the primitives hit within the ray's range, the
//! nearest, and among equally near ones the lowest lane id ([`block::Best`]); every pruning
//! test is conservative, so any traversal order finds the same primitive, parameter and
//! coordinates. The code uses the portable lanes of [`simd`] and is compiled per instruction
//! set ([`isa`]: AVX-512, AVX2, baseline), chosen at run time.
//!
//! **Packets** ([`packet`]). Batches are traced sixteen rays at a time (eight with AVX2), one
//! per SIMD lane: each child box and each leaf primitive is tested against all the packet's
//! rays at once, and where a subtree is entered by few of them each goes on alone with the
//! single-ray loops above. Same hits, bit for bit. On trees of more than
//! [`bvh::INTERLEAVE_BLOCKS`] blocks the column queries (the wavefront's) queue those walks
//! and run eight at a time in turn, each prefetching what it reads next while the others
//! compute (`packet/walkers.rs`).
//!
//! **Queries**: [`Bvh::intersect`](Accel::intersect) and [`Bvh::occluded`](Accel::occluded)
//! for one ray, [`Bvh::intersect_n`] / [`Bvh::occluded_n`] for a batch (in packets, or ray by
//! ray with [`Bvh::set_packets`] or `OPHIS_PACKETS=0`), and [`Bvh::intersect_raw_columns`] /
//! [`Bvh::occluded_columns`] for the wavefront's rays as columns (walks interleaved or not
//! with [`Bvh::set_interleave`] or `OPHIS_WALKERS=0`). [`BruteForce`] tests every primitive
//! and is the oracle in tests.
use crate::math::Ray;
use crate::shape::{Hit, Shape};

mod bins;
pub mod block;
pub mod brute;
pub mod build;
pub mod bvh;
pub mod isa;
pub mod layout;
pub mod order;
pub mod packet;
mod pages;
mod partition;
pub mod simd;
pub mod traverse;
pub mod wide;

pub use brute::BruteForce;
pub use bvh::{Bvh, RawHit, BLOCK_WORDS};
pub use isa::Isa;
pub use packet::RayColumns;

/// A structure answering ray queries against a shape list.
pub trait Accel {
    /// The closest hit with parameter in (0, ray.t_max), if any.
    fn intersect(&self, shapes: &[Shape], ray: &Ray) -> Option<Hit>;
    /// Whether any primitive is hit with parameter in (0, ray.t_max).
    fn occluded(&self, shapes: &[Shape], ray: &Ray) -> bool;
}

#[cfg(test)]
mod tests;
