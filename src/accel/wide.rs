//! A 4-wide BVH, collapsed from the binary SAH tree, traversed with SIMD box tests.
//!
//! Each node holds the bounds of up to four children in structure-of-arrays form, so one ray is
//! tested against four boxes with 4-lane SIMD (glam's `Vec4`). The collapse repeatedly opens
//! the child with the largest surface area until four children are gathered (Wald, Benthin &
//! Boulos, "Getting Rid of Packets", 2008, describe the same n-ary layout). Leaves keep the
//! binary tree's primitive ranges, so the primitive order and the leaf tests are unchanged.

use crate::math::{Bounds3, Vec3};
use glam::Vec4;

/// Lane value marking an empty child.
const EMPTY: u32 = u32::MAX;

/// Four children: their bounds (SoA), and for each either an interior node index
/// (`count` = 0) or a primitive range `child .. child + count`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Node4 {
    min_x: [f32; 4],
    min_y: [f32; 4],
    min_z: [f32; 4],
    max_x: [f32; 4],
    max_y: [f32; 4],
    max_z: [f32; 4],
    pub child: [u32; 4],
    pub count: [u32; 4],
    /// Bit i set when lane i holds a child.
    pub valid: u32,
}

impl Node4 {
    fn empty() -> Node4 {
        Node4 {
            min_x: [f32::INFINITY; 4],
            min_y: [f32::INFINITY; 4],
            min_z: [f32::INFINITY; 4],
            max_x: [f32::NEG_INFINITY; 4],
            max_y: [f32::NEG_INFINITY; 4],
            max_z: [f32::NEG_INFINITY; 4],
            child: [EMPTY; 4],
            count: [0; 4],
            valid: 0,
        }
    }

    fn set(&mut self, lane: usize, b: &Bounds3, child: u32, count: u32) {
        self.min_x[lane] = b.min.x;
        self.min_y[lane] = b.min.y;
        self.min_z[lane] = b.min.z;
        self.max_x[lane] = b.max.x;
        self.max_y[lane] = b.max.y;
        self.max_z[lane] = b.max.z;
        self.child[lane] = child;
        self.count[lane] = count;
        self.valid |= 1 << lane;
    }

    /// Entry distances of the four boxes and the mask of those the ray overlaps in (0, t_max).
    #[inline(always)]
    pub fn hit(&self, o: &[Vec4; 3], inv_d: &[Vec4; 3], t_max: f32) -> (Vec4, u32) {
        let tx0 = (Vec4::from_array(self.min_x) - o[0]) * inv_d[0];
        let tx1 = (Vec4::from_array(self.max_x) - o[0]) * inv_d[0];
        let ty0 = (Vec4::from_array(self.min_y) - o[1]) * inv_d[1];
        let ty1 = (Vec4::from_array(self.max_y) - o[1]) * inv_d[1];
        let tz0 = (Vec4::from_array(self.min_z) - o[2]) * inv_d[2];
        let tz1 = (Vec4::from_array(self.max_z) - o[2]) * inv_d[2];
        let near = tx0
            .min(tx1)
            .max(ty0.min(ty1))
            .max(tz0.min(tz1))
            .max(Vec4::ZERO);
        // Widen the exit a little so rounding never drops a box a primitive inside is hit in.
        let far = tx0
            .max(tx1)
            .min(ty0.max(ty1))
            .min(tz0.max(tz1))
            .min(Vec4::splat(t_max))
            * (1.0 + 3.0 * f32::EPSILON);
        (near, near.cmple(far).bitmask())
    }
}

/// A binary node as the collapse sees it.
pub struct Binary {
    pub bounds: Bounds3,
    /// First child (children adjacent) or first primitive.
    pub offset: u32,
    /// Primitive count; 0 for an interior node.
    pub count: u32,
}

/// Collapses a binary tree (root at index 0, children of an interior node at `offset` and
/// `offset + 1`) into 4-wide nodes; the root is node 0.
pub fn collapse(binary: &[Binary]) -> Vec<Node4> {
    let mut out = Vec::with_capacity(binary.len() / 2 + 1);
    if binary.is_empty() {
        return out;
    }
    out.push(Node4::empty());
    if binary[0].count > 0 {
        // A single leaf: one lane.
        out[0].set(0, &binary[0].bounds, binary[0].offset, binary[0].count);
        return out;
    }
    fill(binary, 0, 0, &mut out);
    out
}

fn area(b: &Bounds3) -> f32 {
    b.surface_area()
}

fn fill(binary: &[Binary], node2: usize, at: usize, out: &mut Vec<Node4>) {
    // Gather up to four children by opening the largest interior child.
    let first = binary[node2].offset as usize;
    let mut kids: Vec<usize> = vec![first, first + 1];
    while kids.len() < 4 {
        let open = kids
            .iter()
            .enumerate()
            .filter(|(_, &k)| binary[k].count == 0)
            .max_by(|a, b| area(&binary[*a.1].bounds).total_cmp(&area(&binary[*b.1].bounds)))
            .map(|(i, _)| i);
        let Some(i) = open else { break };
        let k = kids.swap_remove(i);
        let c = binary[k].offset as usize;
        kids.push(c);
        kids.push(c + 1);
    }
    for (lane, &k) in kids.iter().enumerate() {
        let b = &binary[k];
        if b.count > 0 {
            out[at].set(lane, &b.bounds, b.offset, b.count);
        } else {
            let idx = out.len();
            out.push(Node4::empty());
            out[at].set(lane, &b.bounds, idx as u32, 0);
            fill(binary, k, idx, out);
        }
    }
}

/// Splats a vector's components into three 4-lane vectors.
#[inline(always)]
pub fn splat3(v: Vec3) -> [Vec4; 3] {
    [Vec4::splat(v.x), Vec4::splat(v.y), Vec4::splat(v.z)]
}
