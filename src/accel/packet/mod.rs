//! Packet traversal: a batch of rays (sixteen with AVX-512, eight with AVX2, one per SIMD
//! lane) walks the 8-wide tree together, switching to single-ray traversal where few of them
//! remain.
//!
//! # How the data flows
//!
//! [`traverse`] takes one ray at a time and tests it against a node's eight boxes, or a leaf
//! block's four triangles, at once; each step waits on the last, and its branches depend on the
//! ray. Here the lanes hold rays instead: each child of a node is tested against all the
//! packet's rays at once, and each primitive of a leaf likewise, so one load of a node and one
//! decision (does any ray still need this child?) stand for all of them. A stack entry is a
//! child with the bit mask of the rays that entered it and their entry distances; popped, it
//! keeps only the rays whose closest hit so far is not nearer than their entry. Where a node
//! keeps [`SWITCH_NODE`] rays or fewer, or a leaf [`SWITCH_LEAF`], the packet is no longer
//! worth its width: each of those rays walks that subtree alone ([`traverse`]'s own loop,
//! started there with the shear and reciprocal direction already computed here). Benthin,
//! Wald, Woop, Ernst and Mark, "Combining Single and Packet-Ray Tracing for Arbitrary Ray
//! Distributions on the Intel MIC Architecture", IEEE TVCG 18(9), 2012, describe this switch.
//! Analytic primitives are decided ray by ray by their own exact test, after (for spheres) the
//! conservative f32 pre-test computed in lanes.
//!
//! The wavefront hands its batches over in the pool's order; packets are formed from
//! consecutive rays. (Sorting a batch by direction octant and origin cell first was measured
//! and gained nothing on the Cornell box or the 1M-triangle mesh; nor did sorting it by path
//! depth and pixel, which puts a pixel's samples at the same depth side by side as Mitsuba's
//! packets have them; eight-ray packets on AVX-512 were 8–17 % slower than sixteen.)
//!
//! On large trees the column queries do not walk the rays that go on alone at once: they
//! queue them and interleave their walks (`walkers.rs`). The packet then goes on with those
//! rays' closest hits not yet known, which costs it some pruning; taking such rays out of the
//! packet for good (each of their later subtrees queued too) was measured and lost more.
//!
//! # Same answers
//!
//! Every lane computes the watertight test of [`super::block`] with the same operations in the
//! same order: the corners are splatted and each lane's axis permutation applied by selects,
//! which move bits and round nothing; the shear is [`ShearedRay::new`]'s, in lanes. The box
//! tests are those of [`super::wide::Node8::hit`] with the packet's rays in the lanes. The
//! closest hit is the first in (parameter, id) order ([`super::block::Best`]) and every
//! pruning test is conservative, so the packet finds what the single-ray traversal finds, bit
//! for bit, whatever order it visits the tree in (`tests.rs` compares the two on every
//! instruction set).
//!
//! Everything here is `#[inline(always)]`, compiled per instruction set by [`super::isa`]
//! (no closures: a closure is compiled without the caller's instruction set).

mod any;
mod closest;
mod lanes;
mod walkers;

pub use any::{any, any_batch, any_columns};
pub use closest::{closest, closest_raw, closest_raw_batch, closest_raw_columns};
pub use lanes::RayColumns;

/// A node with at most this many rays left continues ray by ray, where those rays' walks run
/// at once (measured: 2 to 5 level, 1 slower on the 1M-triangle mesh).
pub const SWITCH_NODE: u32 = 3;
/// Where the walks are queued and interleaved (`walkers.rs`), a node with at most this many
/// eighths of the packet's lanes left continues ray by ray: ten rays of sixteen with AVX-512,
/// five of eight with AVX2. Measured on the 1M-triangle mesh with AVX-512 (`bench_accel`, rays
/// per second against three rays): camera rays 1.15×, bounce 1.05×, shadow 1.09×; a packet
/// of sixteen rays that all go alone from the root was 2× slower.
pub const SWITCH_NODE_QUEUED_EIGHTHS: u32 = 5;
/// A leaf with at most this many rays left is tested ray by ray (measured: 1 about 3 % faster
/// than 3 on the Cornell box, level on the mesh).
pub const SWITCH_LEAF: u32 = 1;

/// Whether the rays `active` of a packet of `lanes` go on alone from `node` (a node's or a
/// leaf's reference); `queued`: whether their walks are queued.
#[inline(always)]
fn alone(node: u32, active: u32, lanes: usize, queued: bool) -> bool {
    let most = if node & super::wide::LEAF != 0 {
        SWITCH_LEAF
    } else if queued {
        lanes as u32 * SWITCH_NODE_QUEUED_EIGHTHS / 8
    } else {
        SWITCH_NODE
    };
    active.count_ones() <= most
}

/// Most lanes of a packet.
const MAX_LANES: usize = 16;

#[cfg(test)]
mod tests;
