use super::*;
use crate::math::{Pcg32, Ray, PI};
use crate::shape::{Hit, Sphere};
use std::sync::Arc;

fn cells() -> Scales {
    Scales {
        scale_u: 12.0,
        scale_v: 8.0,
        irregularity: 0.6,
        gap: 0.1,
        seed: 3,
        ..Scales::default()
    }
}

/// Unit normal of the displaced surface P(u, v) by central differences (f64), on the side of `n`.
fn fd_normal(p: impl Fn(f64, f64) -> [f64; 3], u: f64, v: f64, step: f64, n: Vec3) -> Vec3 {
    let d = |a: [f64; 3], b: [f64; 3]| glam::DVec3::new(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    let pu = d(p(u + step, v), p(u - step, v));
    let pv = d(p(u, v + step), p(u, v - step));
    let m = pu.cross(pv).normalize().as_vec3();
    if m.dot(n) < 0.0 {
        -m
    } else {
        m
    }
}

#[test]
fn bumped_normal_matches_the_displaced_plane_for_both_handednesses() {
    let c = cells();
    let s = 0.004; // world units per unit height
    let a = Vec3::new(0.9, 0.1, 0.2);
    let mut rng = Pcg32::new(1, 1);
    let mut worst: f32 = 0.0;
    for flip in [false, true] {
        let b = Vec3::new(-0.2, 0.7, 0.1);
        let n0 = a.cross(b).normalize() * if flip { -1.0 } else { 1.0 };
        let surf = |u: f64, v: f64| {
            let h = c.height(Vec2::new(u as f32, v as f32), 0.0) as f64 * s as f64;
            let q = a.as_dvec3() * u + b.as_dvec3() * v + n0.as_dvec3() * h;
            [q.x, q.y, q.z]
        };
        for _ in 0..2000 {
            let uv = rng.next_vec2();
            let (n, _) = bump_normal(n0, a, b, c.gradient(uv, 0.0), s);
            assert!((n.length() - 1.0).abs() < 1e-5 && n.dot(n0) > 0.0);
            let want = fd_normal(surf, uv.x as f64, uv.y as f64, 2e-3 / 12.0, n0);
            worst = worst.max(n.dot(want).clamp(-1.0, 1.0).acos());
        }
    }
    // Both are central differences of the same C¹ height (steps 1e-3 and 2e-3 cells); the
    // slopes reach ~0.4 rad, so 1e-2 rad is a few percent of the tilt.
    assert!(worst < 1e-2, "worst angle {worst} rad");
    // A bump must actually tilt the normal (a test that cannot fail is a defect).
    let (n, _) = bump_normal(Vec3::Z, Vec3::X, Vec3::Y, Vec2::new(3.0, 0.0), 0.1);
    assert!((n - Vec3::new(-0.3, 0.0, 1.0).normalize()).length() < 1e-5);
}

fn sphere_hit(sph: &Sphere, dir: Vec3) -> SurfaceInteraction {
    let ray = Ray::new(sph.center + dir * 3.0, -dir);
    let (t, uv) = sph.intersect(&ray).expect("aimed at the sphere");
    let hit = Hit {
        t,
        shape: 0,
        prim: 0,
        uv,
    };
    sph.interaction(&hit, &ray)
}

fn bumped(c: &Scales, s: f32) -> Material {
    Material::BumpMap {
        height: FloatTexture::Scales(Arc::new(c.clone())),
        scale: s,
        inner: Box::new(Material::default_diffuse()),
    }
}

#[test]
fn bumped_sphere_matches_the_displaced_sphere() {
    let c = cells();
    let (r, s) = (1.5f32, 0.003f32);
    let sph = Sphere::simple(Vec3::new(0.3, -0.2, 0.5), r);
    let m = bumped(&c, s);
    let surf = |u: f64, v: f64| {
        let (phi, theta) = (2.0 * std::f64::consts::PI * u, std::f64::consts::PI * v);
        let n = glam::DVec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        );
        let h = c.height(Vec2::new(u as f32, v as f32), 0.0) as f64 * s as f64;
        let q = sph.center.as_dvec3() + n * (r as f64 + h);
        [q.x, q.y, q.z]
    };
    let mut rng = Pcg32::new(2, 2);
    let mut worst: f32 = 0.0;
    for _ in 0..2000 {
        let uv = Vec2::new(rng.next_f32(), 0.15 + 0.7 * rng.next_f32());
        let (phi, theta) = (2.0 * PI * uv.x, PI * uv.y);
        let dir = Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        );
        let si = sphere_hit(&sph, dir);
        assert!(
            (si.uv - uv).length() < 1e-4,
            "sphere uv {:?} vs {uv:?}",
            si.uv
        );
        let n = m.shading_frame(&si, si.ng, 0.0).n;
        assert!((n.length() - 1.0).abs() < 1e-5);
        let want = fd_normal(surf, si.uv.x as f64, si.uv.y as f64, 2e-3 / 12.0, si.ng);
        worst = worst.max(n.dot(want).clamp(-1.0, 1.0).acos());
    }
    // Blinn drops h·∂n/∂u, relatively s·h/r ≤ 0.002; plus the difference error of the plane test.
    assert!(worst < 1e-2 + s / r, "worst angle {worst} rad");
}

#[test]
fn normals_stay_unit_finite_and_visible_at_poles_seams_and_grazing_angles() {
    let c = cells();
    let sph = Sphere::simple(Vec3::ZERO, 1.0);
    let m = Material::TwoSided {
        front: Box::new(bumped(&c, 0.05)),
        back: None,
    };
    let mut rng = Pcg32::new(4, 4);
    let dirs = [
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::new(1.0, -1e-7, 0.0).normalize(),
    ];
    for (k, d) in dirs.iter().enumerate() {
        let si = sphere_hit(&sph, *d);
        for _ in 0..500 {
            let wo = crate::math::warp::square_to_uniform_sphere(rng.next_vec2());
            let f = m.shading_frame(&si, wo, 0.0);
            assert!(f.n.is_finite() && f.s.is_finite(), "NaN at direction {k}");
            assert!((f.n.length() - 1.0).abs() < 1e-4);
            assert!(f.s.dot(f.n).abs() < 1e-4);
            let side = si.ng.dot(wo).signum();
            assert!(f.n.dot(wo) * side > 0.0, "normal faces away from wo");
        }
    }
    // keep_visible bends a normal that faces away, and leaves a visible one alone.
    let n = Vec3::new(0.8, 0.0, 0.6);
    let wo = Vec3::new(-0.9, 0.0, 0.1).normalize();
    assert!(n.dot(wo) < 0.0);
    let k = keep_visible(n, Vec3::Z, wo);
    assert!(k.dot(wo) > 0.0 && (k.length() - 1.0).abs() < 1e-5);
    assert_eq!(keep_visible(Vec3::Z, Vec3::Z, wo), Vec3::Z);
}

#[test]
fn per_scale_tilt_rotates_each_normal_by_its_cells_angle() {
    let flat = cells();
    let c = Scales {
        tilt: 8f32.to_radians(),
        ..flat.clone()
    };
    let mut rng = Pcg32::new(6, 6);
    let sph = Sphere::simple(Vec3::ZERO, 1.0);
    let plain = bumped(&flat, 0.002);
    let tilted = bumped(&c, 0.002);
    for _ in 0..300 {
        let d = crate::math::warp::square_to_uniform_sphere(rng.next_vec2());
        let si = sphere_hit(&sph, d);
        if si.uv.y < 0.1 || si.uv.y > 0.9 {
            continue;
        }
        let a = plain.shading_frame(&si, si.ng, 0.0).n;
        let b = tilted.shading_frame(&si, si.ng, 0.0).n;
        let (want, _) = c.tilt_at(si.uv);
        let got = a.dot(b).clamp(-1.0, 1.0).acos();
        assert!((got - want).abs() < 2e-3, "tilt {got} vs {want}");
    }
}

#[test]
fn distant_scales_fade_to_the_unbumped_normal() {
    let c = cells();
    let sph = Sphere::simple(Vec3::ZERO, 1.0);
    let m = bumped(&c, 0.05);
    let si = sphere_hit(&sph, Vec3::new(1.0, 0.2, 0.3).normalize());
    // A footprint of several cells (cells are ~0.5 wide on this sphere).
    let n = m.shading_frame(&si, si.ng, 5.0).n;
    assert!((n - si.ns).length() < 1e-3);
}
