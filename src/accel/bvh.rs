//! Bounding volume hierarchy over all primitives of all shapes.
//!
//! Build: top-down, binned surface-area heuristic over primitive centroids (Wald, "On fast
//! Construction of SAH-based Bounding Volume Hierarchies", 2007), 16 bins per axis, at most
//! [`MAX_LEAF`] primitives per leaf; the two halves of large nodes are built in parallel with
//! rayon. Past depth [`MEDIAN_DEPTH`] nodes split at the object median, which bounds the depth
//! (and so the traversal stack) even for adversarial inputs.
//!
//! Layout: the binary tree is kept as a flat array of 32-byte nodes (an interior node's two
//! children adjacent) and collapsed into 4-wide nodes ([`super::wide`]) for traversal: one ray
//! against four boxes with SIMD, children visited nearest first, popped entries beyond the
//! closest hit so far skipped, a fixed stack, no allocation per ray. Triangle corners are copied
//! in leaf order so leaf tests read contiguous memory.
use super::wide::{collapse, splat3, Binary, Node4};
use super::Accel;
use crate::math::{Bounds3, Ray, Vec3};
use crate::shape::mesh::intersect_watertight_sheared;
use crate::shape::{Hit, Shape};

/// Largest number of primitives in a leaf.
pub const MAX_LEAF: usize = 4;
/// Depth from which nodes split at the object median.
pub const MEDIAN_DEPTH: usize = 64;
const BINS: usize = 16;
// A 4-wide node pushes at most 4 entries per level, and the tree is at most
// MEDIAN_DEPTH + a few levels deep.
const STACK: usize = 4 * (MEDIAN_DEPTH + 8);
/// Cost of a traversal step relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;
/// Below this many primitives a subtree is built on the current thread.
const PARALLEL_MIN: usize = 8192;

/// A flattened node: bounds, and either two adjacent children at `offset` (`count` = 0) or the
/// primitives `offset .. offset + count`.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct Node {
    min: Vec3,
    offset: u32,
    max: Vec3,
    count: u32,
}

const _: () = assert!(std::mem::size_of::<Node>() == 32);

/// The BVH; see the module header.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// (shape, primitive) pairs in leaf order.
    prims: Vec<(u32, u32)>,
    /// For triangle primitives, a copy of their world-space vertices in leaf order, so that leaf
    /// tests read contiguous memory instead of chasing mesh indices (`None` for analytic
    /// primitives). Costs 36 bytes per triangle.
    tris: Vec<Option<[Vec3; 3]>>,
    /// The same tree collapsed to 4-wide nodes, which traversal uses.
    wide: Vec<Node4>,
    depth: usize,
}

#[derive(Clone, Copy)]
struct Ref {
    bounds: Bounds3,
    centroid: Vec3,
    id: (u32, u32),
}

enum Build {
    Leaf(Bounds3, usize, usize),
    Inner(Bounds3, Box<[Build; 2]>),
}

impl Bvh {
    /// Builds the hierarchy over every primitive of `shapes`.
    pub fn build(shapes: &[Shape]) -> Bvh {
        let mut refs = Vec::with_capacity(shapes.iter().map(Shape::prim_count).sum());
        for (s, shape) in shapes.iter().enumerate() {
            for p in 0..shape.prim_count() as u32 {
                let bounds = shape.prim_bounds(p);
                if bounds.is_empty() || !bounds.min.is_finite() || !bounds.max.is_finite() {
                    continue;
                }
                refs.push(Ref {
                    bounds,
                    centroid: bounds.center(),
                    id: (s as u32, p),
                });
            }
        }
        if refs.is_empty() {
            return Bvh::default();
        }
        let (root, depth) = build_node(&mut refs, 0, 1);
        let mut nodes = Vec::with_capacity(2 * refs.len() / MAX_LEAF.max(1) + 1);
        nodes.push(placeholder());
        flatten(&root, 0, &mut nodes);
        let prims: Vec<(u32, u32)> = refs.iter().map(|r| r.id).collect();
        let tris = prims
            .iter()
            .map(|&(s, p)| match &shapes[s as usize] {
                Shape::Mesh(m) => Some(m.vertices(p)),
                _ => None,
            })
            .collect();
        let binary: Vec<Binary> = nodes
            .iter()
            .map(|n| Binary {
                bounds: Bounds3 {
                    min: n.min,
                    max: n.max,
                },
                offset: n.offset,
                count: n.count,
            })
            .collect();
        let wide = collapse(&binary);
        Bvh {
            nodes,
            prims,
            tris,
            wide,
            depth,
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Depth of the tree (1 for a single leaf, 0 when empty).
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Number of primitives referenced.
    pub fn prim_count(&self) -> usize {
        self.prims.len()
    }

    /// Bounds of the whole scene.
    pub fn bounds(&self) -> Bounds3 {
        self.nodes.first().map_or(Bounds3::EMPTY, |n| Bounds3 {
            min: n.min,
            max: n.max,
        })
    }

    /// Shared traversal of the 4-wide tree; `any` stops at the first hit.
    ///
    /// The stack holds (child, primitive count, entry distance) entries; interior children are
    /// pushed far-to-near so the nearest is taken next, and entries beyond the closest hit so
    /// far are skipped when popped. No allocation per ray.
    #[inline]
    fn traverse(&self, shapes: &[Shape], ray: &Ray, any: bool) -> Option<Hit> {
        if self.wide.is_empty() {
            return None;
        }
        let sr = crate::shape::mesh::ShearedRay::new(ray.d)?;
        let o = splat3(ray.o);
        let inv_d = splat3(ray.d.recip());
        let mut r = *ray;
        let mut best = None;
        // Left uninitialised: zeroing it per ray showed in profiles; only pushed slots are read.
        let mut stack = [const { std::mem::MaybeUninit::<(u32, u32, f32)>::uninit() }; STACK];
        stack[0].write((0, 0, 0.0));
        let mut sp = 1usize;
        while sp > 0 {
            sp -= 1;
            // SAFETY: slots below `sp` were all written by a push.
            let (child, count, t_enter) = unsafe { stack[sp].assume_init() };
            if t_enter > r.t_max {
                continue;
            }
            if count > 0 {
                let start = child as usize;
                let end = start + count as usize;
                for (&(s, p), tri) in self.prims[start..end].iter().zip(&self.tris[start..end]) {
                    let hit = match tri {
                        Some([a, b, c]) => intersect_watertight_sheared(*a, *b, *c, &r, &sr),
                        None => shapes[s as usize].intersect_prim_sheared(p, &r, &sr),
                    };
                    if let Some((t, uv)) = hit {
                        r.t_max = t;
                        best = Some(Hit {
                            t,
                            shape: s,
                            prim: p,
                            uv,
                        });
                        if any {
                            return best;
                        }
                    }
                }
                continue;
            }
            let node = &self.wide[child as usize];
            let (near, hits) = node.hit(&o, &inv_d, r.t_max);
            // Empty lanes hold inverted boxes, which a ray with mixed direction signs can still
            // "hit": mask them out.
            let mut mask = hits & node.valid;
            // Hit lanes sorted by entry distance, far first, so the nearest is popped next.
            let mut lanes = [(0usize, 0.0f32); 4];
            let mut n = 0;
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let t = near[lane];
                let mut j = n;
                while j > 0 && lanes[j - 1].1 < t {
                    lanes[j] = lanes[j - 1];
                    j -= 1;
                }
                lanes[j] = (lane, t);
                n += 1;
            }
            for &(lane, t) in &lanes[..n] {
                stack[sp].write((node.child[lane], node.count[lane], t));
                sp += 1;
            }
        }
        best
    }
}

impl Accel for Bvh {
    fn intersect(&self, shapes: &[Shape], ray: &Ray) -> Option<Hit> {
        self.traverse(shapes, ray, false)
    }

    fn occluded(&self, shapes: &[Shape], ray: &Ray) -> bool {
        self.traverse(shapes, ray, true).is_some()
    }
}

fn placeholder() -> Node {
    Node {
        min: Vec3::ZERO,
        offset: 0,
        max: Vec3::ZERO,
        count: 0,
    }
}

fn flatten(b: &Build, at: usize, nodes: &mut Vec<Node>) {
    match b {
        Build::Leaf(bounds, start, count) => {
            nodes[at] = Node {
                min: bounds.min,
                offset: *start as u32,
                max: bounds.max,
                count: *count as u32,
            };
        }
        Build::Inner(bounds, kids) => {
            let c = nodes.len();
            nodes.push(placeholder());
            nodes.push(placeholder());
            nodes[at] = Node {
                min: bounds.min,
                offset: c as u32,
                max: bounds.max,
                count: 0,
            };
            flatten(&kids[0], c, nodes);
            flatten(&kids[1], c + 1, nodes);
        }
    }
}

/// Builds the subtree over `refs` (which start at `start` in the global order); returns it and
/// its depth.
fn build_node(refs: &mut [Ref], start: usize, depth: usize) -> (Build, usize) {
    let n = refs.len();
    let mut bounds = Bounds3::EMPTY;
    let mut cb = Bounds3::EMPTY;
    for r in refs.iter() {
        bounds = bounds.union(&r.bounds);
        cb.grow(r.centroid);
    }
    if n == 1 {
        return (Build::Leaf(bounds, start, n), depth);
    }
    let mid = if depth >= MEDIAN_DEPTH {
        median_split(refs, &cb)
    } else {
        match sah_split(refs, &bounds, &cb) {
            Split::Leaf => return (Build::Leaf(bounds, start, n), depth),
            Split::At(m) => m,
        }
    };
    let (left, right) = refs.split_at_mut(mid);
    let ((l, dl), (r, dr)) = if n >= PARALLEL_MIN {
        rayon::join(
            || build_node(left, start, depth + 1),
            || build_node(right, start + mid, depth + 1),
        )
    } else {
        (
            build_node(left, start, depth + 1),
            build_node(right, start + mid, depth + 1),
        )
    };
    (Build::Inner(bounds, Box::new([l, r])), dl.max(dr))
}

enum Split {
    Leaf,
    At(usize),
}

/// Splits at the object median along the widest centroid axis.
fn median_split(refs: &mut [Ref], cb: &Bounds3) -> usize {
    let axis = cb.max_axis();
    let mid = refs.len() / 2;
    refs.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
    mid
}

/// Chooses the binned-SAH split and partitions `refs` by it.
fn sah_split(refs: &mut [Ref], bounds: &Bounds3, cb: &Bounds3) -> Split {
    let n = refs.len();
    let ext = cb.extent();
    if ext.max_element().is_nan() || ext.max_element() <= 0.0 {
        // All centroids coincide: no plane separates them.
        return if n <= MAX_LEAF {
            Split::Leaf
        } else {
            Split::At(n / 2)
        };
    }
    // Scale that maps a centroid to its bin; slightly shrunk so the maximum lands in the last bin.
    let scale = Vec3::select(
        ext.cmpgt(Vec3::ZERO),
        Vec3::splat(BINS as f32 * (1.0 - 1e-6)) / ext,
        Vec3::ZERO,
    );
    let bin_of = |c: Vec3, axis: usize| -> usize {
        (((c[axis] - cb.min[axis]) * scale[axis]) as usize).min(BINS - 1)
    };
    let mut count = [[0u32; BINS]; 3];
    let mut bb = [[Bounds3::EMPTY; BINS]; 3];
    for r in refs.iter() {
        for axis in 0..3 {
            let b = bin_of(r.centroid, axis);
            count[axis][b] += 1;
            bb[axis][b] = bb[axis][b].union(&r.bounds);
        }
    }
    let mut best = (f32::INFINITY, 0usize, 0usize);
    for axis in 0..3 {
        if ext[axis] <= 0.0 {
            continue;
        }
        // Right-to-left sweep stores the cost of each right side; the left sweep adds its own.
        let mut right_cost = [0.0f32; BINS];
        let (mut acc_b, mut acc_n) = (Bounds3::EMPTY, 0u32);
        for i in (1..BINS).rev() {
            acc_b = acc_b.union(&bb[axis][i]);
            acc_n += count[axis][i];
            right_cost[i] = acc_n as f32 * acc_b.surface_area();
        }
        let (mut acc_b, mut acc_n) = (Bounds3::EMPTY, 0u32);
        for i in 1..BINS {
            acc_b = acc_b.union(&bb[axis][i - 1]);
            acc_n += count[axis][i - 1];
            if acc_n == 0 || acc_n as usize == n {
                continue;
            }
            let cost = acc_n as f32 * acc_b.surface_area() + right_cost[i];
            if cost < best.0 {
                best = (cost, axis, i);
            }
        }
    }
    let area = bounds.surface_area().max(f32::MIN_POSITIVE);
    let split_cost = TRAVERSAL_COST + best.0 / area;
    if n <= MAX_LEAF && (n as f32) <= split_cost {
        return Split::Leaf;
    }
    if !best.0.is_finite() {
        return Split::At(n / 2);
    }
    let (_, axis, split) = best;
    // In-place partition: bins below `split` go left.
    let (mut i, mut j) = (0usize, n);
    while i < j {
        if bin_of(refs[i].centroid, axis) < split {
            i += 1;
        } else {
            j -= 1;
            refs.swap(i, j);
        }
    }
    if i == 0 || i == n {
        return Split::At(n / 2);
    }
    Split::At(i)
}
