//! Single-ray traversal of the 8-wide tree: closest hit and any hit.
//!
//! Closest hit: the ray meets a node's eight boxes at once ([`Node8::hit`]); of the children it
//! enters, the nearest is visited next and the others are pushed far-to-near, so the stack pops
//! them nearest first (all eight sorted and stored at once by [`Vec8::far_first`]); popped
//! entries that start beyond the closest hit so far are skipped. The closest hit is the first
//! in (parameter, id) order ([`Best`]), whatever the visiting order. A node with one child hit
//! pushes nothing. Any hit (shadow rays) skips the sorting and stops at
//! the first primitive hit. The stack is fixed-size and left uninitialised (no allocation and
//! no zeroing per ray).
//!
//! Everything here is `#[inline(always)]`: [`super::isa`] compiles these functions once per
//! instruction set inside `#[target_feature]` wrappers.
use super::block::{widen, Best, Block, RayLanes};
use super::build::MEDIAN_DEPTH;
use super::simd::{prefetch, Vec8};
use super::wide::{leaf_range, Node8, EMPTY_CHILD, LEAF};
use crate::math::{Ray, Vec2, Vec3};
use crate::shape::mesh::ShearedRay;
use crate::shape::Shape;
use std::mem::MaybeUninit;

/// Stack entries: a node visit pushes at most seven, and the tree is at most
/// `MEDIAN_DEPTH + 33` levels deep (median splits halve a range of < 2³² refs); a visit writes
/// eight slots above the top ([`Vec8::far_first`]), one more than it keeps.
pub const STACK: usize = 7 * (MEDIAN_DEPTH + 34) + 1;

/// The arrays a traversal reads.
#[derive(Clone, Copy)]
pub struct View<'a> {
    pub nodes: &'a [Node8],
    pub blocks: &'a [Block],
    pub root: u32,
    /// Global id of each shape's first triangle and the total at the end (see
    /// [`super::Bvh`]), to name the shape and triangle of a hit.
    pub first: &'a [u32],
    /// Whether the column queries interleave their single-ray walks
    /// ([`super::packet::closest_raw_batch`]).
    pub interleave: bool,
}

impl View<'_> {
    /// Prefetches the memory of child reference `c`: a node, or all of a leaf's blocks.
    #[inline(always)]
    pub(crate) fn prefetch(&self, c: u32) {
        if c & LEAF != 0 {
            let (first, n) = leaf_range(c);
            prefetch(self.blocks.as_ptr().wrapping_add(first), n);
        } else {
            prefetch(self.nodes.as_ptr().wrapping_add(c as usize), 1);
        }
    }
}

/// Prefetches the children `mask` of `child`.
#[inline(always)]
fn prefetch_hit(v: View, child: &[u32; 8], mut mask: u32) {
    while mask != 0 {
        v.prefetch(child[mask.trailing_zeros() as usize]);
        mask &= mask - 1;
    }
}

/// The per-ray constants of the box tests.
pub(crate) struct BoxRay<V> {
    pub(crate) o: [V; 3],
    pub(crate) inv_d: [V; 3],
}

impl<V: Vec8> BoxRay<V> {
    /// For `ray` with reciprocal direction `inv`.
    #[inline(always)]
    pub(crate) fn new(ray: &Ray, inv: Vec3) -> BoxRay<V> {
        BoxRay {
            o: [V::splat(ray.o.x), V::splat(ray.o.y), V::splat(ray.o.z)],
            inv_d: [V::splat(inv.x), V::splat(inv.y), V::splat(inv.z)],
        }
    }
}

/// Inserts `key` into `keys[..n]`, kept in descending order (entry distance in the high bits:
/// the farthest child first, the nearest last).
#[inline(always)]
pub(super) fn insert_far_first(keys: &mut [u64; 8], n: usize, key: u64) {
    let mut j = n;
    while j > 0 && keys[j - 1] < key {
        keys[j] = keys[j - 1];
        j -= 1;
    }
    keys[j] = key;
}

/// The closest hit found by a traversal.
#[derive(Clone, Copy, Debug)]
pub struct Found {
    /// Lane id (see [`super::block`]).
    pub id: u32,
    pub t: f32,
    /// Hit coordinates (barycentrics b1, b2 for triangles).
    pub uv: Vec2,
    /// Where the primitive's slot is: block index and lane.
    pub block: u32,
    pub lane: u32,
}

/// The closest hit.
#[inline(always)]
pub fn closest<V: Vec8>(v: View, shapes: &[Shape], ray: &Ray) -> Option<Found> {
    if v.root == EMPTY_CHILD {
        return None;
    }
    closest_below::<V>(v, shapes, ray, v.root, &mut Best::new(ray.t_max))
}

#[inline(always)]
fn closest_below<V: Vec8>(
    v: View,
    shapes: &[Shape],
    ray: &Ray,
    start: u32,
    closest: &mut Best,
) -> Option<Found> {
    let sr = ShearedRay::new(ray.d)?;
    closest_from::<V>(v, shapes, ray, &sr, ray.d.recip(), start, closest)
}

/// [`closest_below`] with the ray's shear `sr` and reciprocal direction `inv` given.
#[inline(always)]
pub(super) fn closest_from<V: Vec8>(
    v: View,
    shapes: &[Shape],
    ray: &Ray,
    sr: &ShearedRay,
    inv: Vec3,
    start: u32,
    closest: &mut Best,
) -> Option<Found> {
    let lanes = RayLanes::new(ray, sr);
    let br = BoxRay::<V>::new(ray, inv);
    // `r` carries the closest hit so far as its extent, for the box tests.
    let mut r = *ray;
    r.t_max = closest.t;
    let mut best = None;
    let mut stack = [const { MaybeUninit::<u64>::uninit() }; STACK];
    let mut sp = 0usize;
    let mut cur = start;
    loop {
        if cur & LEAF != 0 {
            let (first, n) = leaf_range(cur);
            for (k, b) in v.blocks[first..first + n].iter().enumerate() {
                if let Some((lane, uv)) = b.closest(&lanes, ray, closest, shapes) {
                    best = Some(Found {
                        id: closest.id,
                        t: closest.t,
                        uv,
                        block: (first + k) as u32,
                        lane: lane as u32,
                    });
                    r.t_max = closest.t;
                }
            }
        } else {
            let node = &v.nodes[cur as usize];
            let (near, mask) = node.hit(&br.o, &br.inv_d, r.t_max);
            if mask != 0 {
                // The children hit by entry distance, far first, so that the stack pops the
                // nearest first. Their memory is requested now, so that the loads overlap.
                prefetch_hit(v, &node.child, mask);
                // SAFETY: `STACK` leaves room for eight entries above any `sp` reached.
                let out =
                    unsafe { &mut *(stack.as_mut_ptr().add(sp) as *mut [MaybeUninit<u64>; 8]) };
                cur = near.far_first(&node.child, mask, out) as u32;
                sp += mask.count_ones() as usize - 1;
                continue;
            }
        }
        loop {
            if sp == 0 {
                return best;
            }
            sp -= 1;
            // SAFETY: slots below the old `sp` were all written by a push.
            let k = unsafe { stack[sp].assume_init() };
            let (c, t) = (k as u32, f32::from_bits((k >> 32) as u32));
            // Widened: a node whose entry rounds just past an equally close hit may still
            // hold a tie (see `Best`).
            if t <= widen(r.t_max) {
                cur = c;
                break;
            }
        }
    }
}

/// Whether anything is hit in (0, ray.t_max).
#[inline(always)]
pub fn any<V: Vec8>(v: View, shapes: &[Shape], ray: &Ray) -> bool {
    if v.root == EMPTY_CHILD {
        return false;
    }
    any_below::<V>(v, shapes, ray, v.root)
}

#[inline(always)]
fn any_below<V: Vec8>(v: View, shapes: &[Shape], ray: &Ray, start: u32) -> bool {
    let Some(sr) = ShearedRay::new(ray.d) else {
        return false;
    };
    any_from::<V>(v, shapes, ray, &sr, ray.d.recip(), start)
}

/// [`any_below`] with the ray's shear `sr` and reciprocal direction `inv` given.
#[inline(always)]
pub(super) fn any_from<V: Vec8>(
    v: View,
    shapes: &[Shape],
    ray: &Ray,
    sr: &ShearedRay,
    inv: Vec3,
    start: u32,
) -> bool {
    let lanes = RayLanes::new(ray, sr);
    let br = BoxRay::<V>::new(ray, inv);
    let mut stack = [const { MaybeUninit::<u32>::uninit() }; STACK];
    let mut sp = 0usize;
    let mut cur = start;
    loop {
        if cur & LEAF != 0 {
            let (first, n) = leaf_range(cur);
            for b in &v.blocks[first..first + n] {
                if b.any(&lanes, ray, shapes) {
                    return true;
                }
            }
        } else {
            let node = &v.nodes[cur as usize];
            let (_, mask) = node.hit(&br.o, &br.inv_d, ray.t_max);
            if mask != 0 {
                prefetch_hit(v, &node.child, mask & (mask - 1));
                // SAFETY: `STACK` leaves room for eight entries above any `sp` reached.
                let out =
                    unsafe { &mut *(stack.as_mut_ptr().add(sp) as *mut [MaybeUninit<u32>; 8]) };
                cur = V::first_and_rest(&node.child, mask, out);
                sp += mask.count_ones() as usize - 1;
                continue;
            }
        }
        if sp == 0 {
            return false;
        }
        sp -= 1;
        // SAFETY: slots below the old `sp` were all written by a push.
        cur = unsafe { stack[sp].assume_init() };
    }
}
