//! Layout: the built tree turned into the arrays traversal reads.
//!
//! Interior nodes keep their build order (a node before its subtrees). Leaves are numbered in
//! depth-first lane order, which is the order of their ref ranges, and each becomes a run of
//! [`Block`]s holding copies of its triangles' corners, so a leaf test reads contiguous memory
//! instead of chasing mesh indices. Blocks are filled in parallel.
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
pub fn layout(tree: &Tree, ids: &[u32], shapes: &[Shape], first: &[u32]) -> Layout {
    let mut walk = Walk {
        tree,
        nodes: vec![Node8::empty(); tree.nodes.len()],
        leaves: Vec::new(),
        blocks: 0,
        depth: 0,
    };
    let root = walk.slot_ref(tree.root, 1);
    let blocks = walk
        .leaves
        .par_iter()
        .flat_map_iter(|&(start, len)| {
            let lanes = &ids[start as usize..(start + len) as usize];
            lanes.chunks(4).map(|c| {
                let slot = |l: usize| {
                    let id = c.get(l).copied().unwrap_or(EMPTY);
                    (id, corners(shapes, first, id))
                };
                Block::new([slot(0), slot(1), slot(2), slot(3)])
            })
        })
        .collect::<Vec<Block>>();
    debug_assert_eq!(blocks.len(), walk.blocks);
    Layout {
        nodes: walk.nodes,
        blocks,
        root,
        depth: walk.depth,
    }
}

/// The depth-first walk that converts nodes and numbers leaves.
struct Walk<'a> {
    tree: &'a Tree,
    nodes: Vec<Node8>,
    /// Ref ranges (start, len) of the leaves in block order.
    leaves: Vec<(u32, u32)>,
    /// Blocks used so far.
    blocks: usize,
    depth: usize,
}

impl Walk<'_> {
    /// The child reference for `slot`, converting its subtree; `level` is the slot's level.
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
                let b = self.tree.nodes[i as usize];
                let mut node = Node8::empty();
                for lane in 0..8 {
                    if b.slot[lane] != Slot::Empty {
                        let child = self.slot_ref(b.slot[lane], level + 1);
                        node.set(lane, b.lo[lane], b.hi[lane], child);
                    }
                }
                self.nodes[i as usize] = node;
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
