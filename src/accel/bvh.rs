//! The BVH: build, lay out, and answer ray queries (single rays and batches).
use super::block::{Block, ANALYTIC};
use super::build;
use super::isa::{self, Isa};
use super::layout::layout;
use super::packet::RayColumns;
use super::traverse::{Found, View, STACK};
use super::wide::Node8;
use super::Accel;
use crate::math::{Bounds3, Ray};
use crate::shape::{Hit, Shape, SurfaceInteraction};

/// Words of one leaf block in [`Bvh::block_words`].
pub const BLOCK_WORDS: usize = 40;
const _: () = assert!(std::mem::size_of::<Block>() == BLOCK_WORDS * 4);

/// Shape tables up to this long are counted through rather than searched (see `Bvh::hit`).
pub(super) const SHORT_TABLE: usize = 64;

/// The [`Hit`] for a traversal's result; `first` is [`Bvh`]'s table of first triangle ids.
#[inline]
pub(super) fn hit(first: &[u32], f: Found) -> Hit {
    let (shape, prim) = if f.id & ANALYTIC != 0 {
        (f.id & !ANALYTIC, 0)
    } else {
        // The shape is the last whose first triangle is at or before the id: the number of
        // later shapes' firsts not beyond it (the table is sorted, and first[0] = 0). A
        // short table is counted whole (vector compares, no branches), a long one
        // searched.
        let starts = &first[1..first.len() - 1];
        let s = if starts.len() <= SHORT_TABLE {
            starts.iter().map(|&x| (x <= f.id) as usize).sum()
        } else {
            starts.partition_point(|&x| x <= f.id)
        };
        (s as u32, f.id - first[s])
    };
    Hit {
        t: f.t,
        shape,
        prim,
        uv: f.uv,
    }
}

/// A closest hit with the leaf slot it was found in (block and lane), where a triangle's
/// corners are stored.
#[derive(Clone, Copy, Debug)]
pub struct RawHit {
    pub hit: Hit,
    pub block: u32,
    pub lane: u32,
}

/// The bounding volume hierarchy; see the [module header](super).
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node8>,
    blocks: Vec<Block>,
    root: u32,
    /// Global id of each shape's first triangle (mesh triangles counted in shape order); one
    /// entry per shape and the total at the end.
    first: Vec<u32>,
    prims: usize,
    depth: usize,
    bounds: Bounds3,
    isa: Isa,
    /// Whether batches are traced in packets ([`super::packet`]) rather than ray by ray.
    packets: bool,
    /// Whether column queries interleave their rays' single-ray walks (see [`View`]).
    interleave: bool,
}

/// Blocks from which a tree's column queries interleave their single-ray walks
/// (`packet/walkers.rs`): 10 MB of blocks, well beyond the L2 cache, where a walk's next node
/// or leaf is rarely in cache. Below it the queueing costs more than it hides (the
/// Cornell box's spheres: 9 % slower).
pub const INTERLEAVE_BLOCKS: usize = 1 << 16;

impl Default for Bvh {
    fn default() -> Bvh {
        Bvh::build(&[])
    }
}

impl Bvh {
    /// Builds the hierarchy over every primitive of `shapes` (on the current rayon pool).
    pub fn build(shapes: &[Shape]) -> Bvh {
        let mut first = Vec::with_capacity(shapes.len() + 1);
        let mut total = 0u64;
        for s in shapes {
            first.push(total as u32);
            if let Shape::Mesh(m) = s {
                total += m.triangle_count() as u64;
            }
        }
        assert!(total < ANALYTIC as u64, "more than 2³¹ triangles");
        first.push(total as u32);
        let mut refs = build::refs(shapes, &first);
        let prims = refs.len();
        let tree = build::build(&mut refs);
        // Only the ids are needed from here on: free the refs before the blocks are allocated.
        let ids = build::ids(&refs);
        drop(refs);
        let (lo, hi) = (tree.lo, tree.hi);
        let l = layout(tree, &ids, shapes, &first);
        drop(ids);
        // The walk bound of the traversal stack (see `traverse::STACK`).
        assert!(
            7 * l.depth < STACK,
            "tree depth {} exceeds the stack",
            l.depth
        );
        let bounds = match prims {
            0 => Bounds3::EMPTY,
            _ => Bounds3 { min: lo, max: hi },
        };
        let interleave = l.blocks.len() >= INTERLEAVE_BLOCKS
            && std::env::var_os("OPHIS_WALKERS").is_none_or(|v| v != "0");
        Bvh {
            nodes: l.nodes,
            blocks: l.blocks,
            root: l.root,
            first,
            prims,
            depth: l.depth,
            bounds,
            isa: Isa::best(),
            // OPHIS_PACKETS=0 traces batches ray by ray, OPHIS_WALKERS=0 never interleaves
            // walks: for side-by-side measurements.
            packets: std::env::var_os("OPHIS_PACKETS").is_none_or(|v| v != "0"),
            interleave,
        }
    }

    /// Number of 8-wide interior nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of 4-slot leaf blocks.
    pub fn block_count(&self) -> usize {
        self.blocks.len()
    }

    /// Levels of the 8-wide tree, counting leaves (1 for a single leaf, 0 when empty).
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Number of primitives referenced.
    pub fn prim_count(&self) -> usize {
        self.prims
    }

    /// Bounds of everything in the tree.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Bytes held by the structure (nodes, blocks and the shape table).
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of_val(&self.nodes[..])
            + std::mem::size_of_val(&self.blocks[..])
            + std::mem::size_of_val(&self.first[..])
            + std::mem::size_of::<Bvh>()
    }

    /// The instruction-set variant queries use.
    pub fn isa(&self) -> Isa {
        self.isa
    }

    /// Makes queries use `isa`; returns false (and changes nothing) when the CPU lacks it.
    pub fn set_isa(&mut self, isa: Isa) -> bool {
        if isa.supported() {
            self.isa = isa;
        }
        self.isa == isa
    }

    /// Makes batch queries trace in packets (`true`, the default) or ray by ray; both give the
    /// same answers.
    pub fn set_packets(&mut self, on: bool) {
        self.packets = on;
    }

    /// Makes the column queries ([`Bvh::intersect_raw_columns`], [`Bvh::occluded_columns`])
    /// interleave their single-ray walks (`true`) or run each at once; by default they do on
    /// trees of [`INTERLEAVE_BLOCKS`] blocks or more. Both give the same answers.
    pub fn set_interleave(&mut self, on: bool) {
        self.interleave = on;
    }

    fn view(&self) -> View<'_> {
        View {
            nodes: &self.nodes,
            blocks: &self.blocks,
            root: self.root,
            first: &self.first,
            interleave: self.interleave,
        }
    }

    /// The [`Hit`] for a traversal's result.
    #[inline]
    fn hit(&self, f: Found) -> Hit {
        hit(&self.first, f)
    }

    /// The closest hit and its surface geometry: the same as [`Accel::intersect`] followed by
    /// [`Shape::interaction`], but a triangle's corners come from the leaf block the hit was
    /// found in (still in cache) instead of the mesh's index and vertex arrays (two cache misses
    /// per hit on a large mesh).
    #[inline]
    pub fn intersect_interaction(
        &self,
        shapes: &[Shape],
        ray: &Ray,
    ) -> Option<(Hit, SurfaceInteraction)> {
        let f = isa::closest(self.isa, self.view(), shapes, ray)?;
        Some((self.hit(f), self.interaction(shapes, f, ray)))
    }

    /// Closest hits of a batch of rays, as the traversal found them (with the leaf slot of a
    /// triangle, see [`RawHit`]); `out[i]` for `rays[i]`.
    pub fn intersect_raw_n(&self, shapes: &[Shape], rays: &[Ray], out: &mut [Option<RawHit>]) {
        if self.packets {
            assert_eq!(rays.len(), out.len());
            isa::closest_packets_raw(self.isa, self.view(), shapes, rays, out);
            return;
        }
        self.closest_map(shapes, rays, out, |f, _| RawHit {
            hit: self.hit(f),
            block: f.block,
            lane: f.lane,
        });
    }

    /// [`Bvh::intersect_raw_n`] for rays given as columns: `out[i]` for ray `i` (`out` is
    /// `rays.n` long). Packets load the columns directly, without a [`Ray`] per ray.
    pub fn intersect_raw_columns(
        &self,
        shapes: &[Shape],
        rays: &RayColumns,
        out: &mut [Option<RawHit>],
    ) {
        assert_eq!(rays.n, out.len());
        rays.check();
        if self.packets {
            isa::closest_columns_raw(self.isa, self.view(), shapes, rays, out);
        } else {
            let all: Vec<Ray> = (0..rays.n).map(|i| rays.ray(i)).collect();
            self.intersect_raw_n(shapes, &all, out);
        }
    }

    /// [`Bvh::occluded_n`] for rays given as columns: `blocked[i]` for ray `i`.
    pub fn occluded_columns(&self, shapes: &[Shape], rays: &RayColumns, blocked: &mut [bool]) {
        assert_eq!(rays.n, blocked.len());
        rays.check();
        if self.packets {
            isa::any_columns(self.isa, self.view(), shapes, rays, blocked);
        } else {
            let all: Vec<Ray> = (0..rays.n).map(|i| rays.ray(i)).collect();
            self.occluded_n(shapes, &all, blocked);
        }
    }

    /// The surface geometry of a hit found by [`Bvh::intersect_raw_n`] for `ray`.
    #[inline]
    pub fn raw_interaction(&self, shapes: &[Shape], h: &RawHit, ray: &Ray) -> SurfaceInteraction {
        match &shapes[h.hit.shape as usize] {
            Shape::Mesh(m) => {
                let corners = self.blocks[h.block as usize].corners(h.lane as usize);
                m.interaction_at(&h.hit, corners)
            }
            s => s.interaction(&h.hit, ray),
        }
    }

    /// The leaf blocks as one flat array of words: triangle `lane`'s corner `k`, axis `a` of
    /// block `b` is at `b · BLOCK_WORDS + k · 12 + a · 4 + lane` (see [`super::block`]).
    pub fn block_words(&self) -> &[f32] {
        // SAFETY: `Block` is `repr(C)` of f32 and u32 words only (no padding: 160 bytes, 40
        // words), and every bit pattern is a valid f32; the slice covers exactly the blocks.
        unsafe {
            std::slice::from_raw_parts(
                self.blocks.as_ptr() as *const f32,
                self.blocks.len() * BLOCK_WORDS,
            )
        }
    }

    /// [`Bvh::intersect_interaction`] for a batch of rays: `out[i]` for `rays[i]` (the two
    /// slices must have the same length), with one instruction-set dispatch per 64 rays.
    pub fn intersect_interaction_n(
        &self,
        shapes: &[Shape],
        rays: &[Ray],
        out: &mut [Option<SurfaceInteraction>],
    ) {
        self.closest_map(shapes, rays, out, |f, ray| self.interaction(shapes, f, ray));
    }

    /// The surface geometry of a traversal's result.
    #[inline]
    fn interaction(&self, shapes: &[Shape], f: Found, ray: &Ray) -> SurfaceInteraction {
        let h = RawHit {
            hit: self.hit(f),
            block: f.block,
            lane: f.lane,
        };
        self.raw_interaction(shapes, &h, ray)
    }

    /// Traces `rays` in chunks of 64 (one instruction-set dispatch each) and sets `out[i]` to
    /// `f` of `rays[i]`'s closest hit and the ray, or `None`.
    #[inline]
    fn closest_map<T>(
        &self,
        shapes: &[Shape],
        rays: &[Ray],
        out: &mut [Option<T>],
        f: impl Fn(Found, &Ray) -> T,
    ) {
        assert_eq!(rays.len(), out.len());
        let mut raw = [None; 64];
        for (rs, os) in rays.chunks(64).zip(out.chunks_mut(64)) {
            let raw = &mut raw[..rs.len()];
            if self.packets {
                isa::closest_packets(self.isa, self.view(), shapes, rs, raw);
            } else {
                isa::closest_n(self.isa, self.view(), shapes, rs, raw);
            }
            for ((o, r), ray) in os.iter_mut().zip(raw.iter()).zip(rs) {
                *o = r.map(|r| f(r, ray));
            }
        }
    }

    /// Closest hits of a batch of rays: `hits[i]` for `rays[i]` (the two slices must have the
    /// same length). The same answers as [`Accel::intersect`] ray by ray, with one instruction-set
    /// dispatch for the whole batch; an integrator that carries several paths can hand over
    /// its rays this way.
    pub fn intersect_n(&self, shapes: &[Shape], rays: &[Ray], hits: &mut [Option<Hit>]) {
        self.closest_map(shapes, rays, hits, |f, _| self.hit(f));
    }

    /// Occlusion of a batch of rays: `blocked[i]` for `rays[i]`; see [`Bvh::intersect_n`].
    pub fn occluded_n(&self, shapes: &[Shape], rays: &[Ray], blocked: &mut [bool]) {
        assert_eq!(rays.len(), blocked.len());
        if self.packets {
            isa::any_packets(self.isa, self.view(), shapes, rays, blocked);
        } else {
            isa::any_n(self.isa, self.view(), shapes, rays, blocked);
        }
    }
}

impl Accel for Bvh {
    #[inline]
    fn intersect(&self, shapes: &[Shape], ray: &Ray) -> Option<Hit> {
        isa::closest(self.isa, self.view(), shapes, ray).map(|r| self.hit(r))
    }

    #[inline]
    fn occluded(&self, shapes: &[Shape], ray: &Ray) -> bool {
        isa::any(self.isa, self.view(), shapes, ray)
    }
}

#[cfg(test)]
mod gather_tests {
    use super::*;
    use crate::accel::wide::{leaf_range, EMPTY_CHILD, LEAF};
    use crate::math::{Transform, Vec3};
    use crate::shape::TriangleMesh;

    /// The boxes of every leaf below `c` holding a primitive with id below `walls`.
    fn wall_leaves(b: &Bvh, c: u32, walls: u32, out: &mut Vec<(Vec3, Vec3)>, lo: Vec3, hi: Vec3) {
        if c & LEAF != 0 {
            let (f, n) = leaf_range(c);
            if b.blocks[f..f + n]
                .iter()
                .any(|bl| bl.ids().iter().any(|&id| id < walls))
            {
                out.push((lo, hi));
            }
            return;
        }
        let node = &b.nodes[c as usize];
        for lane in 0..8 {
            if node.child[lane] != EMPTY_CHILD {
                let (lo, hi) = node.bounds(lane);
                wall_leaves(b, node.child[lane], walls, out, lo, hi);
            }
        }
    }

    /// The Cornell room (five walls and a light just below the ceiling, two triangles each)
    /// around a dense mesh: each wall's leaf is flat, none holds two walls at an angle, whose
    /// box would be the whole room and entered by every ray (the node's lanes had gone to the
    /// mesh instead).
    #[test]
    fn room_walls_get_leaves_of_their_own() {
        let rot = |axis: Vec3, deg: f32| Transform::rotate(axis, deg).unwrap();
        let walls = [
            Transform::translate(Vec3::new(0.0, -1.0, 0.0)).compose(&rot(Vec3::X, -90.0)),
            Transform::translate(Vec3::new(0.0, 1.0, 0.0)).compose(&rot(Vec3::X, 90.0)),
            Transform::translate(Vec3::new(0.0, 0.0, -1.0)),
            Transform::translate(Vec3::new(-1.0, 0.0, 0.0)).compose(&rot(Vec3::Y, 90.0)),
            Transform::translate(Vec3::new(1.0, 0.0, 0.0)).compose(&rot(Vec3::Y, -90.0)),
            Transform::translate(Vec3::new(0.0, 0.99, 0.0))
                .compose(&rot(Vec3::X, 90.0))
                .compose(&Transform::scale(Vec3::new(0.25, 0.25, 1.0)).unwrap()),
        ];
        let mut shapes: Vec<Shape> = walls
            .iter()
            .map(|t| Shape::Mesh(TriangleMesh::rectangle(t, false).unwrap()))
            .collect();
        // A wavy sheet of 20,000 triangles standing in the lower middle of the room.
        let k = 100u32;
        let mut p = Vec::new();
        for j in 0..=k {
            for i in 0..=k {
                let (x, y) = (i as f32 / k as f32, j as f32 / k as f32);
                let z = 0.1 * (20.0 * x).sin() * (17.0 * y).cos();
                p.push(Vec3::new(x - 0.5, 0.8 * y - 0.95, z));
            }
        }
        let mut idx = Vec::new();
        for j in 0..k {
            for i in 0..k {
                let a = j * (k + 1) + i;
                idx.push([a, a + 1, a + k + 2]);
                idx.push([a, a + k + 2, a + k + 1]);
            }
        }
        let t = Transform::IDENTITY;
        shapes.push(Shape::Mesh(
            TriangleMesh::new(p, None, None, idx, &t, false, false).unwrap(),
        ));
        let bvh = Bvh::build(&shapes);
        let mut leaves = Vec::new();
        wall_leaves(&bvh, bvh.root, 12, &mut leaves, Vec3::ZERO, Vec3::ZERO);
        assert!(leaves.len() >= 5, "{leaves:?}");
        for (lo, hi) in leaves {
            let e = hi - lo;
            // The ceiling and the light 0.01 below it may share a leaf.
            assert!(
                e.min_element() <= 0.0101,
                "a wall leaf spans {lo:?} .. {hi:?}"
            );
        }
    }
}
