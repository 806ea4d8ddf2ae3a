//! Top-down binned-SAH build, straight into 8-wide nodes, on all threads.
//!
//! Each primitive becomes a 32-byte [`Ref`] (its bounds and lane id). A node's range of refs is
//! split by the binned surface-area heuristic (Wald, "On fast Construction of SAH-based Bounding
//! Volume Hierarchies", 2007; 16 bins per axis over centroids) into two; an 8-wide node then
//! keeps splitting its child with the largest surface area until it has eight (the greedy
//! collapse of a binary SAH tree, without building the binary tree), a child the cost model
//! made a leaf included if splitting it lowers its own cost by [`FREE_SPLIT_GAIN`]. The cost
//! model counts leaf primitives in blocks of four ([`super::block`]): a leaf of five costs as
//! much as one of eight, which steers leaves towards full blocks. A split that starts a new
//! node is charged the whole node test (`NODE_COST`), not one lane's share: a range of 9–16
//! primitives then becomes one leaf of up to four blocks rather than a node with two leaves in
//! its eight lanes (on the 1M-triangle benchmark mesh, 47 % of the nodes had been such nodes).
//!
//! Past binary depth [`MEDIAN_DEPTH`] ranges split at the object median, which bounds the depth
//! (and so the traversal stack) even for adversarial inputs. Leaves hold at most [`MAX_LEAF`]
//! primitives.
//!
//! Threads: the bins of large ranges are filled in parallel chunks and merged (counts add and
//! bounds take min/max, so the result does not depend on the chunking), and large ranges are
//! partitioned chunk by chunk in parallel, then the misplaced refs exchanged (fixed chunks: the
//! order does not depend on the thread count); the subtrees of a node are built in parallel,
//! each into its own node list, and appended in lane order. The tree is therefore the same
//! whatever the thread count.
use super::bins::{area, best_plane, blocks, Binner, Bins, BINS};
use super::block::ANALYTIC;
use super::partition::{partition, partition_parallel};
use super::wide::Node8;
use crate::math::Vec3;
use crate::shape::Shape;
use glam::Vec4;
use rayon::prelude::*;

/// Largest number of primitives in a leaf.
pub const MAX_LEAF: usize = 16;
const _: () = assert!(MAX_LEAF.div_ceil(4) <= super::wide::MAX_LEAF_BLOCKS);
/// Binary depth from which ranges split at the object median.
pub const MEDIAN_DEPTH: usize = 64;
/// Cost of a binary split (a share of an 8-wide node test) relative to one block test.
const SPLIT_COST: f32 = 0.35;
/// Cost of a range's first split, which makes a node of its own: the whole node test (the
/// seven binary splits an 8-wide node stands for), however few of its lanes end up used.
const NODE_COST: f32 = 7.0 * SPLIT_COST;
/// A leaf is split into more of its node's lanes only if that brings its cost below this
/// fraction of the leaf's (the lane's box test comes with the node's, at no extra cost).
const FREE_SPLIT_GAIN: f32 = 0.7;
/// Below this many refs a subtree is built on the current thread.
const PARALLEL_MIN: usize = 4096;
/// From this many refs the bins are filled in parallel chunks of this size.
pub(super) const BIN_CHUNK: usize = 32 * 1024;

/// A primitive's bounds; `lo.w` holds its lane id (see [`super::block`]) as bits, `hi.w` is 0.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Ref {
    pub(super) lo: Vec4,
    pub(super) hi: Vec4,
}

impl Ref {
    /// The lane id.
    pub fn id(&self) -> u32 {
        self.lo.w.to_bits()
    }

    /// Twice the centroid (in xyz).
    #[inline(always)]
    pub(super) fn c2(&self) -> Vec4 {
        self.lo + self.hi
    }
}

/// Refs for every primitive with finite, non-empty bounds. Triangles get their global id (mesh
/// triangles counted in shape order, `first[s]` for the first of shape `s`), analytic shapes
/// [`ANALYTIC`] | their shape index. Written in place in parallel (no second copy of the array).
pub fn refs(shapes: &[Shape], first: &[u32]) -> Vec<Ref> {
    // A ref with empty bounds marks a primitive left out.
    let none = Ref {
        lo: Vec4::INFINITY,
        hi: Vec4::NEG_INFINITY,
    };
    let mut out = Vec::with_capacity(shapes.iter().map(Shape::prim_count).sum());
    for (s, shape) in shapes.iter().enumerate() {
        let make = |p: usize| {
            let b = shape.prim_bounds(p as u32);
            if b.is_empty() || !b.min.is_finite() || !b.max.is_finite() {
                return none;
            }
            let id = match shape {
                Shape::Mesh(_) => first[s] + p as u32,
                _ => ANALYTIC | s as u32,
            };
            Ref {
                lo: b.min.extend(f32::from_bits(id)),
                hi: b.max.extend(0.0),
            }
        };
        let n = shape.prim_count();
        // Written in place by all threads (rayon extends a vector with an indexed iterator in
        // its spare room), so the array's fresh pages are first touched on all of them.
        if n >= PARALLEL_MIN {
            out.par_extend((0..n).into_par_iter().map(make));
        } else {
            out.extend((0..n).map(make));
        }
    }
    let kept = |r: &Ref| r.lo.x <= r.hi.x;
    if !out.par_iter().all(kept) {
        out.retain(kept);
    }
    out
}

/// A child slot while building.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    Empty,
    /// Index of an interior node.
    Inner(u32),
    /// Refs `start .. start + len`.
    Leaf {
        start: u32,
        len: u32,
    },
}

/// `Nodes::len` of an interior lane.
pub const INNER: u8 = u8::MAX;

/// The nodes of a tree being built, already in their final [`Node8`] form except that a leaf
/// lane's `child` holds its first ref and `len` its ref count; an interior lane has `len` =
/// [`INNER`] and an unused one 0. The layout turns leaf lanes into block references in place.
#[derive(Default)]
pub struct Nodes {
    pub node: Vec<Node8>,
    pub len: Vec<[u8; 8]>,
}

impl Nodes {
    /// The slot of lane `lane` of node `i`.
    pub fn slot(&self, i: usize, lane: usize) -> Slot {
        match self.len[i][lane] {
            0 => Slot::Empty,
            INNER => Slot::Inner(self.node[i].child[lane]),
            n => Slot::Leaf {
                start: self.node[i].child[lane],
                len: n as u32,
            },
        }
    }
}

/// The built tree: its nodes (the root, when interior, is node 0), the root slot and the
/// bounds of everything. Leaves hold ranges of the reordered refs, in increasing order along a
/// depth-first walk.
pub struct Tree {
    pub nodes: Nodes,
    pub root: Slot,
    pub lo: Vec3,
    pub hi: Vec3,
}

/// Builds the tree over `refs`, reordering them so that every leaf is a contiguous range.
pub fn build(refs: &mut [Ref]) -> Tree {
    let mut nodes = Nodes::default();
    if refs.is_empty() {
        return Tree {
            nodes,
            root: Slot::Empty,
            lo: Vec3::ZERO,
            hi: Vec3::ZERO,
        };
    }
    let span = span_of(refs, 0, 0);
    let root = subtree(refs, 0, span, &mut nodes);
    Tree {
        nodes,
        root,
        lo: span.lo.truncate(),
        hi: span.hi.truncate(),
    }
}

/// A range of refs with its bounds and centroid bounds (of `lo + hi`) and binary depth.
#[derive(Clone, Copy, Debug)]
struct Span {
    start: usize,
    len: usize,
    lo: Vec4,
    hi: Vec4,
    clo: Vec4,
    chi: Vec4,
    depth: usize,
}

impl Span {
    fn area(&self) -> f32 {
        area(self.lo, self.hi)
    }
}

/// Bounds and centroid bounds of `refs` (which start at `start`).
fn span_of(refs: &[Ref], start: usize, depth: usize) -> Span {
    let inf = Vec4::splat(f32::INFINITY);
    let fold = |(lo, hi, clo, chi): (Vec4, Vec4, Vec4, Vec4), r: &Ref| {
        let c = r.c2();
        (lo.min(r.lo), hi.max(r.hi), clo.min(c), chi.max(c))
    };
    let merge = |a: (Vec4, Vec4, Vec4, Vec4), b: (Vec4, Vec4, Vec4, Vec4)| {
        (a.0.min(b.0), a.1.max(b.1), a.2.min(b.2), a.3.max(b.3))
    };
    let init = (inf, -inf, inf, -inf);
    let (lo, hi, clo, chi) = if refs.len() >= BIN_CHUNK {
        refs.par_chunks(BIN_CHUNK)
            .map(|c| c.iter().fold(init, fold))
            .reduce(|| init, merge)
    } else {
        refs.iter().fold(init, fold)
    };
    Span {
        start,
        len: refs.len(),
        lo,
        hi,
        clo,
        chi,
        depth,
    }
}

/// The subtree over `refs` (the refs of `span`, which starts at global index `span.start`):
/// a leaf, or an interior node appended to `out` (whose indices are local to `out`).
fn subtree(refs: &mut [Ref], base: usize, span: Span, out: &mut Nodes) -> Slot {
    match split(refs, &span, Mode::Node) {
        None => leaf(&span),
        Some((l, r)) => Slot::Inner(wide_node(refs, base, l, r, out)),
    }
}

/// What may still happen to a kid of a node being gathered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kid {
    /// Not yet considered for splitting.
    Open,
    /// The cost model made it a leaf; a split into another lane may still pay.
    Leaf,
    /// A leaf for good.
    Final,
}

/// Builds the 8-wide node whose range was split into `l` and `r`; returns its index in `out`.
fn wide_node(refs: &mut [Ref], base: usize, l: Span, r: Span, out: &mut Nodes) -> u32 {
    // Kids in range order, with what may still happen to them.
    let mut kids: Vec<(Span, Kid)> = Vec::with_capacity(8);
    kids.push((l, Kid::Open));
    kids.push((r, Kid::Open));
    while kids.len() < 8 {
        // Split the largest kid that may still be split: an open one as the cost model
        // decides, a leaf only if that alone lowers its cost (the new lane's box test comes
        // with the node's; see `Mode::Free`). A large leaf comes before smaller
        // open kids: in the Cornell room two walls made one leaf whose box was the whole
        // room, tested by every ray, while the lanes went to the mesh.
        let pick = (0..kids.len())
            .filter(|&i| kids[i].1 != Kid::Final)
            .max_by(|&a, &b| {
                kids[a]
                    .0
                    .area()
                    .total_cmp(&kids[b].0.area())
                    .then(b.cmp(&a))
            });
        let Some(i) = pick else { break };
        let free = kids[i].1 == Kid::Leaf;
        let k = kids[i].0;
        let local = k.start - base;
        let mode = if free { Mode::Free } else { Mode::Lane };
        match split(&mut refs[local..local + k.len], &k, mode) {
            None if free => kids[i].1 = Kid::Final,
            None => kids[i].1 = Kid::Leaf,
            Some((a, b)) => {
                let state = if free { Kid::Leaf } else { Kid::Open };
                kids[i] = (a, state);
                kids.insert(i + 1, (b, state));
            }
        }
    }
    let index = out.node.len();
    out.node.push(Node8::empty());
    out.len.push([0; 8]);
    let total: usize = kids.iter().map(|k| k.0.len).sum();
    // Cut `refs` into the kids' disjoint ranges.
    let mut pieces = Vec::with_capacity(kids.len());
    let mut rest = refs;
    for (k, _) in &kids {
        let (head, tail) = rest.split_at_mut(k.len);
        pieces.push(head);
        rest = tail;
    }
    let mut slots = [Slot::Empty; 8];
    let open = |k: &Kid| *k == Kid::Open;
    if total >= PARALLEL_MIN && kids.iter().filter(|k| open(&k.1)).count() > 1 {
        let built: Vec<(Slot, Nodes)> = pieces
            .into_par_iter()
            .zip(kids.par_iter())
            .map(|(piece, (k, state))| {
                let mut sub = Nodes::default();
                let slot = if open(state) {
                    subtree(piece, k.start, *k, &mut sub)
                } else {
                    leaf(k)
                };
                (slot, sub)
            })
            .collect();
        // Grow the list once, to its exact size, rather than by doubling.
        let more: usize = built.iter().map(|b| b.1.node.len()).sum();
        out.node.reserve_exact(more);
        out.len.reserve_exact(more);
        for (lane, (slot, sub)) in built.into_iter().enumerate() {
            slots[lane] = append(out, slot, sub);
        }
    } else {
        for (lane, (piece, (k, state))) in pieces.into_iter().zip(&kids).enumerate() {
            slots[lane] = if open(state) {
                subtree(piece, k.start, *k, out)
            } else {
                leaf(k)
            };
        }
    }
    for (lane, (k, _)) in kids.iter().enumerate() {
        let (child, len) = match slots[lane] {
            Slot::Empty => unreachable!("every kid fills its lane"),
            Slot::Inner(i) => (i, INNER),
            Slot::Leaf { start, len } => {
                assert!(len as usize <= MAX_LEAF);
                (start, len as u8)
            }
        };
        out.node[index].set(lane, k.lo.truncate(), k.hi.truncate(), child);
        out.len[index][lane] = len;
    }
    index as u32
}

fn leaf(k: &Span) -> Slot {
    Slot::Leaf {
        start: k.start as u32,
        len: k.len as u32,
    }
}

/// Appends a subtree built into its own list (root at index 0) to `out`; returns its slot.
fn append(out: &mut Nodes, slot: Slot, sub: Nodes) -> Slot {
    let shift = out.node.len() as u32;
    for (mut n, len) in sub.node.into_iter().zip(sub.len) {
        for (c, &l) in n.child.iter_mut().zip(&len) {
            if l == INNER {
                *c += shift;
            }
        }
        out.node.push(n);
        out.len.push(len);
    }
    match slot {
        Slot::Inner(i) => Slot::Inner(i + shift),
        s => s,
    }
}

/// What a split would cost beyond its children.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// The range is a subtree's root: splitting it makes a node (see [`NODE_COST`]).
    Node,
    /// The range is a kid of a node being gathered: a split takes one more of its lanes.
    Lane,
    /// A kid the cost model made a leaf, split into another lane of its node (whose box
    /// test comes with the node's): only if the split lowers its cost by [`FREE_SPLIT_GAIN`].
    Free,
}

/// Splits a span's refs in two (reordering them), or `None` to make it a leaf; `mode` says
/// what the split itself costs.
fn split(refs: &mut [Ref], sp: &Span, mode: Mode) -> Option<(Span, Span)> {
    let free = mode == Mode::Free;
    let n = sp.len;
    if n <= 1 {
        return None;
    }
    // An analytic primitive (sphere, disk) costs far more to test than a box: each gets a leaf
    // of its own, so that its box culls it.
    let analytic = n <= MAX_LEAF && refs.iter().any(|r| r.id() & ANALYTIC != 0);
    // One block tests up to four triangles at the cost of one: splitting them would add a box
    // test and a second block, unless lanes are free.
    if n <= 4 && !free && !analytic {
        return None;
    }
    if sp.depth >= MEDIAN_DEPTH {
        return Some(median_split(refs, sp));
    }
    let ext = sp.chi - sp.clo;
    if !(ext.x.max(ext.y).max(ext.z) > 0.0) {
        // All centroids coincide: no plane separates them.
        return (n > MAX_LEAF).then(|| halves(refs, sp, n / 2));
    }
    // Small ranges need fewer candidate planes; the sweep's cost is per bin.
    let nb = n.clamp(4, BINS);
    let scale = Vec4::select(
        ext.cmpgt(Vec4::ZERO),
        Vec4::splat(nb as f32 * (1.0 - 1e-6)) / ext,
        Vec4::ZERO,
    );
    let binner = Binner {
        clo: sp.clo,
        scale,
        last: Vec4::splat((nb - 1) as f32),
    };
    let bins = if n >= 2 * BIN_CHUNK {
        refs.par_chunks(BIN_CHUNK)
            .map(|c| {
                let mut bins = Bins::EMPTY;
                binner.fill(c, &mut bins);
                bins
            })
            .reduce(|| Bins::EMPTY, |a, b| a.merge(&b))
    } else {
        let mut bins = Bins::EMPTY;
        binner.fill(refs, &mut bins);
        bins
    };
    // Best plane: minimum of area·blocks summed over both sides.
    let mut best = (f32::INFINITY, 0usize, 0usize);
    for a in 0..3 {
        if ext[a] > 0.0 {
            let (cost, plane) = best_plane(&bins, a, nb, n);
            if cost < best.0 {
                best = (cost, a, plane);
            }
        }
    }
    let (cost, axis, plane) = best;
    // A leaf's split into another lane costs no traversal step, but more, emptier blocks:
    // take it only when it clearly pays.
    let split_cost = match mode {
        Mode::Lane => SPLIT_COST + cost / sp.area().max(f32::MIN_POSITIVE),
        Mode::Node => NODE_COST + cost / sp.area().max(f32::MIN_POSITIVE),
        Mode::Free => cost / sp.area().max(f32::MIN_POSITIVE) / FREE_SPLIT_GAIN,
    };
    if n <= MAX_LEAF && !analytic && blocks(n as u32) <= split_cost {
        return None;
    }
    if !cost.is_finite() {
        return Some(halves(refs, sp, n / 2));
    }
    let plane_f = plane as f32;
    let below = |r: &Ref| binner.below(r.c2(), axis, plane_f);
    let (i, [lclo, lchi, rclo, rchi]) = if n >= 2 * BIN_CHUNK {
        partition_parallel(refs, &below)
    } else {
        partition(refs, &below)
    };
    if i == 0 || i == n {
        return Some(halves(refs, sp, n / 2));
    }
    let inf = Vec4::splat(f32::INFINITY);
    let side = |range: std::ops::Range<usize>| {
        let (mut lo, mut hi) = (inf, -inf);
        for b in range {
            lo = lo.min(bins.lo[axis][b]);
            hi = hi.max(bins.hi[axis][b]);
        }
        (lo, hi)
    };
    let (llo, lhi) = side(0..plane);
    let (rlo, rhi) = side(plane..nb);
    let d = sp.depth + 1;
    Some((
        Span {
            start: sp.start,
            len: i,
            lo: llo,
            hi: lhi,
            clo: lclo,
            chi: lchi,
            depth: d,
        },
        Span {
            start: sp.start + i,
            len: n - i,
            lo: rlo,
            hi: rhi,
            clo: rclo,
            chi: rchi,
            depth: d,
        },
    ))
}

/// Splits at the object median along the widest centroid axis.
fn median_split(refs: &mut [Ref], sp: &Span) -> (Span, Span) {
    let e = sp.chi - sp.clo;
    let axis = if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    };
    let mid = refs.len() / 2;
    refs.select_nth_unstable_by(mid, |a, b| a.c2()[axis].total_cmp(&b.c2()[axis]));
    halves(refs, sp, mid)
}

/// The spans of `refs[..mid]` and `refs[mid..]`.
fn halves(refs: &[Ref], sp: &Span, mid: usize) -> (Span, Span) {
    let (l, r) = refs.split_at(mid);
    (
        span_of(l, sp.start, sp.depth + 1),
        span_of(r, sp.start + mid, sp.depth + 1),
    )
}

/// The lane ids of the refs in their current order (for filling blocks after the refs are
/// freed).
pub fn ids(refs: &[Ref]) -> Vec<u32> {
    refs.par_iter().map(Ref::id).collect()
}
