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
//! and gained nothing on the Cornell box or the 1M-triangle mesh.)
//!
//! # Same answers
//!
//! Every lane computes the watertight test of [`super::block`] with the same operations in the
//! same order: the corners are splatted and each lane's axis permutation applied by selects,
//! which move bits and round nothing; the shear is [`ShearedRay::new`]'s, in lanes. The box
//! tests are those of [`super::wide::Node8::hit`] with the packet's rays in the lanes. The
//! closest hit is the first in (parameter, id) order ([`super::block::Best`]) and every
//! pruning test is conservative, so the packet finds what the single-ray traversal finds, bit
//! for bit, whatever order it visits the tree in (`packet_tests.rs` compares the two on every
//! instruction set).
//!
//! Everything here is `#[inline(always)]`, compiled per instruction set by [`super::isa`]
//! (no closures: a closure is compiled without the caller's instruction set).
use super::block::{widen, Best, Block, ANALYTIC, EMPTY, NO_HIT};
use super::bvh::SHORT_TABLE;
use super::simd::Vec8;
use super::traverse::{self, Found, View, STACK};
use super::wide::{leaf_range, LEAF};
use super::RawHit;
use crate::math::{Ray, Vec2, Vec3};
use crate::shape::mesh::{edge_f64, gamma, ShearedRay};
use crate::shape::{Hit, Shape};
use crate::simd::{Float, Int, Mask};
use std::mem::MaybeUninit;

/// A node with at most this many rays left continues ray by ray (measured: 2 to 5 level,
/// 1 slower on the 1M-triangle mesh).
pub const SWITCH_NODE: u32 = 3;
/// A leaf with at most this many rays left is tested ray by ray (measured: 1 about 3 % faster
/// than 3 on the Cornell box, level on the mesh).
pub const SWITCH_LEAF: u32 = 1;

/// Most lanes of a packet.
const MAX_LANES: usize = 16;

/// `a < b ? a : b` lane by lane (the box test's min, as [`Vec8::min`]).
#[inline(always)]
fn min_of<F: Float>(a: F, b: F) -> F {
    F::select(a.lt(b), a, b)
}

/// `a > b ? a : b` lane by lane.
#[inline(always)]
fn max_of<F: Float>(a: F, b: F) -> F {
    F::select(a.gt(b), a, b)
}

/// An axis index per lane (0, 1 or 2), as the two masks `is 0` and `is 1`.
#[derive(Clone, Copy)]
struct Axis<M> {
    x: M,
    y: M,
}

impl<M: Mask> Axis<M> {
    /// The axis of lane `i`.
    #[inline(always)]
    fn lane(&self, i: usize) -> usize {
        let (x, y) = (self.x.bits() >> i & 1, self.y.bits() >> i & 1);
        (2 - 2 * x - y) as usize
    }

    #[inline(always)]
    fn pick<F: Float<M = M>>(self, x: F, y: F, z: F) -> F {
        F::select(self.x, x, F::select(self.y, y, z))
    }
}

/// `n ? a : b` for masks.
#[inline(always)]
fn either<M: Mask>(n: M, a: M, b: M) -> M {
    (n & a) | (!n & b)
}

/// A batch of rays as columns (structure of arrays): `o[axis][i]`, `d[axis][i]` and
/// `t_max[i]` for ray `i < n`, as the wavefront keeps its paths.
#[derive(Clone, Copy)]
pub struct RayColumns<'a> {
    pub o: [&'a [f32]; 3],
    pub d: [&'a [f32]; 3],
    pub t_max: &'a [f32],
    pub n: usize,
}

impl RayColumns<'_> {
    /// Ray `i`.
    #[inline]
    pub fn ray(&self, i: usize) -> Ray {
        Ray {
            o: Vec3::new(self.o[0][i], self.o[1][i], self.o[2][i]),
            d: Vec3::new(self.d[0][i], self.d[1][i], self.d[2][i]),
            t_max: self.t_max[i],
        }
    }
}

/// The rays of a packet in lanes, with the per-ray constants of the box and triangle tests.
struct Lanes<F: Float> {
    /// Rows: origin x, y, z, extent, direction x, y, z, per lane (for rays that go on alone).
    row: [[f32; MAX_LANES]; 7],
    /// Lanes holding a ray that can hit anything (a nonzero direction).
    valid: u32,
    o: [F; 3],
    d: [F; 3],
    inv_d: [F; 3],
    /// The rays' own extents.
    t_max: F,
    /// The watertight test's permutation and shear ([`ShearedRay`]).
    k: [Axis<F::M>; 3],
    s: [F; 3],
    /// The shear and reciprocal direction per lane, for rays that go on alone.
    s_lanes: [[f32; MAX_LANES]; 3],
    inv_lanes: [[f32; MAX_LANES]; 3],
}

impl<F: Float> Lanes<F> {
    /// The packet of `rays`.
    #[inline(always)]
    fn new(rays: &[Ray]) -> Lanes<F> {
        debug_assert!(rays.len() <= F::LANES && F::LANES <= MAX_LANES);
        // Zero in lanes without a ray (a zero direction makes them invalid).
        let mut a = [[0.0f32; MAX_LANES]; 7];
        for (i, r) in rays.iter().enumerate() {
            a[0][i] = r.o.x;
            a[1][i] = r.o.y;
            a[2][i] = r.o.z;
            a[3][i] = r.t_max;
            a[4][i] = r.d.x;
            a[5][i] = r.d.y;
            a[6][i] = r.d.z;
        }
        Lanes::from_rows(a, rays.len())
    }

    /// The packet of rays `base .. base + count` of `c` (`count` at most `F::LANES`).
    #[inline(always)]
    fn from_columns(c: &RayColumns, base: usize, count: usize) -> Lanes<F> {
        debug_assert!(count <= F::LANES && base + count <= c.n);
        let cols = [c.o[0], c.o[1], c.o[2], c.t_max, c.d[0], c.d[1], c.d[2]];
        let mut a = [[0.0f32; MAX_LANES]; 7];
        for (row, col) in a.iter_mut().zip(cols) {
            if base + F::LANES <= col.len() {
                F::load_at(col, base).store(&mut row[..]);
                row[count..].fill(0.0);
            } else {
                row[..count].copy_from_slice(&col[base..base + count]);
            }
        }
        Lanes::from_rows(a, count)
    }

    /// The packet of the rays in the rows `a` (lanes `count..` zero); the shear is
    /// [`ShearedRay::new`]'s, computed in lanes.
    #[inline(always)]
    fn from_rows(a: [[f32; MAX_LANES]; 7], count: usize) -> Lanes<F> {
        let zero = F::splat(0.0);
        let one = F::splat(1.0);
        let d = [F::load(&a[4]), F::load(&a[5]), F::load(&a[6])];
        let (ax, ay, az) = (d[0].abs(), d[1].abs(), d[2].abs());
        // The dominant axis kz as `ShearedRay::new` picks it, then kx and ky after it in
        // cyclic order, exchanged where d[kz] < 0.
        let (x_y, x_z, y_z) = (ax.gt(ay), ax.gt(az), ay.gt(az));
        let kz0 = x_y & x_z;
        let kz1 = !x_y & y_z;
        let kz2 = !(kz0 | kz1);
        let kz = Axis { x: kz0, y: kz1 };
        let dz = kz.pick(d[0], d[1], d[2]);
        let neg = dz.lt(zero);
        let kx = Axis {
            x: either(neg, kz1, kz2),
            y: either(neg, kz2, kz0),
        };
        let ky = Axis {
            x: either(neg, kz2, kz1),
            y: either(neg, kz0, kz2),
        };
        let valid = (!dz.eq(zero)).bits() & ((1u32 << count) - 1);
        let s = [
            kx.pick(d[0], d[1], d[2]) / dz,
            ky.pick(d[0], d[1], d[2]) / dz,
            one / dz,
        ];
        // As `Vec3::recip`: one division per component.
        let inv_d = [one / d[0], one / d[1], one / d[2]];
        let mut s_lanes = [[0.0f32; MAX_LANES]; 3];
        let mut inv_lanes = [[0.0f32; MAX_LANES]; 3];
        for a in 0..3 {
            s[a].store(&mut s_lanes[a][..]);
            inv_d[a].store(&mut inv_lanes[a][..]);
        }
        Lanes {
            row: a,
            valid,
            o: [F::load(&a[0]), F::load(&a[1]), F::load(&a[2])],
            d,
            inv_d,
            t_max: F::load(&a[3]),
            k: [kx, ky, kz],
            s,
            s_lanes,
            inv_lanes,
        }
    }

    /// The lanes of `active` that an analytic primitive's own test must decide: for a sphere
    /// those that pass [`crate::shape::Sphere::intersect`]'s conservative pre-test (computed in lanes with
    /// the same operations), for other shapes all of them.
    #[inline(always)]
    fn candidates(&self, shape: &Shape, active: u32) -> u32 {
        let Shape::Sphere(s) = shape else {
            return active;
        };
        let c = [
            F::splat(s.center.x),
            F::splat(s.center.y),
            F::splat(s.center.z),
        ];
        let f = [self.o[0] - c[0], self.o[1] - c[1], self.o[2] - c[2]];
        let d = &self.d;
        let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let fd = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
        let unit = (dd - F::splat(1.0)).abs().lt(F::splat(1e-6));
        let b = F::select(unit, fd, fd / dd);
        let l = [f[0] - d[0] * b, f[1] - d[1] * b, f[2] - d[2] * b];
        let ll = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
        let ff = f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
        let r2 = s.radius * s.radius;
        let outside = ll.gt(F::splat(r2 * 1.001) + F::splat(1e-5) * ff);
        active & !outside.bits()
    }

    /// Lane `i`'s ray.
    #[inline(always)]
    fn ray(&self, i: usize) -> Ray {
        let a = &self.row;
        Ray {
            o: Vec3::new(a[0][i], a[1][i], a[2][i]),
            d: Vec3::new(a[4][i], a[5][i], a[6][i]),
            t_max: a[3][i],
        }
    }

    /// Lane `i`'s shear and reciprocal direction, for [`traverse`]'s single-ray loops.
    #[inline(always)]
    fn single(&self, i: usize) -> (ShearedRay, Vec3) {
        let sr = ShearedRay {
            kx: self.k[0].lane(i),
            ky: self.k[1].lane(i),
            kz: self.k[2].lane(i),
            sx: self.s_lanes[0][i],
            sy: self.s_lanes[1][i],
            sz: self.s_lanes[2][i],
        };
        let inv = Vec3::new(
            self.inv_lanes[0][i],
            self.inv_lanes[1][i],
            self.inv_lanes[2][i],
        );
        (sr, inv)
    }

    /// Entry distances into the box `lo ..= hi` and the lanes of `active` that overlap it
    /// before `t_max` (as [`super::wide::Node8::hit`] computes them for one ray).
    #[inline(always)]
    fn enter(&self, lo: [f32; 3], hi: [f32; 3], t_max: F, active: u32) -> (F, u32) {
        let mut near = F::splat(0.0);
        let mut far = t_max;
        for a in 0..3 {
            let t0 = (F::splat(lo[a]) - self.o[a]) * self.inv_d[a];
            let t1 = (F::splat(hi[a]) - self.o[a]) * self.inv_d[a];
            near = max_of(min_of(t0, t1), near);
            far = min_of(max_of(t0, t1), far);
        }
        let far = far * F::splat(1.0 + 3.0 * f32::EPSILON);
        (near, near.le(far).bits() & active)
    }

    /// Corner `p` relative to the ray origins, in each lane's permuted axes. (A method, not a
    /// closure: a closure is compiled without the caller's instruction set.)
    #[inline(always)]
    fn relative(&self, p: [f32; 3]) -> (F, F, F) {
        let d = [
            F::splat(p[0]) - self.o[0],
            F::splat(p[1]) - self.o[1],
            F::splat(p[2]) - self.o[2],
        ];
        (
            self.k[0].pick(d[0], d[1], d[2]),
            self.k[1].pick(d[0], d[1], d[2]),
            self.k[2].pick(d[0], d[1], d[2]),
        )
    }

    /// The watertight test of slot `slot` of `b` (a triangle) for the lanes of `active`,
    /// against each ray's own extent and, for `first`, not beyond `best`. Returns the lanes
    /// hit, their parameter and their barycentrics b1, b2.
    #[inline(always)]
    fn triangle(&self, b: &Block, slot: usize, active: u32, best: F) -> (u32, F, F, F) {
        let zero = F::splat(0.0);
        let (a0, a1, a2) = self.relative(b.corner(0, slot));
        let (b0, b1, b2) = self.relative(b.corner(1, slot));
        let (c0, c1, c2) = self.relative(b.corner(2, slot));
        let [sx, sy, sz] = self.s;
        let (ax, ay) = (a0 - sx * a2, a1 - sy * a2);
        let (bx, by) = (b0 - sx * b2, b1 - sy * b2);
        let (cx, cy) = (c0 - sx * c2, c1 - sy * c2);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        let on_edge = (u.eq(zero) | v.eq(zero) | w.eq(zero)).bits() & active;
        if on_edge != 0 {
            let mut a = [[0.0f32; MAX_LANES]; 9];
            for (row, x) in a.iter_mut().zip([ax, ay, bx, by, cx, cy, u, v, w]) {
                x.store(&mut row[..]);
            }
            redo_edges(on_edge, &mut a);
            (u, v, w) = (F::load(&a[6]), F::load(&a[7]), F::load(&a[8]));
        }
        let mixed = (u.lt(zero) | v.lt(zero) | w.lt(zero)) & (u.gt(zero) | v.gt(zero) | w.gt(zero));
        let inside = active & !mixed.bits();
        if inside == 0 {
            return (0, zero, zero, zero);
        }
        let det = u + v + w;
        let (az, bz, cz) = (sz * a2, sz * b2, sz * c2);
        let t_scaled = u * az + v * bz + w * cz;
        let tmd = self.t_max * det;
        let in_range = (det.lt(zero) & t_scaled.lt(zero) & t_scaled.gt(tmd))
            | (det.gt(zero) & t_scaled.gt(zero) & t_scaled.lt(tmd));
        let inv = F::splat(1.0) / det;
        let t = t_scaled * inv;
        let t_ok = t.gt(zero) & t.lt(self.t_max);
        let max_zt = az.abs().max(bz.abs()).max(cz.abs());
        let max_xt = ax.abs().max(bx.abs()).max(cx.abs());
        let max_yt = ay.abs().max(by.abs()).max(cy.abs());
        let (g2, g3, g5) = (F::splat(gamma(2)), F::splat(gamma(3)), F::splat(gamma(5)));
        let delta_z = g3 * max_zt;
        let delta_x = g5 * (max_xt + max_zt);
        let delta_y = g5 * (max_yt + max_zt);
        let delta_e = F::splat(2.0) * (g2 * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = u.abs().max(v.abs()).max(w.abs());
        let delta_t =
            F::splat(3.0) * (g3 * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv.abs();
        let beyond_error = t.gt(delta_t);
        let first = t.le(best);
        let hit = (in_range & t_ok & beyond_error & first).bits() & inside;
        (hit, t, v * inv, w * inv)
    }
}

/// The f64 redo of the edge functions in the lanes of `on_edge` (see the scalar test): `a`
/// holds the lanes of ax, ay, bx, by, cx, cy, and u, v, w, which it updates.
#[cold]
#[inline(never)]
fn redo_edges(on_edge: u32, a: &mut [[f32; MAX_LANES]; 9]) {
    let mut m = on_edge;
    while m != 0 {
        let l = m.trailing_zeros() as usize;
        m &= m - 1;
        let [ax, ay, bx, by, cx, cy] = [0, 1, 2, 3, 4, 5].map(|r| a[r][l]);
        a[6][l] = edge_f64(cx, by, cy, bx);
        a[7][l] = edge_f64(ax, cy, ay, cx);
        a[8][l] = edge_f64(bx, ay, by, ax);
    }
}

/// The closest hits of the packet so far, in lanes: [`NO_HIT`] (flipped) where none.
struct Closest<F: Float> {
    t: F,
    /// Lane ids with the top bit flipped, so that a signed compare orders them as unsigned.
    id: F::I,
    /// Hit coordinates.
    u: F,
    v: F,
    /// Where the primitive's slot is: block index and lane.
    block: F::I,
    slot: F::I,
}

/// Flips the top bit: signed order of the result is unsigned order of `id`.
#[inline(always)]
fn ordered(id: u32) -> i32 {
    (id ^ (1 << 31)) as i32
}

impl<F: Float> Closest<F> {
    /// Lane `i`'s closest hit so far as a [`Best`].
    #[inline(always)]
    fn best(&self, i: usize) -> Best {
        Best {
            t: self.t.lane(i),
            id: (self.id.lane(i) as u32) ^ (1 << 31),
        }
    }

    /// Records `f`, a closer hit for lane `i`.
    #[inline(always)]
    fn set(&mut self, i: usize, f: Found) {
        let m = F::M::from_bits(1 << i);
        self.t = F::select(m, F::splat(f.t), self.t);
        self.id = F::I::select(m, F::I::splat(ordered(f.id)), self.id);
        self.u = F::select(m, F::splat(f.uv.x), self.u);
        self.v = F::select(m, F::splat(f.uv.y), self.v);
        self.block = F::I::select(m, F::I::splat(f.block as i32), self.block);
        self.slot = F::I::select(m, F::I::splat(f.lane as i32), self.slot);
    }

    /// The hits found, lane by lane, into `out`, each with its shape and triangle named from
    /// `first` ([`super::bvh::hit`], in lanes where the table is short).
    #[inline(always)]
    fn write_raw(&self, first: &[u32], out: &mut [Option<RawHit>]) {
        let starts = &first[1..first.len() - 1];
        if starts.len() > SHORT_TABLE {
            let mut found = [None; MAX_LANES];
            self.write(&mut found[..out.len()]);
            for (o, f) in out.iter_mut().zip(found) {
                *o = f.map(|f| RawHit {
                    hit: super::bvh::hit(first, f),
                    block: f.block,
                    lane: f.lane,
                });
            }
            return;
        }
        // Triangles: the shape is the number of later shapes' first ids not beyond the id,
        // and the triangle the id less the last such first id (`first[0]` is 0).
        let id = self.id ^ F::I::splat(i32::MIN);
        let mut shape = F::I::splat(0);
        let mut base = F::I::splat(0);
        for &x in starts {
            // Triangle ids are below 2³¹, so a signed compare orders them.
            let m = !id.lt(F::I::splat(x as i32));
            shape = shape + F::I::select(m, F::I::splat(1), F::I::splat(0));
            base = F::I::select(m, F::I::splat(x as i32), base);
        }
        let triangle = !id.lt(F::I::splat(0));
        let shape = F::I::select(triangle, shape, id & F::I::splat(!(ANALYTIC as i32)));
        let prim = F::I::select(triangle, id - base, F::I::splat(0));
        let mut a = [[0u32; MAX_LANES]; 8];
        self.t.to_bits().store(&mut a[0][..]);
        id.store(&mut a[1][..]);
        self.u.to_bits().store(&mut a[2][..]);
        self.v.to_bits().store(&mut a[3][..]);
        self.block.store(&mut a[4][..]);
        self.slot.store(&mut a[5][..]);
        shape.store(&mut a[6][..]);
        prim.store(&mut a[7][..]);
        for (i, o) in out.iter_mut().enumerate() {
            *o = (a[1][i] != NO_HIT).then(|| RawHit {
                hit: Hit {
                    t: f32::from_bits(a[0][i]),
                    shape: a[6][i],
                    prim: a[7][i],
                    uv: Vec2::new(f32::from_bits(a[2][i]), f32::from_bits(a[3][i])),
                },
                block: a[4][i],
                lane: a[5][i],
            });
        }
    }

    /// The hits found, lane by lane, into `out`.
    #[inline(always)]
    fn write(&self, out: &mut [Option<Found>]) {
        let mut a = [[0u32; MAX_LANES]; 6];
        self.t.to_bits().store(&mut a[0][..]);
        self.id.store(&mut a[1][..]);
        self.u.to_bits().store(&mut a[2][..]);
        self.v.to_bits().store(&mut a[3][..]);
        self.block.store(&mut a[4][..]);
        self.slot.store(&mut a[5][..]);
        for (i, o) in out.iter_mut().enumerate() {
            let id = a[1][i] ^ (1 << 31);
            *o = (id != NO_HIT).then(|| Found {
                id,
                t: f32::from_bits(a[0][i]),
                uv: Vec2::new(f32::from_bits(a[2][i]), f32::from_bits(a[3][i])),
                block: a[4][i],
                lane: a[5][i],
            });
        }
    }

    /// Leaf `leaf` for the lanes of `active`.
    #[inline(always)]
    fn leaf(&mut self, v: View, shapes: &[Shape], p: &Lanes<F>, leaf: u32, active: u32) {
        let (first, n) = leaf_range(leaf);
        for (k, b) in v.blocks[first..first + n].iter().enumerate() {
            for (slot, &id) in b.ids().iter().enumerate() {
                if id == EMPTY {
                    continue;
                }
                let block = (first + k) as u32;
                if id & ANALYTIC != 0 {
                    self.analytic(shapes, p, id, block, slot, active);
                    continue;
                }
                let (hit, t, b1, b2) = p.triangle(b, slot, active, self.t);
                if hit == 0 {
                    continue;
                }
                // As `Best::takes`: closer, or as close with a lower id.
                let idl = F::I::splat(ordered(id));
                let take = hit & (t.lt(self.t) | (t.eq(self.t) & idl.lt(self.id))).bits();
                if take == 0 {
                    continue;
                }
                let m = F::M::from_bits(take);
                self.t = F::select(m, t, self.t);
                self.id = F::I::select(m, idl, self.id);
                self.u = F::select(m, b1, self.u);
                self.v = F::select(m, b2, self.v);
                self.block = F::I::select(m, F::I::splat(block as i32), self.block);
                self.slot = F::I::select(m, F::I::splat(slot as i32), self.slot);
            }
        }
    }

    /// An analytic primitive, ray by ray (its own exact test).
    #[inline(always)]
    fn analytic(
        &mut self,
        shapes: &[Shape],
        p: &Lanes<F>,
        id: u32,
        block: u32,
        slot: usize,
        active: u32,
    ) {
        let shape = &shapes[(id & !ANALYTIC) as usize];
        let mut bits = p.candidates(shape, active);
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            if let Some((t, uv)) = decide(shape, &p.ray(i)) {
                let mut best = self.best(i);
                if best.takes(t, id) {
                    self.set(
                        i,
                        Found {
                            id,
                            t,
                            uv,
                            block,
                            lane: slot as u32,
                        },
                    );
                }
            }
        }
    }

    /// Each ray of `active` alone through the subtree `node`.
    #[inline(always)]
    fn single<V: Vec8>(&mut self, v: View, shapes: &[Shape], p: &Lanes<F>, node: u32, active: u32) {
        let mut bits = active;
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let mut best = self.best(i);
            let (sr, inv) = p.single(i);
            if let Some(f) =
                traverse::closest_from::<V>(v, shapes, &p.ray(i), &sr, inv, node, &mut best)
            {
                self.set(i, f);
            }
        }
    }
}

/// A pending subtree: its reference, the rays that entered it and their entry distances.
#[derive(Clone, Copy)]
struct Entry<F> {
    node: u32,
    rays: u32,
    near: F,
}

/// [`closest`] with each hit's shape and triangle named, as [`super::Bvh::intersect_raw_n`]
/// gives them.
#[inline(always)]
pub fn closest_raw<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &[Ray],
    out: &mut [Option<RawHit>],
) {
    search::<F, V>(v, shapes, &Lanes::new(rays)).write_raw(v.first, out);
}

/// [`closest_raw`] for the rays `base .. base + out.len()` of `rays`.
#[inline(always)]
pub fn closest_raw_columns<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &RayColumns,
    base: usize,
    out: &mut [Option<RawHit>],
) {
    let p = Lanes::from_columns(rays, base, out.len());
    search::<F, V>(v, shapes, &p).write_raw(v.first, out);
}

/// The closest hits of `rays` in lanes.
#[inline(always)]
fn search<F: Float, V: Vec8>(v: View, shapes: &[Shape], p: &Lanes<F>) -> Closest<F> {
    let mut c = Closest::<F> {
        t: p.t_max,
        id: F::I::splat(ordered(NO_HIT)),
        u: F::splat(0.0),
        v: F::splat(0.0),
        block: F::I::splat(0),
        slot: F::I::splat(0),
    };
    if v.root != super::wide::EMPTY_CHILD && p.valid != 0 {
        walk::<F, V>(v, shapes, p, &mut c);
    }
    c
}

/// The closest hits of `rays` (at most `F::LANES`): `out[i]` for `rays[i]`, the same as
/// [`traverse::closest`] gives ray by ray.
#[inline(always)]
pub fn closest<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &[Ray],
    out: &mut [Option<Found>],
) {
    search::<F, V>(v, shapes, &Lanes::new(rays)).write(out);
}

#[inline(always)]
fn walk<F: Float, V: Vec8>(v: View, shapes: &[Shape], p: &Lanes<F>, c: &mut Closest<F>) {
    let mut stack = [const { MaybeUninit::<Entry<F>>::uninit() }; STACK];
    let mut sp = 0usize;
    let (mut cur, mut active) = (v.root, p.valid);
    loop {
        if active.count_ones()
            <= if cur & LEAF != 0 {
                SWITCH_LEAF
            } else {
                SWITCH_NODE
            }
        {
            c.single::<V>(v, shapes, p, cur, active);
        } else if cur & LEAF != 0 {
            c.leaf(v, shapes, p, cur, active);
        } else {
            let node = &v.nodes[cur as usize];
            // The children entered, sorted far first by the entry of their first ray (keys
            // of entry bits and child lane; the entries' lanes stay where they were stored).
            let mut near = [[0.0f32; MAX_LANES]; 8];
            let mut rays = [0u32; 8];
            let mut keys = [0u64; 8];
            let mut n = 0;
            for lane in 0..8 {
                if node.child[lane] == super::wide::EMPTY_CHILD {
                    continue;
                }
                let (lo, hi) = node.corners(lane);
                let (t, m) = p.enter(lo, hi, c.t, active);
                if m == 0 {
                    continue;
                }
                t.store(&mut near[lane][..]);
                rays[lane] = m;
                let key = ((near[lane][m.trailing_zeros() as usize].to_bits() as u64) << 32)
                    | lane as u64;
                let mut j = n;
                while j > 0 && keys[j - 1] < key {
                    keys[j] = keys[j - 1];
                    j -= 1;
                }
                keys[j] = key;
                n += 1;
            }
            if n > 0 {
                for &key in &keys[..n - 1] {
                    let lane = (key & 7) as usize;
                    stack[sp].write(Entry {
                        node: node.child[lane],
                        rays: rays[lane],
                        near: F::load(&near[lane]),
                    });
                    sp += 1;
                }
                let lane = (keys[n - 1] & 7) as usize;
                (cur, active) = (node.child[lane], rays[lane]);
                continue;
            }
        }
        loop {
            if sp == 0 {
                return;
            }
            sp -= 1;
            // SAFETY: slots below the old `sp` were all written by a push.
            let e = unsafe { stack[sp].assume_init() };
            // Widened as in `traverse`: an entry rounding just past an equally close hit may
            // still hold a tie.
            let keep = e.near.le(c.t * F::splat(widen(1.0))).bits() & e.rays;
            if keep != 0 {
                (cur, active) = (e.node, keep);
                break;
            }
        }
    }
}

/// [`any`] for the rays `base .. base + out.len()` of `rays`.
#[inline(always)]
pub fn any_columns<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &RayColumns,
    base: usize,
    out: &mut [bool],
) {
    occlusion::<F, V>(v, shapes, &Lanes::from_columns(rays, base, out.len()), out);
}

/// Occlusion of `rays` (at most `F::LANES`): `out[i]` for `rays[i]`, the same as
/// [`traverse::any`] gives ray by ray.
#[inline(always)]
pub fn any<F: Float, V: Vec8>(v: View, shapes: &[Shape], rays: &[Ray], out: &mut [bool]) {
    occlusion::<F, V>(v, shapes, &Lanes::new(rays), out);
}

/// Occlusion of the packet `p` into `out`.
#[inline(always)]
fn occlusion<F: Float, V: Vec8>(v: View, shapes: &[Shape], p: &Lanes<F>, out: &mut [bool]) {
    let mut blocked = 0u32;
    if v.root != super::wide::EMPTY_CHILD && p.valid != 0 {
        blocked = any_walk::<F, V>(v, shapes, p);
    }
    for (i, o) in out.iter_mut().enumerate() {
        *o = blocked & (1 << i) != 0;
    }
}

#[inline(always)]
fn any_walk<F: Float, V: Vec8>(v: View, shapes: &[Shape], p: &Lanes<F>) -> u32 {
    let mut stack = [const { MaybeUninit::<(u32, u32)>::uninit() }; STACK];
    let mut sp = 0usize;
    let mut blocked = 0u32;
    let (mut cur, mut active) = (v.root, p.valid);
    let inf = F::splat(f32::INFINITY);
    loop {
        if active.count_ones()
            <= if cur & LEAF != 0 {
                SWITCH_LEAF
            } else {
                SWITCH_NODE
            }
        {
            let mut bits = active;
            while bits != 0 {
                let i = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let (sr, inv) = p.single(i);
                if traverse::any_from::<V>(v, shapes, &p.ray(i), &sr, inv, cur) {
                    blocked |= 1 << i;
                }
            }
        } else if cur & LEAF != 0 {
            let (first, n) = leaf_range(cur);
            'blocks: for b in &v.blocks[first..first + n] {
                for (slot, &id) in b.ids().iter().enumerate() {
                    if id == EMPTY {
                        continue;
                    }
                    let hit = if id & ANALYTIC != 0 {
                        any_analytic(&shapes[(id & !ANALYTIC) as usize], p, active)
                    } else {
                        p.triangle(b, slot, active, inf).0
                    };
                    blocked |= hit;
                    active &= !hit;
                    if active == 0 {
                        break 'blocks;
                    }
                }
            }
        } else {
            let node = &v.nodes[cur as usize];
            let mut next = None;
            for lane in 0..8 {
                let child = node.child[lane];
                if child == super::wide::EMPTY_CHILD {
                    continue;
                }
                let (lo, hi) = node.corners(lane);
                let (_, rays) = p.enter(lo, hi, p.t_max, active);
                if rays == 0 {
                    continue;
                }
                match next {
                    None => next = Some((child, rays)),
                    Some(_) => {
                        stack[sp].write((child, rays));
                        sp += 1;
                    }
                }
            }
            if let Some((child, rays)) = next {
                (cur, active) = (child, rays);
                continue;
            }
        }
        loop {
            if sp == 0 || blocked == p.valid {
                return blocked;
            }
            sp -= 1;
            // SAFETY: slots below the old `sp` were all written by a push.
            let (node, rays) = unsafe { stack[sp].assume_init() };
            let keep = rays & !blocked;
            if keep != 0 {
                (cur, active) = (node, keep);
                break;
            }
        }
    }
}

/// The lanes of `active` whose ray hits the analytic primitive `shape`, ray by ray.
#[inline(always)]
fn any_analytic<F: Float>(shape: &Shape, p: &Lanes<F>, active: u32) -> u32 {
    let mut hit = 0;
    let mut bits = p.candidates(shape, active);
    while bits != 0 {
        let i = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        if decide(shape, &p.ray(i)).is_some() {
            hit |= 1 << i;
        }
    }
    hit
}

#[cfg(test)]
#[path = "packet_tests.rs"]
mod tests;

/// An analytic primitive's own test for a ray that passed [`Lanes::candidates`].
#[inline]
fn decide(shape: &Shape, ray: &Ray) -> Option<(f32, Vec2)> {
    match shape {
        Shape::Sphere(s) => s.intersect_exact(ray),
        s => s.intersect_prim(0, ray),
    }
}
