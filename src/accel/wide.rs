//! The 8-wide node: the bounds of up to eight children, tested against one ray at once.
//!
//! Bounds are stored as structure-of-arrays (`lo[axis][lane]`, `hi[axis][lane]`), so the slab
//! test is six 8-lane subtractions and multiplications and a handful of min/max (one AVX2
//! instruction each). Children are referenced by a [`u32`]: an interior node's index, a leaf
//! (a run of [`super::block::Block`]s, see [`leaf_ref`]), or [`EMPTY_CHILD`]. Wald, Benthin &
//! Boulos, "Getting Rid of Packets", 2008, describe this n-ary layout for single-ray SIMD
//! traversal.
use super::simd::Vec8;
use crate::math::Vec3;

/// Child reference of an unused lane.
pub const EMPTY_CHILD: u32 = u32::MAX;
/// Flag of a leaf reference.
pub const LEAF: u32 = 1 << 31;
/// Bits 27..30 of a leaf reference hold its block count minus one.
const BLOCKS_SHIFT: u32 = 27;
/// Most blocks in one leaf.
pub const MAX_LEAF_BLOCKS: usize = 16;
/// Most blocks a leaf reference can address.
pub const MAX_BLOCKS: usize = 1 << BLOCKS_SHIFT;

/// The reference of a leaf holding blocks `first .. first + count`.
pub fn leaf_ref(first: usize, count: usize) -> u32 {
    assert!((1..=MAX_LEAF_BLOCKS).contains(&count) && first < MAX_BLOCKS);
    LEAF | ((count as u32 - 1) << BLOCKS_SHIFT) | first as u32
}

/// The block range of a leaf reference.
#[inline(always)]
pub fn leaf_range(r: u32) -> (usize, usize) {
    let first = (r & ((1 << BLOCKS_SHIFT) - 1)) as usize;
    let count = (((r >> BLOCKS_SHIFT) & 0xf) + 1) as usize;
    (first, count)
}

/// Eight children; see the module header.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct Node8 {
    lo: [[f32; 8]; 3],
    hi: [[f32; 8]; 3],
    pub child: [u32; 8],
}

const _: () = assert!(std::mem::size_of::<Node8>() == 224);

impl Node8 {
    /// A node with no children.
    pub fn empty() -> Node8 {
        Node8 {
            lo: [[f32::INFINITY; 8]; 3],
            hi: [[f32::INFINITY; 8]; 3],
            child: [EMPTY_CHILD; 8],
        }
    }

    /// Sets lane `lane` to a child with bounds `lo ..= hi`.
    pub fn set(&mut self, lane: usize, lo: Vec3, hi: Vec3, child: u32) {
        for a in 0..3 {
            self.lo[a][lane] = lo[a];
            self.hi[a][lane] = hi[a];
        }
        self.child[lane] = child;
    }

    /// Bounds of lane `lane`.
    pub fn bounds(&self, lane: usize) -> (Vec3, Vec3) {
        let v = |b: &[[f32; 8]; 3]| Vec3::new(b[0][lane], b[1][lane], b[2][lane]);
        (v(&self.lo), v(&self.hi))
    }

    /// Bounds of lane `lane` as arrays (low corner, high corner).
    #[inline(always)]
    pub fn corners(&self, lane: usize) -> ([f32; 3], [f32; 3]) {
        (
            [self.lo[0][lane], self.lo[1][lane], self.lo[2][lane]],
            [self.hi[0][lane], self.hi[1][lane], self.hi[2][lane]],
        )
    }

    /// Entry distances of the eight boxes and the bit mask of the children the ray overlaps in
    /// [0, t_max]. `o` and `inv_d` are the ray origin and reciprocal direction, splatted.
    #[inline(always)]
    pub fn hit<V: Vec8>(&self, o: &[V; 3], inv_d: &[V; 3], t_max: f32) -> (V, u32) {
        let mut near = V::splat(0.0);
        let mut far = V::splat(t_max);
        for a in 0..3 {
            let t0 = V::load(&self.lo[a]).sub(o[a]).mul(inv_d[a]);
            let t1 = V::load(&self.hi[a]).sub(o[a]).mul(inv_d[a]);
            // `x.max(near)` keeps `near` when x is NaN (0·∞ for an origin on a slab plane of a
            // direction parallel to it), and likewise for `far`: the test stays conservative.
            near = t0.min(t1).max(near);
            far = t0.max(t1).min(far);
        }
        // Widen the exit a little so rounding never drops a box a primitive inside is hit in.
        let far = far.mul(V::splat(1.0 + 3.0 * f32::EPSILON));
        (near, near.le_bits(far) & V::used_bits(&self.child))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::simd::Pair8;

    #[test]
    fn leaf_refs_round_trip_and_empty_lanes_are_never_hit() {
        for (first, count) in [(0, 1), (12345, 16), (MAX_BLOCKS - 1, 3)] {
            let r = leaf_ref(first, count);
            assert!(r & LEAF != 0 && r != EMPTY_CHILD);
            assert_eq!(leaf_range(r), (first, count));
        }
        let mut n = Node8::empty();
        n.set(2, Vec3::splat(-1.0), Vec3::splat(1.0), 7);
        assert_eq!(n.bounds(2), (Vec3::splat(-1.0), Vec3::splat(1.0)));
        // Every direction sign pattern, including zero components and an infinite extent.
        for d in [
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(-0.0, 1.0, 0.0),
        ] {
            let inv = d.recip();
            let s = Pair8::splat;
            let o = [s(-5.0 * d.x), s(-5.0 * d.y), s(-5.0 * d.z)];
            let inv = [s(inv.x), s(inv.y), s(inv.z)];
            let (near, mask) = n.hit(&o, &inv, f32::INFINITY);
            assert_eq!(mask, 1 << 2, "{d}");
            let near = near.to_array()[2];
            assert!((near - 4.0).abs() < 1e-5, "{d}: {near}");
            assert_eq!(n.hit(&o, &inv, 3.9).1, 0, "{d}");
        }
    }
}
