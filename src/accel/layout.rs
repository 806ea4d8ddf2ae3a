//! Layout: the built tree turned into the arrays traversal reads.
//!
//! Interior nodes keep their build order (a node before its subtrees) and their memory: only
//! their leaf lanes are rewritten, from ref ranges to block references. Leaves are numbered in
//! depth-first lane order, which is the order of their ref ranges, and each becomes a run of
//! [`Block`]s holding copies of its triangles' corners, so a leaf test reads contiguous memory
//! instead of chasing mesh indices. The block array is allocated once at its final size and
//! filled in parallel, block by block, in place (first written by the threads that fill it).
use super::block::{Block, ANALYTIC, EMPTY};
use super::build::{Slot, Tree};
use super::wide::{leaf_ref, Node8, EMPTY_CHILD, MAX_LEAF_BLOCKS};
use crate::math::Vec3;
use crate::shape::Shape;
use rayon::prelude::*;

/// The traversal arrays.
pub struct Layout {
    pub nodes: Vec<Node8>,
    pub blocks: Vec<Block>,
    /// Child reference of the root ([`EMPTY_CHILD`] for an empty scene).
    pub root: u32,
    /// Levels of the 8-wide tree, counting the leaf level (0 when empty).
    pub depth: usize,
}

/// Lays out `tree`; `ids` are the lane ids of the reordered refs, `first[s]` the global id of
/// shape `s`'s first triangle.
pub fn layout(tree: Tree, ids: &[u32], shapes: &[Shape], first: &[u32]) -> Layout {
    let mut walk = Walk {
        tree,
        leaves: Vec::new(),
        blocks: 0,
        depth: 0,
    };
    let root = walk.slot_ref(walk.tree.root, 1);
    // Each block's refs: where its lane ids start and how many it has.
    let mut spans: Vec<(u32, u8)> = Vec::with_capacity(walk.blocks);
    for &(start, len) in &walk.leaves {
        for at in (start..start + len).step_by(4) {
            spans.push((at, (start + len - at).min(4) as u8));
        }
    }
    // On huge pages where the system gives them (see `pages.rs`): the traversal reads the blocks
    // at scattered places. Filled in parallel, in place: the array's pages are cleared by the
    // kernel as they are first written (42 MB for the 1M-triangle mesh), on all threads.
    let mut blocks = super::pages::with_capacity(spans.len());
    spans
        .par_iter()
        .map(|&(at, n)| {
            let lanes = &ids[at as usize..at as usize + n as usize];
            let slot = |l: usize| {
                let id = lanes.get(l).copied().unwrap_or(EMPTY);
                (id, corners(shapes, first, id))
            };
            Block::new([slot(0), slot(1), slot(2), slot(3)])
        })
        .collect_into_vec(&mut blocks);
    Layout {
        nodes: walk.tree.nodes.node,
        blocks,
        root,
        depth: walk.depth,
    }
}

/// The depth-first walk that numbers leaves and rewrites their lanes.
struct Walk {
    tree: Tree,
    /// Ref ranges (start, len) of the leaves in block order.
    leaves: Vec<(u32, u32)>,
    /// Blocks used so far.
    blocks: usize,
    depth: usize,
}

impl Walk {
    /// The child reference for `slot`, rewriting its subtree; `level` is the slot's level.
    fn slot_ref(&mut self, slot: Slot, level: usize) -> u32 {
        if slot != Slot::Empty {
            self.depth = self.depth.max(level);
        }
        match slot {
            Slot::Empty => EMPTY_CHILD,
            Slot::Leaf { start, len } => {
                let n = (len as usize).div_ceil(4);
                assert!(n <= MAX_LEAF_BLOCKS, "leaf of {len} primitives");
                let r = leaf_ref(self.blocks, n);
                self.blocks += n;
                self.leaves.push((start, len));
                r
            }
            Slot::Inner(i) => {
                for lane in 0..8 {
                    let s = self.tree.nodes.slot(i as usize, lane);
                    if s != Slot::Empty {
                        let child = self.slot_ref(s, level + 1);
                        self.tree.nodes.node[i as usize].child[lane] = child;
                    }
                }
                i
            }
        }
    }
}

/// World-space corners of the triangle with lane id `id` (zeros for other lanes).
fn corners(shapes: &[Shape], first: &[u32], id: u32) -> [Vec3; 3] {
    if id == EMPTY || id & ANALYTIC != 0 {
        return [Vec3::ZERO; 3];
    }
    let s = first[..shapes.len()].partition_point(|&f| f <= id) - 1;
    match &shapes[s] {
        Shape::Mesh(m) => m.vertices(id - first[s]),
        _ => unreachable!("triangle id {id} maps to an analytic shape"),
    }
}
