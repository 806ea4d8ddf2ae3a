use super::super::test_util::{mean_and_sigma, wl};
use super::super::{Light, LightSampleContext};
use super::*;
use crate::math::Pcg32;
use crate::shape::Sphere;

fn si_at(p: Vec3, ng: Vec3) -> SurfaceInteraction {
    SurfaceInteraction {
        p,
        t: 1.0,
        ng,
        ns: ng,
        uv: Vec2::ZERO,
        dpdu: Vec3::X,
        dpdv: Vec3::Y,
        shape: 0,
        prim: 0,
    }
}

#[test]
fn emits_from_the_front_side_only() {
    let light = Light::Area(AreaLight::new(0, Spectrum::Constant(4.0)));
    assert!(!light.is_delta() && !light.is_infinite());
    let si = si_at(Vec3::ZERO, Vec3::Z);
    assert_eq!(
        light.l(&si, Vec3::new(0.3, 0.0, 1.0).normalize(), &wl())[0],
        4.0
    );
    assert!(light
        .l(&si, Vec3::new(0.3, 0.0, -1.0).normalize(), &wl())
        .is_black());
    assert!(light.le(Vec3::Z, &wl()).is_black());
    // Without shapes (or with an index out of range) nothing is sampled and nothing panics.
    let ctx = LightSampleContext {
        p: Vec3::ONE,
        n: Vec3::ZERO,
    };
    assert!(light
        .sample_li(&ctx, Vec2::splat(0.5), &wl(), &[])
        .is_none());
    assert_eq!(light.pdf_li(&ctx, Vec3::Z, &[], Some(&si)), 0.0);
    assert_eq!(light.power(&[]), 0.0);
}

fn sphere(flip_normals: bool) -> Shape {
    Shape::Sphere(
        Sphere::new(
            Vec3::ZERO,
            1.0,
            &crate::math::Transform::IDENTITY,
            flip_normals,
        )
        .expect("valid sphere"),
    )
}

/// A unit sphere at the origin emitting radiance 2 (inwards with `flip_normals`), seen from a
/// shading point at distance 3 on +z with normal `n`.
fn sphere_light(flip_normals: bool, n: Vec3) -> ([Shape; 1], Light, LightSampleContext) {
    let light = Light::Area(AreaLight::new(0, Spectrum::Constant(2.0)));
    let ctx = LightSampleContext {
        p: Vec3::new(0.0, 0.0, 3.0),
        n,
    };
    ([sphere(flip_normals)], light, ctx)
}

#[test]
fn sphere_light_irradiance_matches_closed_form() {
    // A sphere of radius r at distance d, seen by a surface facing its centre: E = π L (r/d)².
    let (shapes, light, ctx) = sphere_light(false, -Vec3::Z);
    let mut rng = Pcg32::new(9, 2);
    let (mean, sigma) = mean_and_sigma((0..20_000).map(|_| {
        let Some(s) = light.sample_li(&ctx, rng.next_vec2(), &wl(), &shapes) else {
            return 0.0;
        };
        let si = si_at(s.p_light, s.p_light.normalize());
        let pdf = light.pdf_li(&ctx, s.wi, &shapes, Some(&si));
        assert!((pdf - s.pdf).abs() <= 1e-3 * s.pdf, "{pdf} vs {}", s.pdf);
        (s.l[0] * s.wi.dot(ctx.n).max(0.0) / s.pdf) as f64
    }));
    let want = std::f64::consts::PI * 2.0 / 9.0;
    assert!(
        (mean - want).abs() <= 4.0 * sigma + 1e-4 * want,
        "{mean} vs {want} ± {sigma}"
    );
    assert!((light.power(&shapes) - PI * 4.0 * PI * 2.0).abs() < 1e-3);
}

#[test]
fn inward_facing_sphere_is_dark_from_outside() {
    let (shapes, light, ctx) = sphere_light(true, Vec3::ZERO);
    let mut rng = Pcg32::new(1, 2);
    for _ in 0..100 {
        assert!(light
            .sample_li(&ctx, rng.next_vec2(), &wl(), &shapes)
            .is_none());
    }
}
