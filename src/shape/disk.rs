//! Analytic disk: the unit disk in the local xy-plane at z = 0, normal +z, placed by `to_world`.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |
//!
//! `to_world` may be any invertible affine map (the disk becomes an ellipse under a non-uniform scale).
//!
//! UV convention (as Mitsuba 3): u = r (distance from the centre in local units), v = φ/(2π)
//! with φ = atan2(y, x) wrapped to [0, 2π). dp/du is the radial direction, dp/dv = 2π·(−y, x, 0);
//! at the centre, where φ is undefined, an arbitrary tangent frame is used.
//!
//! Direct sampling is uniform by area (concentric map, Shirley & Chiu 1997), converted to solid
//! angle. An affine map has a constant Jacobian, so uniform in local space is uniform in world
//! space.
use super::{area_to_solid_angle, Hit, ShapeSample, SurfaceInteraction};
use crate::math::{warp, Bounds3, Frame, Ray, Transform, Vec2, Vec3, INV_2PI, PI};
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: super::Parts, Transform = Shape "disk" []
    "analytic unit disk, placed by `to_world`"
    [super::PLACEMENT] load);

fn load(a: &mut Args, parent: Transform) -> Result<super::Parts, SceneError> {
    let (to_world, flip) = super::placement(a, &parent)?;
    Ok(vec![(None, super::Shape::Disk(Disk::new(&to_world, flip)))])
}

/// A disk in world space.
#[derive(Clone, Debug)]
pub struct Disk {
    pub to_world: Transform,
    pub flip_normals: bool,
    /// Unit world normal (after `flip_normals`).
    normal: Vec3,
    /// World area.
    area: f32,
}

impl Disk {
    /// A disk from Mitsuba's parameters.
    pub fn new(to_world: &Transform, flip_normals: bool) -> Disk {
        let n = to_world.normal(Vec3::Z).normalize_or_zero();
        let ex = to_world.vector(Vec3::X);
        let ey = to_world.vector(Vec3::Y);
        Disk {
            to_world: *to_world,
            flip_normals,
            normal: if flip_normals { -n } else { n },
            area: PI * ex.cross(ey).length(),
        }
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        let mut b = Bounds3::EMPTY;
        for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            b.grow(self.to_world.point(Vec3::new(x, y, 0.0)));
        }
        b
    }

    /// Intersection with parameter in (0, ray.t_max); the uv is the local (x, y) of the hit.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<(f32, Vec2)> {
        // An affine map preserves ray parameters when the direction is mapped unnormalised.
        let o = self.to_world.inv.transform_point3(ray.o);
        let d = self.to_world.inv.transform_vector3(ray.d);
        if d.z == 0.0 {
            return None;
        }
        let t = -o.z / d.z;
        if !(t > 0.0 && t < ray.t_max) {
            return None;
        }
        let x = o.x + t * d.x;
        let y = o.y + t * d.y;
        if x * x + y * y <= 1.0 {
            Some((t, Vec2::new(x, y)))
        } else {
            None
        }
    }

    /// Surface geometry at a hit found by [`Disk::intersect`].
    pub fn interaction(&self, hit: &Hit, _ray: &Ray) -> SurfaceInteraction {
        let local = hit.uv;
        let p = self.to_world.point(Vec3::new(local.x, local.y, 0.0));
        let (uv, dpdu, dpdv) = self.parametrise(local);
        SurfaceInteraction {
            p,
            t: hit.t,
            ng: self.normal,
            ns: self.normal,
            uv,
            dpdu,
            dpdv,
            shape: hit.shape,
            prim: hit.prim,
        }
    }

    fn parametrise(&self, local: Vec2) -> (Vec2, Vec3, Vec3) {
        let r = local.length();
        let mut phi = local.y.atan2(local.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let uv = Vec2::new(r, (phi * INV_2PI).min(crate::math::ONE_MINUS_EPSILON));
        if r > 1e-6 {
            let dpdu = self
                .to_world
                .vector(Vec3::new(local.x / r, local.y / r, 0.0));
            let dpdv = self
                .to_world
                .vector(Vec3::new(-local.y, local.x, 0.0) * (2.0 * PI));
            (uv, dpdu, dpdv)
        } else {
            let f = Frame::from_z(self.normal);
            (uv, f.s, f.t)
        }
    }

    /// World-space area (π for the unit disk; scaled by the transform).
    pub fn area(&self) -> f32 {
        self.area
    }

    /// Samples a point uniformly by area; the density is converted to solid angle at `ref_p`.
    pub fn sample_direct(&self, ref_p: Vec3, u: Vec2) -> Option<ShapeSample> {
        let local = warp::square_to_uniform_disk_concentric(u);
        let p = self.to_world.point(Vec3::new(local.x, local.y, 0.0));
        let pdf = area_to_solid_angle(1.0 / self.area, ref_p, p, self.normal);
        if !super::positive_finite(pdf) {
            return None;
        }
        let (uv, _, _) = self.parametrise(local);
        Some(ShapeSample {
            p,
            n: self.normal,
            uv,
            pdf,
        })
    }

    /// Solid-angle density of [`Disk::sample_direct`] choosing `p` (normal `n`) from `ref_p`.
    pub fn pdf_direct(&self, ref_p: Vec3, p: Vec3, n: Vec3) -> f32 {
        area_to_solid_angle(1.0 / self.area, ref_p, p, n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;
    use crate::shape::test_util::subtended_solid_angle;
    use crate::shape::Shape;

    #[test]
    fn hits_inside_the_rim_only_with_mitsuba_uv() {
        let t = Transform::translate(Vec3::new(0.0, 0.0, 2.0))
            .compose(&Transform::scale(Vec3::splat(3.0)).unwrap());
        let d = Disk::new(&t, false);
        let ray = Ray::new(Vec3::new(0.0, 1.5, 5.0), -Vec3::Z);
        let (th, uv) = d.intersect(&ray).unwrap();
        assert!((th - 3.0).abs() < 1e-6);
        let si = d.interaction(
            &Hit {
                t: th,
                shape: 0,
                prim: 0,
                uv,
            },
            &ray,
        );
        assert!((si.p - Vec3::new(0.0, 1.5, 2.0)).length() < 1e-6);
        assert!(
            (si.uv - Vec2::new(0.5, 0.25)).length() < 1e-6,
            "{:?}",
            si.uv
        );
        assert!((si.ng - Vec3::Z).length() < 1e-6);
        assert!((d.area() - 9.0 * PI).abs() < 1e-4);
        assert!(d
            .intersect(&Ray::new(Vec3::new(0.0, 3.01, 5.0), -Vec3::Z))
            .is_none());
        assert!(d
            .intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z))
            .is_none());
        assert!((Disk::new(&t, true).normal + Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn area_sampling_integrates_to_the_subtended_solid_angle() {
        // A disk of radius R seen from height h on its axis subtends 2π(1 − h/√(h²+R²)).
        let (rad, h) = (2.0f32, 1.5f32);
        let t = Transform::scale(Vec3::new(rad, rad, 1.0)).unwrap();
        let d = Disk::new(&t, false);
        let r = Vec3::new(0.0, 0.0, h);
        let mut rng = Pcg32::new(17, 2);
        let on_disk = |smp: &ShapeSample| {
            assert!(smp.p.z.abs() < 1e-6 && smp.p.truncate().length() <= rad * (1.0 + 1e-6));
        };
        let d = Shape::Disk(d);
        let (mean, sigma) = subtended_solid_angle(&d, r, &mut rng, (200_000, 1e-5), on_disk);
        let (rad, h) = (rad as f64, h as f64);
        let want = 2.0 * std::f64::consts::PI * (1.0 - h / (h * h + rad * rad).sqrt());
        assert!(
            (mean - want).abs() < 4.0 * sigma,
            "{mean} ± {sigma} vs {want}"
        );
    }
}
