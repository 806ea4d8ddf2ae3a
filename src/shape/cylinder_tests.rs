use super::*;
use crate::math::{warp, Pcg32};
use crate::shape::test_util::subtended_solid_angle;
use crate::shape::Shape;

/// The cylinder from `p0` to `p1` of `radius`, placed by `to_world`, normals outwards.
fn cylinder(p0: [f32; 3], p1: [f32; 3], radius: f32, to_world: &Transform) -> Cylinder {
    Cylinder::new(p0.into(), p1.into(), radius, to_world, false).unwrap()
}

fn hit(c: &Cylinder, ray: &Ray) -> Option<SurfaceInteraction> {
    crate::shape::test_util::first_hit(c.intersect(ray), |h| c.interaction(h, ray))
}

/// Radius 1, axis from (0, 0, 0) to (0, 0, 2).
fn upright() -> Cylinder {
    cylinder([0.0, 0.0, 0.0], [0.0, 0.0, 2.0], 1.0, &Transform::IDENTITY)
}

#[test]
fn hit_distances_match_analytic_answers() {
    let c = upright();
    let t = |o: Vec3, d: Vec3| c.intersect(&Ray::new(o, d)).map(|h| h.0);
    let close = |a: Option<f32>, b: f32| {
        a.is_some_and(|a| (a - b).abs() <= 4.0 * f32::EPSILON * b.max(1.0))
    };
    assert!(close(t(Vec3::new(-5.0, 0.0, 1.0), Vec3::X), 4.0));
    // From the axis: the wall at distance 1.
    assert!(close(
        t(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.6, 0.8, 0.0)),
        1.0
    ));
    // A chord at distance h from the axis: 5 − sqrt(1 − h²).
    let h = 0.6f32;
    assert!(close(
        t(Vec3::new(-5.0, h, 0.5), Vec3::X),
        5.0 - (1.0 - h * h).sqrt()
    ));
    // Above the top, below the bottom, along the axis, behind: misses.
    assert!(t(Vec3::new(-5.0, 0.0, 2.5), Vec3::X).is_none());
    assert!(t(Vec3::new(-5.0, 0.0, -0.1), Vec3::X).is_none());
    assert!(t(Vec3::new(0.5, 0.0, -5.0), Vec3::Z).is_none());
    assert!(t(Vec3::new(5.0, 0.0, 1.0), Vec3::X).is_none());
    // In through the open top, out through the wall: the far root.
    let d = Vec3::new(1.0, 0.0, -1.0).normalize();
    let got = t(Vec3::new(0.0, 0.0, 3.0), d).unwrap();
    assert!((got - 2f32.sqrt()).abs() < 1e-5, "{got}");
    // Clipped by t_max.
    let mut short = Ray::new(Vec3::new(-5.0, 0.0, 1.0), Vec3::X);
    short.t_max = 3.9;
    assert!(c.intersect(&short).is_none());
}

#[test]
fn p0_p1_radius_and_to_world_place_it_as_mitsuba_does() {
    // Axis along +x from (1, 2, 3), length 4, radius 0.5, then moved by (0, 0, 10).
    let t = Transform::translate(Vec3::new(0.0, 0.0, 10.0));
    let c = cylinder([1.0, 2.0, 3.0], [5.0, 2.0, 3.0], 0.5, &t);
    assert!((c.radius - 0.5).abs() < 1e-6 && (c.length - 4.0).abs() < 1e-6);
    assert!((c.area() - 2.0 * PI * 0.5 * 4.0).abs() < 1e-4);
    let si = hit(&c, &Ray::new(Vec3::new(3.0, 2.0, 20.0), -Vec3::Z)).unwrap();
    assert!(
        (si.p - Vec3::new(3.0, 2.0, 13.5)).length() < 1e-5,
        "{}",
        si.p
    );
    assert!((si.ng - Vec3::Z).length() < 1e-5 && (si.uv.y - 0.5).abs() < 1e-5);
    let b = c.bounds();
    assert!((b.min - Vec3::new(1.0, 1.5, 12.5)).length() < 1e-5, "{b:?}");
    assert!((b.max - Vec3::new(5.0, 2.5, 13.5)).length() < 1e-5, "{b:?}");
    // u = 0 lies along the frame's x axis (Duff et al.'s basis, as Mitsuba's), v along the axis.
    let f = Frame::from_z(Vec3::X);
    let si = hit(&c, &Ray::new(Vec3::new(3.0, 2.0, 13.0) + f.s * 5.0, -f.s)).unwrap();
    assert!(si.uv.x < 1e-5 || si.uv.x > 1.0 - 1e-5, "{}", si.uv);
}

#[test]
fn tangents_match_finite_differences_and_normal_points_out() {
    let rot = Transform::rotate(Vec3::new(1.0, 2.0, 0.5), 33.0).unwrap();
    let c = cylinder([0.2, 0.0, 0.0], [0.2, 1.0, 3.0], 0.7, &rot);
    let point = |u: f32, v: f32| {
        let phi = 2.0 * PI * u;
        c.to_world.point(Vec3::new(phi.cos(), phi.sin(), v))
    };
    let axis_a = c.to_world.point(Vec3::ZERO);
    let axis = c.to_world.vector(Vec3::Z).normalize();
    let mut rng = Pcg32::new(3, 9);
    for _ in 0..100 {
        let (u, v) = (0.05 + 0.9 * rng.next_f32(), 0.05 + 0.9 * rng.next_f32());
        let p = point(u, v);
        let (q, n, uv, dpdu, dpdv) = c.at_local(c.to_world.inverse().point(p));
        assert!((q - p).length() < 1e-4 && (uv - Vec2::new(u, v)).abs().max_element() < 1e-4);
        let e = 1e-3;
        let fd_u = (point(u + e, v) - point(u - e, v)) / (2.0 * e);
        let fd_v = (point(u, v + e) - point(u, v - e)) / (2.0 * e);
        let tol = e * e * 250.0 * c.radius + 1e-3;
        assert!((fd_u - dpdu).length() < tol && (fd_v - dpdv).length() < tol);
        // Outward: away from the axis, and along dp/du × dp/dv as in Mitsuba.
        let radial = (p - axis_a) - axis * (p - axis_a).dot(axis);
        assert!((n - radial.normalize()).length() < 1e-4);
        assert!(dpdu.cross(dpdv).normalize().dot(n) > 0.999);
    }
    let flipped = Cylinder {
        flip_normals: true,
        ..c.clone()
    };
    let si = hit(
        &flipped,
        &Ray::new(axis_a + axis * 0.5, axis.cross(Vec3::X).normalize()),
    )
    .unwrap();
    let radial = (si.p - axis_a) - axis * (si.p - axis_a).dot(axis);
    assert!(si.ng.dot(radial) < 0.0);
}

#[test]
fn non_circular_sections_and_bad_parameters_are_rejected() {
    let oval = Transform::scale(Vec3::new(1.0, 2.0, 1.0)).unwrap();
    assert!(matches!(
        Cylinder::new(Vec3::ZERO, Vec3::Z, 1.0, &oval, false),
        Err(ShapeError::NonUniformScale { .. })
    ));
    // Stretching along the axis only is a longer cylinder.
    let long = Transform::scale(Vec3::new(2.0, 2.0, 5.0)).unwrap();
    let c = Cylinder::new(Vec3::ZERO, Vec3::Z, 1.0, &long, false).unwrap();
    assert!((c.radius - 2.0).abs() < 1e-6 && (c.length - 5.0).abs() < 1e-6);
    assert!(Cylinder::new(Vec3::ZERO, Vec3::Z, 0.0, &Transform::IDENTITY, false).is_err());
    assert!(Cylinder::new(Vec3::ONE, Vec3::ONE, 1.0, &Transform::IDENTITY, false).is_err());
}

#[test]
fn area_sampling_density_integrates_the_seen_solid_angle() {
    // E[1/pdf] over area samples = ∫ |cos θ'| / d² dA, the solid angle the surface covers
    // counted once per layer; the reference is a fine midpoint quadrature over (φ, z).
    let c = cylinder([0.0, 0.0, 0.0], [0.0, 0.0, 1.5], 0.4, &Transform::IDENTITY);
    let r = Vec3::new(1.1, -0.3, 0.6);
    let mut quad = 0.0f64;
    let (nphi, nz) = (2000, 1000);
    for i in 0..nphi {
        for j in 0..nz {
            let phi = 2.0 * std::f64::consts::PI * (i as f64 + 0.5) / nphi as f64;
            let z = 1.5 * (j as f64 + 0.5) / nz as f64;
            let p = DVec3::new(0.4 * phi.cos(), 0.4 * phi.sin(), z);
            let n = DVec3::new(phi.cos(), phi.sin(), 0.0);
            let w = p - r.as_dvec3();
            let d2 = w.length_squared();
            quad += (n.dot(w) / d2.sqrt()).abs() / d2;
        }
    }
    quad *= c.area() as f64 / (nphi * nz) as f64;
    let mut rng = Pcg32::new(8, 1);
    let c = Shape::Cylinder(c);
    let (mean, sigma) = subtended_solid_angle(&c, r, &mut rng, (200_000, 1e-5), |_| ());
    assert!(
        (mean - quad).abs() < 4.0 * sigma,
        "{mean} ± {sigma} vs {quad}"
    );
}

#[test]
fn spawned_rays_do_not_rehit_a_thin_cylinder() {
    let c = cylinder([0.1, 0.2, 0.3], [0.1, 0.2, 1.3], 1e-3, &Transform::IDENTITY);
    let mut rng = Pcg32::new(5, 7);
    let mut hits = 0;
    for _ in 0..10_000 {
        let dir = warp::square_to_uniform_sphere(rng.next_vec2());
        let target = Vec3::new(0.1, 0.2, 0.3 + rng.next_f32());
        let Some(si) = hit(&c, &Ray::new(target - dir, dir)) else {
            continue;
        };
        hits += 1;
        let out = warp::square_to_uniform_sphere(rng.next_vec2());
        let out = if out.dot(si.ng) < 0.0 { -out } else { out };
        let again = c.intersect(&Ray::spawn(si.p, si.ng, out));
        // Leaving outwards can only meet the cylinder again through... nothing: it is convex
        // in cross-section, so any second hit would be a self-intersection.
        assert!(again.is_none(), "{again:?}");
    }
    assert!(hits > 5000, "{hits}");
}
