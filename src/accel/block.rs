//! Leaf storage: blocks of four primitive slots, triangles tested four at a time.
//!
//! A [`Block`] holds the world-space corners of up to four triangles in structure-of-arrays
//! form (`p[corner][axis][lane]`) and one id per lane: a triangle's global primitive id, an
//! analytic primitive (sphere, disk: [`ANALYTIC`] | shape index, tested by the shape's own code),
//! or [`EMPTY`] padding. A leaf is a run of consecutive blocks.
//!
//! The four triangles are tested with the watertight test of Woop, Benthin and Wald,
//! "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013, lane by lane exactly as the scalar
//! [`crate::shape::mesh::intersect_watertight_sheared`] does it: the same operations in the same
//! order, so a triangle gives bit-for-bit the same t and barycentrics in either. That includes
//! the f64 redo of edge functions that round to zero, and the rejection of hits closer than the
//! rounding error of t (see the scalar test). The SIMD pass decides, against the ray's own
//! range, which triangles are candidates, and keeps those not beyond the closest hit so far;
//! [`Block::closest`] then takes the first of them in (parameter, id) order ([`Best`]), so the
//! closest hit is the same whatever order the traversal meets the blocks in.
use super::simd::{max_bits, sign_bits, F4};
use crate::math::{Ray, Vec2, Vec3};
use crate::shape::mesh::{edge_f64, gamma, ShearedRay};
use crate::shape::Shape;

/// Lane id of padding.
pub const EMPTY: u32 = u32::MAX;
/// Flag of a lane holding an analytic primitive; the low bits are its shape index.
pub const ANALYTIC: u32 = 1 << 31;

/// Four primitive slots; see the module header.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Block {
    p: [[[f32; 4]; 3]; 3],
    id: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<Block>() == 160);

impl Block {
    /// A block from four slots: `(id, corners)`; corners are ignored for non-triangle ids.
    pub fn new(slots: [(u32, [Vec3; 3]); 4]) -> Block {
        let mut b = Block {
            p: [[[0.0; 4]; 3]; 3],
            id: [EMPTY; 4],
        };
        // Non-triangle lanes repeat a triangle's corners so that no lane computes with zeros
        // (which would send it down the f64 edge path) before the lane mask is applied.
        let fill = slots
            .iter()
            .find(|s| s.0 & ANALYTIC == 0)
            .map_or([Vec3::ONE, Vec3::X, Vec3::Y], |s| s.1);
        for (lane, (id, corners)) in slots.into_iter().enumerate() {
            let c = if id & ANALYTIC == 0 { corners } else { fill };
            for (k, v) in c.iter().enumerate() {
                for a in 0..3 {
                    b.p[k][a][lane] = v[a];
                }
            }
            b.id[lane] = id;
        }
        b
    }

    /// Lane ids.
    #[inline(always)]
    pub fn ids(&self) -> [u32; 4] {
        self.id
    }

    /// The corners stored in lane `lane` (a triangle lane's are its mesh's vertices, bit for
    /// bit).
    #[inline]
    pub fn corners(&self, lane: usize) -> [Vec3; 3] {
        [0, 1, 2].map(|k| Vec3::new(self.p[k][0][lane], self.p[k][1][lane], self.p[k][2][lane]))
    }

    /// Corner `k` of the triangle in lane `lane`, as x, y, z.
    #[inline(always)]
    pub fn corner(&self, k: usize, lane: usize) -> [f32; 3] {
        [self.p[k][0][lane], self.p[k][1][lane], self.p[k][2][lane]]
    }

    /// Lanes holding triangles, as bits: those whose id has the top bit clear.
    #[inline(always)]
    fn triangles(&self) -> u32 {
        !sign_bits(&self.id) & 0xf
    }

    /// Lanes holding analytic primitives, as bits.
    #[inline(always)]
    fn analytic(&self) -> u32 {
        sign_bits(&self.id) & !max_bits(&self.id)
    }

    /// Corner `k` relative to the ray origin, in the permuted axes.
    #[inline(always)]
    fn relative(&self, k: usize, r: &RayLanes) -> (F4, F4, F4) {
        let [kx, ky, kz] = r.k;
        (
            F4::load(&self.p[k][kx]) - r.o[0],
            F4::load(&self.p[k][ky]) - r.o[1],
            F4::load(&self.p[k][kz]) - r.o[2],
        )
    }

    /// The SIMD part of the watertight test against `t_max`; `None` when no triangle lane is
    /// hit.
    #[inline(always)]
    fn test(&self, r: &RayLanes, t_max: f32, best: f32) -> Option<Lanes> {
        let tri = self.triangles();
        // An analytic primitive has a leaf of its own (see `build::split`): its block has
        // nothing for the lanes to test.
        if tri == 0 {
            return None;
        }
        let zero = F4::splat(0.0);
        let (a0, a1, a2) = self.relative(0, r);
        let (b0, b1, b2) = self.relative(1, r);
        let (c0, c1, c2) = self.relative(2, r);
        let (sx, sy, sz) = (r.s[0], r.s[1], r.s[2]);
        let (ax, ay) = (a0 - sx * a2, a1 - sy * a2);
        let (bx, by) = (b0 - sx * b2, b1 - sy * b2);
        let (cx, cy) = (c0 - sx * c2, c1 - sy * c2);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        let on_edge = (u.eq(zero) | v.eq(zero) | w.eq(zero)).bits() & tri;
        if on_edge != 0 {
            (u, v, w) = redo_edges(on_edge, [ax, ay, bx, by, cx, cy], [u, v, w]);
        }
        let mixed = (u.lt(zero) | v.lt(zero) | w.lt(zero)) & (u.gt(zero) | v.gt(zero) | w.gt(zero));
        // Most blocks a ray reaches miss all their triangles: stop before the t computation.
        let inside = tri & !mixed.bits();
        if inside == 0 {
            return None;
        }
        let det = u + v + w;
        let (az, bz, cz) = (sz * a2, sz * b2, sz * c2);
        let t_scaled = u * az + v * bz + w * cz;
        let tmd = F4::splat(t_max) * det;
        let in_range = (det.lt(zero) & t_scaled.lt(zero) & t_scaled.gt(tmd))
            | (det.gt(zero) & t_scaled.gt(zero) & t_scaled.lt(tmd));
        let inv = F4::splat(1.0) / det;
        let t = t_scaled * inv;
        let t_ok = t.gt(zero) & t.lt(F4::splat(t_max));
        // The forward error bound of t (see the scalar test), lane by lane.
        let max_zt = az.abs().max(bz.abs()).max(cz.abs());
        let max_xt = ax.abs().max(bx.abs()).max(cx.abs());
        let max_yt = ay.abs().max(by.abs()).max(cy.abs());
        let (g2, g3, g5) = (
            F4::splat(gamma(2)),
            F4::splat(gamma(3)),
            F4::splat(gamma(5)),
        );
        let delta_z = g3 * max_zt;
        let delta_x = g5 * (max_xt + max_zt);
        let delta_y = g5 * (max_yt + max_zt);
        let delta_e = F4::splat(2.0) * (g2 * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = u.abs().max(v.abs()).max(w.abs());
        let delta_t =
            F4::splat(3.0) * (g3 * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv.abs();
        let beyond_error = t.gt(delta_t);
        let first = t.le(F4::splat(best));
        let hit = (in_range & t_ok & beyond_error & first).bits() & inside;
        Some(Lanes { hit, t, v, w, inv })
    }

    /// Closest-hit test of the four slots: a slot is a candidate when its primitive is hit
    /// within the ray's own range (0, `ray.t_max`), and a candidate replaces `best` when it is
    /// closer, or as close with a lower id (see [`Best`]). Returns the lane and hit coordinates
    /// of the last replacement, if any.
    #[inline(always)]
    pub fn closest(
        &self,
        r: &RayLanes,
        ray: &Ray,
        best: &mut Best,
        shapes: &[Shape],
    ) -> Option<(usize, Vec2)> {
        let lanes = self.test(r, ray.t_max, best.t);
        let analytic = self.analytic();
        let hit = lanes.as_ref().map_or(0, |l| l.hit);
        let mut todo = hit | analytic;
        if todo == 0 {
            return None;
        }
        let mut found = None;
        // The hit lanes' values, stored once.
        let arrays = lanes.map(|l| {
            (
                l.t.to_array(),
                l.v.to_array(),
                l.w.to_array(),
                l.inv.to_array(),
            )
        });
        while todo != 0 {
            let l = todo.trailing_zeros() as usize;
            todo &= todo - 1;
            let id = self.id[l];
            if analytic & (1 << l) != 0 {
                let shape = &shapes[(id & !ANALYTIC) as usize];
                if let Some((t, uv)) = shape.intersect_prim(0, ray) {
                    if best.takes(t, id) {
                        found = Some((l, uv));
                    }
                }
                continue;
            }
            let Some((t, v, w, inv)) = &arrays else {
                continue;
            };
            if best.takes(t[l], id) {
                found = Some((l, Vec2::new(v[l] * inv[l], w[l] * inv[l])));
            }
        }
        found
    }

    /// Whether any slot is hit in (0, ray.t_max).
    #[inline(always)]
    pub fn any(&self, r: &RayLanes, ray: &Ray, shapes: &[Shape]) -> bool {
        if self
            .test(r, ray.t_max, f32::INFINITY)
            .is_some_and(|l| l.hit != 0)
        {
            return true;
        }
        let mut analytic = self.analytic();
        while analytic != 0 {
            let l = analytic.trailing_zeros() as usize;
            analytic &= analytic - 1;
            let shape = &shapes[(self.id[l] & !ANALYTIC) as usize];
            if shape.intersect_prim(0, ray).is_some() {
                return true;
            }
        }
        false
    }
}

/// The closest hit so far of one ray: its parameter (the ray's `t_max` before any hit) and
/// lane id ([`NO_HIT`] before any hit). Hits are ordered by parameter, then by id, so the
/// closest hit is one primitive whatever order a traversal meets them in (two triangles can
/// be hit at exactly the same parameter, e.g. on a shared edge).
#[derive(Clone, Copy, Debug)]
pub struct Best {
    pub t: f32,
    pub id: u32,
}

/// [`Best::id`] before any hit.
pub const NO_HIT: u32 = u32::MAX;

impl Best {
    /// Nothing hit yet within (0, t_max).
    #[inline(always)]
    pub fn new(t_max: f32) -> Best {
        Best {
            t: t_max,
            id: NO_HIT,
        }
    }

    /// Replaces the best hit by a candidate at `t` with lane id `id` if it comes first;
    /// returns whether it did.
    #[inline(always)]
    pub fn takes(&mut self, t: f32, id: u32) -> bool {
        if t < self.t || (t == self.t && id < self.id) {
            (self.t, self.id) = (t, id);
            true
        } else {
            false
        }
    }
}

/// `t` a few ulps larger: a pruning bound that rounding cannot undercut (a box's entry
/// distance may round just past a hit inside it).
#[inline(always)]
pub fn widen(t: f32) -> f32 {
    t * (1.0 + 4.0 * f32::EPSILON)
}

/// The f64 redo of the edge functions in the lanes of `on_edge` (see the scalar test).
#[cold]
#[inline(never)]
fn redo_edges(on_edge: u32, s: [F4; 6], uvw: [F4; 3]) -> (F4, F4, F4) {
    let [ax, ay, bx, by, cx, cy] = s.map(F4::to_array);
    let [mut u, mut v, mut w] = uvw.map(F4::to_array);
    let mut m = on_edge;
    while m != 0 {
        let l = m.trailing_zeros() as usize;
        m &= m - 1;
        u[l] = edge_f64(cx[l], by[l], cy[l], bx[l]);
        v[l] = edge_f64(ax[l], cy[l], ay[l], cx[l]);
        w[l] = edge_f64(bx[l], ay[l], by[l], ax[l]);
    }
    (F4::from_array(u), F4::from_array(v), F4::from_array(w))
}

/// Per-lane results of [`Block::test`].
struct Lanes {
    hit: u32,
    t: F4,
    v: F4,
    w: F4,
    inv: F4,
}

/// The per-ray part of the block test: the watertight test's axis permutation and shear, with
/// the origin's permuted components, splatted to four lanes.
#[derive(Clone, Copy, Debug)]
pub struct RayLanes {
    k: [usize; 3],
    o: [F4; 3],
    s: [F4; 3],
}

impl RayLanes {
    #[inline(always)]
    pub fn new(ray: &Ray, sr: &ShearedRay) -> RayLanes {
        RayLanes {
            k: [sr.kx, sr.ky, sr.kz],
            o: {
                let o = ray.o.to_array();
                [
                    F4::splat(o[sr.kx]),
                    F4::splat(o[sr.ky]),
                    F4::splat(o[sr.kz]),
                ]
            },
            s: [F4::splat(sr.sx), F4::splat(sr.sy), F4::splat(sr.sz)],
        }
    }
}

#[cfg(test)]
#[path = "block_tests.rs"]
mod tests;
