//! Analytic sphere.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `center` | point | (0, 0, 0) | object space | centre |
//! | `radius` | float | 1.0 | object space | radius; positive |
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |
//!
//! The transform is folded into a world-space centre and radius; its rotation is kept so that
//! texture coordinates turn with the sphere.
//!
//! UV convention (as Mitsuba 3): in the sphere's local frame, with the unit vector q from the
//! centre to the hit point, u = φ/(2π) with φ = atan2(q.y, q.x) wrapped to [0, 2π), and
//! v = θ/π with θ = acos(q.z). dp/du and dp/dv are the derivatives of that map; at the poles,
//! where dp/du vanishes, an arbitrary tangent frame is used instead.
//!
//! Intersection solves the quadratic in f64 with the cancellation-free form of the discriminant
//! (Haines et al., "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems, 2019);
//! the hit point is re-projected onto the sphere.
//!
//! Direct sampling: from outside, directions are sampled uniformly in the cone the sphere
//! subtends; from inside (or on) the sphere, points are sampled uniformly by area.
//!
//! Limits: non-uniform scale and shear are rejected (a sphere would become an ellipsoid).
use super::{area_to_solid_angle, Hit, ShapeError, ShapeSample, SurfaceInteraction};
use crate::math::{
    safe_sqrt, warp, Bounds3, Frame, Mat3, Ray, Transform, Vec2, Vec3, INV_2PI, INV_PI, PI,
};
use crate::plugin::{declare, Args, Param, SceneError};
use glam::DVec3;

declare!(PLUGIN: super::Parts, Transform = Shape "sphere" []
    "analytic sphere"
    [&[
        Param::object_point("center", [0.0, 0.0, 0.0])
            .doc("centre"),
        super::RADIUS,
    ], super::PLACEMENT] load);

fn load(a: &mut Args, parent: Transform) -> Result<super::Parts, SceneError> {
    let (to_world, flip) = super::placement(a, &parent)?;
    let center = a.point("center")?;
    let radius = a.float("radius")?;
    super::one(
        a,
        Sphere::new(center, radius, &to_world, flip).map(super::Shape::Sphere),
    )
}

/// A sphere in world space.
#[derive(Clone, Debug)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    pub flip_normals: bool,
    /// Local-to-world rotation (orthonormal columns; may include a mirror).
    pub rotation: Mat3,
}

impl Sphere {
    /// A sphere from Mitsuba's parameters; `to_world` must be a similarity transform.
    pub fn new(
        center: Vec3,
        radius: f32,
        to_world: &Transform,
        flip_normals: bool,
    ) -> Result<Sphere, ShapeError> {
        if !super::positive_finite(radius) {
            return Err(ShapeError::BadRadius {
                shape: "sphere",
                radius,
            });
        }
        let lin = Mat3::from_mat4(to_world.m);
        let scales = [
            lin.x_axis.length(),
            lin.y_axis.length(),
            lin.z_axis.length(),
        ];
        if !lin.is_finite() || scales.iter().any(|&s| !super::positive_finite(s)) {
            return Err(ShapeError::BadTransform { shape: "sphere" });
        }
        let s = scales[0];
        // A similarity has equal axis lengths and orthogonal axes.
        let tol = 1e-4 * s;
        let ortho = lin.x_axis.dot(lin.y_axis).abs()
            + lin.y_axis.dot(lin.z_axis).abs()
            + lin.z_axis.dot(lin.x_axis).abs();
        if (scales[1] - s).abs() > tol || (scales[2] - s).abs() > tol || ortho > tol * s {
            return Err(ShapeError::NonUniformScale {
                shape: "sphere",
                scales,
            });
        }
        Ok(Sphere {
            center: to_world.point(center),
            radius: radius * s,
            flip_normals,
            rotation: lin * (1.0 / s),
        })
    }

    /// A sphere with an identity rotation.
    pub fn simple(center: Vec3, radius: f32) -> Sphere {
        Sphere {
            center,
            radius,
            flip_normals: false,
            rotation: Mat3::IDENTITY,
        }
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        let r = Vec3::splat(self.radius);
        Bounds3 {
            min: self.center - r,
            max: self.center + r,
        }
    }

    /// Nearest intersection with parameter in (0, ray.t_max); the returned uv is unused (zero).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<(f32, Vec2)> {
        // Most rays that reach a sphere's bounds pass beside it: a conservative test in f32
        // first. The line's distance to the centre, |l|, is computed with an error of a few
        // ulps of |f|, far inside the margin, so no ray the exact test below hits is dropped.
        let f32_f = ray.o - self.center;
        // For a unit direction (every ray the integrators spawn, to a few ulps) the division
        // by |d|² changes b by less than 1e-6·|f|, which moves |l|² by less than 3e-6·|f|²:
        // inside the margin, so it is skipped (a division is most of this test's latency).
        let dd = ray.d.length_squared();
        let fd = f32_f.dot(ray.d);
        let b = if (dd - 1.0).abs() < 1e-6 { fd } else { fd / dd };
        let l = f32_f - ray.d * b;
        let r2 = self.radius * self.radius;
        if l.length_squared() > r2 * 1.001 + 1e-5 * f32_f.length_squared() {
            return None;
        }
        self.intersect_exact(ray)
    }

    /// [`Sphere::intersect`] without its pre-test: the root of the quadratic in f64. (Any
    /// conservative pre-test gives the same answers: it only drops rays this misses.)
    pub(crate) fn intersect_exact(&self, ray: &Ray) -> Option<(f32, Vec2)> {
        let f = ray.o.as_dvec3() - self.center.as_dvec3();
        let d = ray.d.as_dvec3();
        let r = self.radius as f64;
        let a = d.length_squared();
        let b = f.dot(d); // half of the usual b
        let c = f.length_squared() - r * r;
        // From outside or on the sphere (c ≥ 0) moving away from its centre (b ≥ 0) both roots
        // are ≤ 0: q below is ≤ 0, so c / q ≤ 0 and q / a ≤ 0, and the code below would
        // return `None` too (bit for bit the same answer), without its square root and
        // divisions. Every ray leaving a sphere's surface outwards is such a ray.
        if b >= 0.0 && c >= 0.0 {
            return None;
        }
        // b² − ac computed as a·(r² − |f − (b/a) d|²) avoids cancellation for distant spheres.
        let l = f - (b / a) * d;
        let disc = a * (r * r - l.length_squared());
        let (t0, t1) = super::quadratic_roots(a, b, c, disc)?;
        let t_max = ray.t_max as f64;
        let t = if t0 > 0.0 { t0 } else { t1 };
        if t > 0.0 && t < t_max {
            Some((t as f32, Vec2::ZERO))
        } else {
            None
        }
    }

    /// The point and outward unit normal at parameter `t` of `ray` (a hit).
    #[inline]
    fn point_normal(&self, t: f32, ray: &Ray) -> (Vec3, Vec3) {
        let p_raw = (ray.o.as_dvec3() + ray.d.as_dvec3() * t as f64) - self.center.as_dvec3();
        let n = unit_or_z(p_raw);
        (self.center + n * self.radius, n)
    }

    /// What shading at a hit needs of [`Sphere::interaction`] without the texture
    /// coordinates: (point, geometric normal, ∂p/∂u), bit for bit the same.
    pub(crate) fn shading_geometry(&self, hit: &Hit, ray: &Ray) -> (Vec3, Vec3, Vec3) {
        let (p, n) = self.point_normal(hit.t, ray);
        let q = self.rotation.transpose() * n;
        let sin_t = safe_sqrt(1.0 - q.z * q.z);
        let dpdu = if sin_t > 1e-6 {
            self.rotation * (Vec3::new(-q.y, q.x, 0.0) * (2.0 * PI * self.radius))
        } else {
            Frame::from_z(n).s * (2.0 * PI * self.radius)
        };
        (p, if self.flip_normals { -n } else { n }, dpdu)
    }

    /// Surface geometry at a hit found by [`Sphere::intersect`].
    pub fn interaction(&self, hit: &Hit, ray: &Ray) -> SurfaceInteraction {
        let (p, n) = self.point_normal(hit.t, ray);
        let (uv, dpdu, dpdv) = self.parametrise(n);
        let ng = if self.flip_normals { -n } else { n };
        SurfaceInteraction {
            p,
            t: hit.t,
            ng,
            ns: ng,
            uv,
            dpdu,
            dpdv,
            shape: hit.shape,
            prim: hit.prim,
        }
    }

    /// UV and tangents for the outward unit normal `n` (world space).
    fn parametrise(&self, n: Vec3) -> (Vec2, Vec3, Vec3) {
        let q = self.rotation.transpose() * n;
        let mut phi = q.y.atan2(q.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let u = (phi * INV_2PI).min(crate::math::ONE_MINUS_EPSILON);
        let theta = crate::math::safe_acos(q.z);
        let v = theta * INV_PI;
        let r = self.radius;
        let sin_t = safe_sqrt(1.0 - q.z * q.z);
        let (dpdu, dpdv) = if sin_t > 1e-6 {
            let (sp, cp) = phi.sin_cos();
            let du = Vec3::new(-q.y, q.x, 0.0) * (2.0 * PI * r);
            let dv = Vec3::new(q.z * cp, q.z * sp, -sin_t) * (PI * r);
            (self.rotation * du, self.rotation * dv)
        } else {
            let f = Frame::from_z(n);
            (f.s * (2.0 * PI * r), f.t * (PI * r))
        };
        (Vec2::new(u, v), dpdu, dpdv)
    }

    /// Surface area 4πr².
    pub fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    /// Samples a point for direct lighting as seen from `ref_p` (see the module header).
    pub fn sample_direct(&self, ref_p: Vec3, u: Vec2) -> Option<ShapeSample> {
        let to_c = self.center - ref_p;
        let dc2 = to_c.length_squared();
        let r2 = self.radius * self.radius;
        if dc2 <= r2 * (1.0 + 1e-5) {
            // Inside or on the surface: uniform area sampling.
            let n = warp::square_to_uniform_sphere(u);
            let p = self.center + n * self.radius;
            let (uv, _, _) = self.parametrise(n);
            let ng = if self.flip_normals { -n } else { n };
            let pdf = area_to_solid_angle(1.0 / self.area(), ref_p, p, ng);
            if !super::positive_finite(pdf) {
                return None;
            }
            return Some(ShapeSample { p, n: ng, uv, pdf });
        }
        let dc = dc2.sqrt();
        let sin2_max = r2 / dc2;
        let cos_max = safe_sqrt(1.0 - sin2_max);
        // 1 − cos θmax without cancellation for small, distant spheres.
        let one_minus_cos_max = sin2_max / (1.0 + cos_max);
        let one_minus_cos = u.x * one_minus_cos_max;
        let cos_t = 1.0 - one_minus_cos;
        let sin2_t = one_minus_cos * (2.0 - one_minus_cos);
        // Angle α at the centre between the direction to `ref_p` and the sampled point
        // (law of sines/cosines in the triangle ref–centre–point, near intersection).
        let ratio = dc / self.radius;
        let cos_a = ratio * sin2_t + cos_t * safe_sqrt(1.0 - ratio * ratio * sin2_t);
        let sin_a = safe_sqrt(1.0 - cos_a * cos_a);
        let phi = 2.0 * PI * u.y;
        let frame = Frame::from_z(-to_c / dc);
        let n = frame
            .to_world(Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a))
            .normalize();
        let p = self.center + n * self.radius;
        let (uv, _, _) = self.parametrise(n);
        let ng = if self.flip_normals { -n } else { n };
        Some(ShapeSample {
            p,
            n: ng,
            uv,
            pdf: 1.0 / (2.0 * PI * one_minus_cos_max),
        })
    }

    /// Solid-angle density of [`Sphere::sample_direct`] choosing `p` (normal `n`) from `ref_p`.
    pub fn pdf_direct(&self, ref_p: Vec3, p: Vec3, n: Vec3) -> f32 {
        let dc2 = (self.center - ref_p).length_squared();
        let r2 = self.radius * self.radius;
        if dc2 <= r2 * (1.0 + 1e-5) {
            return area_to_solid_angle(1.0 / self.area(), ref_p, p, n);
        }
        let sin2_max = r2 / dc2;
        let cos_max = safe_sqrt(1.0 - sin2_max);
        1.0 / (2.0 * PI * sin2_max / (1.0 + cos_max))
    }
}

/// Normalises in f64; a zero vector (a hit exactly at the centre cannot happen) maps to +z.
fn unit_or_z(v: DVec3) -> Vec3 {
    let l = v.length();
    if l > 0.0 && l.is_finite() {
        (v / l).as_vec3()
    } else {
        Vec3::Z
    }
}

#[cfg(test)]
#[path = "sphere_tests.rs"]
mod tests;
