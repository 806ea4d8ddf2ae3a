//! Analytic cylinder (Mitsuba's `cylinder`): the side surface of a circular cylinder, open at
//! both ends (no caps, as in Mitsuba).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `p0` | point | (0, 0, 0) | object space | start of the axis |
//! | `p1` | point | (0, 0, 1) | object space | end of the axis |
//! | `radius` | float | 1.0 | object space | radius; positive |
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |
//!
//! Local frame (as Mitsuba 3): the unit cylinder x² + y² = 1, 0 ≤ z ≤ 1, placed by
//! `to_world · translate(p0) · frame(p1 − p0) · scale(r, r, |p1 − p0|)`, where `frame(d)` has z
//! along d and x, y from the branchless orthonormal basis of Duff et al., "Building an
//! Orthonormal Basis, Revisited", JCGT 6(1), 2017 ([`Frame::from_z`]) — the same basis Mitsuba
//! uses, so that texture coordinates agree: u = φ/2π with φ = atan2(y, x) in [0, 2π), v = z.
//! dp/du = 2π·(−y, x, 0) and dp/dv = (0, 0, 1), mapped to the world.
//!
//! Intersection solves the quadratic of the infinite cylinder in local space, in f64 with the
//! cancellation-free discriminant (as for the sphere, Haines et al. 2019), and keeps the
//! nearest root whose height lies in [0, 1]; the hit is re-projected onto the surface.
//!
//! Direct sampling picks a point uniformly by area (u ↦ height, φ) and converts to solid angle;
//! points facing away or hidden by the cylinder itself are left to the shadow ray.
//!
//! Limits: `to_world` must keep the cross-section circular and the axis perpendicular to it
//! (Mitsuba only warns; ophis refuses, since area sampling would be wrong).
use super::{area_to_solid_angle, Hit, ShapeError, ShapeSample, SurfaceInteraction};
use crate::math::{Bounds3, Frame, Mat4, Ray, Transform, Vec2, Vec3, INV_2PI, PI};
use crate::plugin::{declare, Args, Param, SceneError};
use glam::{DVec2, DVec3};

declare!(PLUGIN: super::Parts, Transform = Shape "cylinder" []
    "analytic cylinder side, open at both ends"
    [&[
        Param::object_point("p0", [0.0, 0.0, 0.0])
            .doc("start of the axis"),
        Param::object_point("p1", [0.0, 0.0, 1.0])
            .doc("end of the axis"),
        super::RADIUS,
    ], super::PLACEMENT] load);

fn load(a: &mut Args, parent: Transform) -> Result<super::Parts, SceneError> {
    let (to_world, flip) = super::placement(a, &parent)?;
    let p0 = a.point("p0")?;
    let p1 = a.point("p1")?;
    let radius = a.float("radius")?;
    super::one(
        a,
        Cylinder::new(p0, p1, radius, &to_world, flip).map(super::Shape::Cylinder),
    )
}

/// A cylinder in world space.
#[derive(Clone, Debug)]
pub struct Cylinder {
    /// Unit cylinder → world.
    pub to_world: Transform,
    pub flip_normals: bool,
    /// World radius and length.
    pub radius: f32,
    pub length: f32,
}

impl Cylinder {
    /// A cylinder from Mitsuba's parameters.
    pub fn new(
        p0: Vec3,
        p1: Vec3,
        radius: f32,
        to_world: &Transform,
        flip_normals: bool,
    ) -> Result<Cylinder, ShapeError> {
        let bad = || ShapeError::BadTransform { shape: "cylinder" };
        if !super::positive_finite(radius) {
            return Err(ShapeError::BadRadius {
                shape: "cylinder",
                radius,
            });
        }
        let d = p1 - p0;
        let len = d.length();
        if !super::positive_finite(len) {
            return Err(ShapeError::BadTransform { shape: "cylinder" });
        }
        let f = Frame::from_z(d / len);
        let frame = Mat4::from_cols(
            f.s.extend(0.0),
            f.t.extend(0.0),
            f.n.extend(0.0),
            p0.extend(1.0),
        );
        let local = Transform::new(frame * Mat4::from_scale(Vec3::new(radius, radius, len)))
            .ok_or_else(bad)?;
        let m = to_world.compose(&local);
        let (ex, ey, ez) = (m.vector(Vec3::X), m.vector(Vec3::Y), m.vector(Vec3::Z));
        let (r, l) = (ex.length(), ez.length());
        if !(super::positive_finite(r) && super::positive_finite(l) && m.m.is_finite()) {
            return Err(bad());
        }
        // The cross-section must stay a circle (x, y images orthogonal, equally long) and the
        // axis perpendicular to it.
        let tol = 1e-4;
        let ortho =
            ex.dot(ey).abs() / (r * r) + ex.dot(ez).abs() / (r * l) + ey.dot(ez).abs() / (r * l);
        if (ey.length() - r).abs() > tol * r || ortho > tol {
            return Err(ShapeError::NonUniformScale {
                shape: "cylinder",
                scales: [r, ey.length(), l],
            });
        }
        Ok(Cylinder {
            to_world: m,
            flip_normals,
            radius: r,
            length: l,
        })
    }

    /// World-space bounds: the box around the two end circles.
    pub fn bounds(&self) -> Bounds3 {
        let ex = self.to_world.vector(Vec3::X);
        let ey = self.to_world.vector(Vec3::Y);
        let half = (ex * ex + ey * ey).powf(0.5);
        let a = self.to_world.point(Vec3::ZERO);
        let b = self.to_world.point(Vec3::Z);
        Bounds3 {
            min: a.min(b) - half,
            max: a.max(b) + half,
        }
    }

    /// Nearest intersection with parameter in (0, ray.t_max); the uv is unused (zero).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<(f32, Vec2)> {
        let inv = self.to_world.inv.as_dmat4();
        // An affine map keeps ray parameters when the direction is mapped unnormalised.
        let o = inv.transform_point3(ray.o.as_dvec3());
        let d = inv.transform_vector3(ray.d.as_dvec3());
        let (f, g) = (DVec2::new(o.x, o.y), DVec2::new(d.x, d.y));
        let a = g.length_squared();
        if a == 0.0 {
            return None; // along the axis: the side is never crossed
        }
        let b = f.dot(g);
        let c = f.length_squared() - 1.0;
        // b² − ac as a·(1 − |f − (b/a) g|²): no cancellation for distant origins.
        let l = f - (b / a) * g;
        let disc = a * (1.0 - l.length_squared());
        let (t0, t1) = super::quadratic_roots(a, b, c, disc)?;
        let t_max = ray.t_max as f64;
        [t0, t1]
            .into_iter()
            .find(|&t| {
                let z = o.z + t * d.z;
                t > 0.0 && t < t_max && (0.0..=1.0).contains(&z)
            })
            .map(|t| (t as f32, Vec2::ZERO))
    }

    /// The local point (on the unit surface) of a hit.
    fn local_hit(&self, hit: &Hit, ray: &Ray) -> DVec3 {
        let p = ray.o.as_dvec3() + ray.d.as_dvec3() * hit.t as f64;
        let q = self.to_world.inv.as_dmat4().transform_point3(p);
        let r = (q.x * q.x + q.y * q.y).sqrt();
        let (x, y) = if r > 0.0 {
            (q.x / r, q.y / r)
        } else {
            (1.0, 0.0)
        };
        DVec3::new(x, y, q.z.clamp(0.0, 1.0))
    }

    /// Surface geometry at a hit found by [`Cylinder::intersect`].
    pub fn interaction(&self, hit: &Hit, ray: &Ray) -> SurfaceInteraction {
        let local = self.local_hit(hit, ray).as_vec3();
        let (p, n, uv, dpdu, dpdv) = self.at_local(local);
        SurfaceInteraction {
            p,
            t: hit.t,
            ng: n,
            ns: n,
            uv,
            dpdu,
            dpdv,
            shape: hit.shape,
            prim: hit.prim,
        }
    }

    /// World point, normal (after `flip_normals`), uv and tangents of a local surface point.
    fn at_local(&self, q: Vec3) -> (Vec3, Vec3, Vec2, Vec3, Vec3) {
        let mut phi = q.y.atan2(q.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let uv = Vec2::new((phi * INV_2PI).min(crate::math::ONE_MINUS_EPSILON), q.z);
        let dpdu = self.to_world.vector(Vec3::new(-q.y, q.x, 0.0) * (2.0 * PI));
        let dpdv = self.to_world.vector(Vec3::Z);
        let out = self
            .to_world
            .normal(Vec3::new(q.x, q.y, 0.0))
            .normalize_or_zero();
        let n = if self.flip_normals { -out } else { out };
        (self.to_world.point(q), n, uv, dpdu, dpdv)
    }

    /// Surface area 2π r L.
    pub fn area(&self) -> f32 {
        2.0 * PI * self.radius * self.length
    }

    /// Samples a point uniformly by area, with its density in solid angle seen from `ref_p`.
    pub(crate) fn sample_direct(&self, ref_p: Vec3, u: Vec2) -> Option<ShapeSample> {
        let (s, c) = (2.0 * PI * u.y).sin_cos();
        let (p, n, uv, _, _) = self.at_local(Vec3::new(c, s, u.x));
        let pdf = area_to_solid_angle(1.0 / self.area(), ref_p, p, n);
        super::positive_finite(pdf).then_some(ShapeSample { p, n, uv, pdf })
    }

    /// Solid-angle density of [`Cylinder::sample_direct`] choosing `p` (normal `n`) from `ref_p`.
    pub(crate) fn pdf_direct(&self, ref_p: Vec3, p: Vec3, n: Vec3) -> f32 {
        area_to_solid_angle(1.0 / self.area(), ref_p, p, n)
    }
}

#[cfg(test)]
#[path = "cylinder_tests.rs"]
mod tests;
