use super::*;
use crate::math::Pcg32;

fn hit(s: &Sphere, ray: &Ray) -> Option<SurfaceInteraction> {
    crate::shape::test_util::first_hit(s.intersect(ray), |h| s.interaction(h, ray))
}

#[test]
fn hit_distances_match_analytic_answers() {
    let s = Sphere::simple(Vec3::new(1.0, 2.0, 3.0), 2.0);
    // From outside along the axis: enters at distance 13 − 2.
    let (t, _) = s
        .intersect(&Ray::new(Vec3::new(1.0, 2.0, -10.0), Vec3::Z))
        .unwrap();
    assert!((t - 11.0).abs() <= 11.0 * 4.0 * f32::EPSILON, "{t}");
    // From the centre: exits at the radius.
    let (t, _) = s
        .intersect(&Ray::new(s.center, Vec3::new(0.6, 0.0, 0.8)))
        .unwrap();
    assert!((t - 2.0).abs() <= 2.0 * 4.0 * f32::EPSILON, "{t}");
    // Off-axis chord: distance from the axis h gives t = 13 − sqrt(r² − h²).
    let h = 1.5f32;
    let (t, _) = s
        .intersect(&Ray::new(Vec3::new(1.0 + h, 2.0, -10.0), Vec3::Z))
        .unwrap();
    let want = 13.0 - (4.0 - h * h).sqrt();
    assert!(
        (t - want).abs() <= want * 8.0 * f32::EPSILON,
        "{t} vs {want}"
    );
    // Behind the ray and beyond t_max: misses.
    assert!(s
        .intersect(&Ray::new(Vec3::new(1.0, 2.0, 10.0), Vec3::Z))
        .is_none());
    let mut short = Ray::new(Vec3::new(1.0, 2.0, -10.0), Vec3::Z);
    short.t_max = 10.9;
    assert!(s.intersect(&short).is_none());
}

#[test]
fn tangent_rays_hit_or_miss_by_their_side() {
    let s = Sphere::simple(Vec3::ZERO, 2.0);
    let inside = Ray::new(Vec3::new(2.0 * (1.0 - 1e-4), 0.0, -10.0), Vec3::Z);
    let outside = Ray::new(Vec3::new(2.0 * (1.0 + 1e-4), 0.0, -10.0), Vec3::Z);
    assert!(s.intersect(&inside).is_some());
    assert!(s.intersect(&outside).is_none());
}

#[test]
fn distant_small_sphere_is_hit_precisely() {
    // |f|² − r² cancels badly in f32 here; the f64 solve keeps the distance to ~1 ulp.
    let s = Sphere::simple(Vec3::new(0.0, 0.0, 1.0e4), 1.0e-2);
    let (t, _) = s.intersect(&Ray::new(Vec3::ZERO, Vec3::Z)).unwrap();
    let want = 1.0e4f32 - 1.0e-2;
    assert!((t - want).abs() <= want * 2.0 * f32::EPSILON, "{t}");
}

#[test]
fn uv_follows_mitsuba_convention_and_rotation() {
    let s = Sphere::simple(Vec3::ZERO, 1.0);
    let si = hit(&s, &Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X)).unwrap();
    assert!(
        si.uv.x.abs() < 1e-6 && (si.uv.y - 0.5).abs() < 1e-6,
        "{:?}",
        si.uv
    );
    let si = hit(&s, &Ray::new(Vec3::new(0.0, 5.0, 0.0), -Vec3::Y)).unwrap();
    assert!((si.uv.x - 0.25).abs() < 1e-6, "{:?}", si.uv);
    // A 90° turn about z moves u = 0 to world +y.
    let rot = Transform::rotate(Vec3::Z, 90.0).unwrap();
    let s = Sphere::new(Vec3::ZERO, 1.0, &rot, false).unwrap();
    let si = hit(&s, &Ray::new(Vec3::new(0.0, 5.0, 0.0), -Vec3::Y)).unwrap();
    assert!(
        si.uv.x.abs() < 1e-5 || (si.uv.x - 1.0).abs() < 1e-5,
        "{:?}",
        si.uv
    );
}

#[test]
fn tangents_match_finite_differences_and_poles_are_finite() {
    let rot = Transform::rotate(Vec3::new(1.0, 2.0, 0.5), 33.0).unwrap();
    let s = Sphere::new(Vec3::new(0.5, 0.0, 0.0), 2.0, &rot, false).unwrap();
    let mut rng = Pcg32::new(11, 0);
    let point = |u: f32, v: f32| {
        let (phi, theta) = (2.0 * PI * u, PI * v);
        let q = Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        );
        s.center + s.rotation * q * s.radius
    };
    for _ in 0..100 {
        let u = 0.1 + 0.8 * rng.next_f32();
        let v = 0.1 + 0.8 * rng.next_f32();
        let p = point(u, v);
        let n = (p - s.center).normalize();
        let (uv, dpdu, dpdv) = s.parametrise(n);
        assert!(
            (uv - Vec2::new(u, v)).abs().max_element() < 1e-4,
            "{uv:?} {u} {v}"
        );
        let e = 1e-3;
        let fd_u = (point(u + e, v) - point(u - e, v)) / (2.0 * e);
        let fd_v = (point(u, v + e) - point(u, v - e)) / (2.0 * e);
        // Central differences err by O(e²·|p'''|) ≈ e²·(2π)³·r.
        let tol = e * e * 250.0 * s.radius + 1e-3;
        assert!((fd_u - dpdu).length() < tol, "{fd_u} {dpdu}");
        assert!((fd_v - dpdv).length() < tol, "{fd_v} {dpdv}");
    }
    let si = hit(
        &s,
        &Ray::new(s.center + rot.vector(Vec3::Z) * 5.0, -rot.vector(Vec3::Z)),
    )
    .unwrap();
    assert!(si.dpdu.is_finite() && si.dpdv.is_finite() && si.dpdu.length() > 0.0);
    assert!(si.dpdu.cross(si.dpdv).length() > 0.0);
}

#[test]
fn flip_normals_points_inwards() {
    let s = Sphere::new(Vec3::ZERO, 1.0, &Transform::IDENTITY, true).unwrap();
    let si = hit(&s, &Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z)).unwrap();
    assert!((si.ng - Vec3::Z).length() < 1e-6 && (si.ns - Vec3::Z).length() < 1e-6);
}

#[test]
fn non_similarity_transforms_are_rejected() {
    let t = Transform::scale(Vec3::new(1.0, 2.0, 1.0)).unwrap();
    assert!(matches!(
        Sphere::new(Vec3::ZERO, 1.0, &t, false),
        Err(ShapeError::NonUniformScale { .. })
    ));
    assert!(Sphere::new(Vec3::ZERO, -1.0, &Transform::IDENTITY, false).is_err());
    let t = Transform::scale(Vec3::splat(3.0)).unwrap();
    let s = Sphere::new(Vec3::X, 2.0, &t, false).unwrap();
    assert!((s.radius - 6.0).abs() < 1e-5 && (s.center - Vec3::new(3.0, 0.0, 0.0)).length() < 1e-5);
}

#[test]
fn cone_sampling_is_uniform_in_the_subtended_cone() {
    let s = Sphere::simple(Vec3::new(0.3, -0.2, 4.0), 1.5);
    let r = Vec3::new(-0.5, 0.4, -0.6);
    let to_c = s.center - r;
    let dc = to_c.length();
    let cos_max = (1.0 - (s.radius / dc).powi(2)).sqrt();
    let omega = 2.0 * PI * (1.0 - cos_max);
    let mut rng = Pcg32::new(2024, 3);
    let n = 100_000;
    let mut sum_cos = 0.0f64;
    for _ in 0..n {
        let smp = s.sample_direct(r, rng.next_vec2()).unwrap();
        assert!(((smp.p - s.center).length() - s.radius).abs() < 1e-5 * s.radius);
        let w = (smp.p - r).normalize();
        // The sampled point is the visible one: the first hit along w.
        let (t, _) = s.intersect(&Ray::new(r, w)).unwrap();
        assert!((t - (smp.p - r).length()).abs() < 1e-3, "{t}");
        assert!((1.0 / smp.pdf - omega).abs() < 1e-4 * omega);
        let pdf = s.pdf_direct(r, smp.p, smp.n);
        assert!((pdf - smp.pdf).abs() <= 1e-5 * pdf);
        sum_cos += w.dot(to_c / dc) as f64;
    }
    // cos θ is uniform on [cos θmax, 1] for uniform cone sampling.
    let mean = sum_cos / n as f64;
    let want = 0.5 * (1.0 + cos_max as f64);
    let sigma = (1.0 - cos_max as f64) / 12f64.sqrt() / (n as f64).sqrt();
    assert!((mean - want).abs() < 4.0 * sigma, "{mean} vs {want}");
}

#[test]
fn inside_sampling_covers_all_directions() {
    // From inside, E[1/pdf] over area samples is the full sphere of directions, 4π.
    let s = Sphere::simple(Vec3::new(1.0, 0.0, 0.0), 2.0);
    let r = Vec3::new(1.5, 0.7, -0.9);
    let mut rng = Pcg32::new(99, 1);
    let (mean, sigma) = crate::shape::test_util::mean_and_error(200_000, || {
        let smp = s.sample_direct(r, rng.next_vec2()).unwrap();
        let pdf = s.pdf_direct(r, smp.p, smp.n);
        assert!((pdf - smp.pdf).abs() <= 1e-4 * pdf);
        1.0 / smp.pdf as f64
    });
    let want = 4.0 * std::f64::consts::PI;
    assert!((mean - want).abs() < 4.0 * sigma, "{mean} ± {sigma}");
}

#[test]
fn spawned_rays_do_not_rehit_a_tiny_sphere() {
    let s = Sphere::simple(Vec3::new(0.2, 0.1, -0.3), 1e-3);
    let mut rng = Pcg32::new(5, 5);
    for _ in 0..10_000 {
        let dir = warp::square_to_uniform_sphere(rng.next_vec2());
        let ray = Ray::new(s.center - dir * 1.0, dir);
        let si = hit(&s, &ray).unwrap();
        // Leaving outwards must escape; going inwards must reach the far side, not the origin.
        let out = warp::square_to_uniform_sphere(rng.next_vec2());
        let out = if out.dot(si.ng) < 0.0 { -out } else { out };
        assert!(s.intersect(&Ray::spawn(si.p, si.ng, out)).is_none());
        let inward = -out;
        let (t, _) = s.intersect(&Ray::spawn(si.p, si.ng, inward)).unwrap();
        let chord = 2.0 * s.radius * inward.dot(-si.ng);
        assert!(t > 0.5 * chord, "t {t} chord {chord}");
    }
}

#[test]
fn the_f32_pretest_never_drops_a_hit() {
    // Rays aimed at points just inside and outside the silhouette, at many scales and
    // distances, with and without the pre-test: the same answers, bit for bit.
    let mut rng = crate::math::Pcg32::new(5, 9);
    let mut near_misses = 0;
    let mut grazing_hits = 0;
    for case in 0..200_000 {
        let scale = [1e-3f32, 1.0, 1e3, 1e5][case % 4];
        let center = Vec3::new(
            rng.next_f32() - 0.5,
            rng.next_f32() - 0.5,
            rng.next_f32() - 0.5,
        ) * (10.0 * scale);
        let radius = scale * (0.01 + rng.next_f32());
        let s = Sphere::simple(center, radius);
        let dir = crate::math::warp::square_to_uniform_sphere(rng.next_vec2());
        let side = crate::math::Frame::from_z(dir);
        let phi = 2.0 * std::f32::consts::PI * rng.next_f32();
        // Distance of the line from the centre: within 1e-3 of the radius either way.
        let off = radius * (1.0 + (rng.next_f32() - 0.5) * 2e-3);
        let target = center + (side.s * phi.cos() + side.t * phi.sin()) * off;
        let dist = scale * (1.0 + 100.0 * rng.next_f32());
        let ray = Ray::new(target - dir * dist, dir);
        let (a, b) = (s.intersect(&ray), s.intersect_exact(&ray));
        assert_eq!(
            a.map(|h| h.0.to_bits()),
            b.map(|h| h.0.to_bits()),
            "case {case}: {ray:?}"
        );
        if b.is_some() && off > radius * 0.9999 {
            grazing_hits += 1;
        }
        if b.is_none() {
            near_misses += 1;
        }
    }
    assert!(
        grazing_hits > 1000 && near_misses > 1000,
        "{grazing_hits} {near_misses}"
    );
}
