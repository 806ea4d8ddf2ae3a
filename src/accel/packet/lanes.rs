//! A packet's rays in lanes ([`Lanes`]), with the per-ray constants of the box and triangle
//! tests computed once, and the tests themselves: a box against every ray, a triangle against
//! every ray (the watertight test of [`crate::accel::block`], operation for operation), the
//! spheres' pre-test.
use super::MAX_LANES;
use crate::accel::block::Block;
use crate::math::{Ray, Vec2, Vec3};
use crate::shape::mesh::{edge_f64, gamma, ShearedRay};
use crate::shape::Shape;
use crate::simd::{Float, Mask};

/// `a < b ? a : b` lane by lane (the box test's min, as [`crate::accel::simd::Vec8::min`]).
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
    /// Panics unless every column holds the `n` rays.
    pub fn check(&self) {
        let short =
            self.o.iter().chain(&self.d).any(|c| c.len() < self.n) || self.t_max.len() < self.n;
        assert!(!short, "ray columns shorter than their {} rays", self.n);
    }

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
pub(super) struct Lanes<F: Float> {
    /// Rows: origin x, y, z, extent, direction x, y, z, per lane (for rays that go on alone).
    row: [[f32; MAX_LANES]; 7],
    /// Lanes holding a ray that can hit anything (a nonzero direction).
    pub(super) valid: u32,
    o: [F; 3],
    d: [F; 3],
    inv_d: [F; 3],
    /// The rays' own extents.
    pub(super) t_max: F,
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
    pub(super) fn new(rays: &[Ray]) -> Lanes<F> {
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
    pub(super) fn from_columns(c: &RayColumns, base: usize, count: usize) -> Lanes<F> {
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
    pub(super) fn candidates(&self, shape: &Shape, active: u32) -> u32 {
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
    pub(super) fn ray(&self, i: usize) -> Ray {
        let a = &self.row;
        Ray {
            o: Vec3::new(a[0][i], a[1][i], a[2][i]),
            d: Vec3::new(a[4][i], a[5][i], a[6][i]),
            t_max: a[3][i],
        }
    }

    /// Lane `i`'s shear and reciprocal direction, for [`traverse`]'s single-ray loops.
    #[inline(always)]
    pub(super) fn single(&self, i: usize) -> (ShearedRay, Vec3) {
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
    pub(super) fn enter(&self, lo: [f32; 3], hi: [f32; 3], t_max: F, active: u32) -> (F, u32) {
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
    pub(super) fn triangle(&self, b: &Block, slot: usize, active: u32, best: F) -> (u32, F, F, F) {
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

/// An analytic primitive's own test for a ray that passed [`Lanes::candidates`].
#[inline]
pub(super) fn decide(shape: &Shape, ray: &Ray) -> Option<(f32, Vec2)> {
    match shape {
        Shape::Sphere(s) => s.intersect_exact(ray),
        s => s.intersect_prim(0, ray),
    }
}
