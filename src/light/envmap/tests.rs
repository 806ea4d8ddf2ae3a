use super::super::test_util::{mean_and_sigma, wl};
use super::super::Light;
use super::*;
use crate::math::warp::square_to_uniform_sphere;
use crate::math::Pcg32;

/// A map of constant-spectrum texels with the given values (row-major, top row first).
fn map(width: usize, height: usize, values: &[f32], to_world: Transform) -> EnvMapLight {
    let texels = values.iter().map(|&v| Spectrum::Constant(v)).collect();
    EnvMapLight::from_texels(width, height, texels, values, 1.0, to_world)
}

/// A dim map with a bright patch away from the poles and a second one touching the top row.
fn patchy(width: usize, height: usize) -> Vec<f32> {
    let mut v = vec![0.1; width * height];
    for y in 2..4 {
        for x in 5..8 {
            v[y * width + x] = 50.0;
        }
    }
    v[3] = 20.0;
    v[width * (height - 1)] = 0.0;
    v
}

/// ∫ L dω by exact quadrature of the piecewise-constant texels.
fn quadrature(width: usize, height: usize, values: &[f32]) -> f64 {
    let pi = std::f64::consts::PI;
    let mut sum = 0.0;
    for y in 0..height {
        let band =
            (pi * y as f64 / height as f64).cos() - (pi * (y + 1) as f64 / height as f64).cos();
        for x in 0..width {
            sum += values[y * width + x] as f64 * band * 2.0 * pi / width as f64;
        }
    }
    sum
}

fn rotation() -> Transform {
    Transform::rotate(Vec3::new(1.0, 2.0, 0.5), 70.0).unwrap()
}

#[test]
fn lat_long_mapping_round_trips_and_follows_mitsuba() {
    let mut rng = Pcg32::new(1, 1);
    for _ in 0..1000 {
        let uv = Vec2::new(rng.next_f32(), 0.001 + 0.998 * rng.next_f32());
        let back = direction_to_uv(uv_to_direction(uv));
        let du = (back.x - uv.x).abs();
        assert!(
            du.min(1.0 - du) < 1e-4 && (back.y - uv.y).abs() < 1e-4,
            "{uv} {back}"
        );
        let d = square_to_uniform_sphere(rng.next_vec2());
        assert!((uv_to_direction(direction_to_uv(d)) - d).length() < 1e-4);
    }
    // Column centres of a 4-wide map: φ = 45°, 135°, 225°, 315° from −z towards +x.
    let values = [1.0, 2.0, 3.0, 4.0, 11.0, 12.0, 13.0, 14.0];
    let light = map(4, 2, &values, Transform::IDENTITY);
    let (s, c) = (0.5f32.sqrt(), 0.5f32.sqrt());
    let dirs = [
        Vec3::new(s, 0.3, -c),
        Vec3::new(s, 0.3, c),
        Vec3::new(-s, 0.3, c),
        Vec3::new(-s, 0.3, -c),
    ];
    for (i, d) in dirs.iter().enumerate() {
        assert_eq!(light.le(*d, &wl())[0], values[i], "top row, column {i}");
        let below = Vec3::new(d.x, -d.y, d.z);
        assert_eq!(
            light.le(below, &wl())[0],
            values[4 + i],
            "bottom row, column {i}"
        );
    }
    assert_eq!(direction_to_uv(Vec3::Y).y, 0.0);
    assert_eq!(direction_to_uv(-Vec3::Y).y, 1.0);
    // `to_world` rotates the map: the world direction R d sees what d saw before.
    let rotated = map(4, 2, &values, rotation());
    for d in dirs {
        assert_eq!(
            rotated.le(rotation().vector(d), &wl())[0],
            light.le(d, &wl())[0]
        );
    }
}

#[test]
fn importance_sampling_integrates_the_map() {
    let (w, h) = (16, 8);
    let values = patchy(w, h);
    let want = quadrature(w, h, &values);
    let light = Light::EnvMap(map(w, h, &values, rotation()));
    assert!(light.is_infinite() && !light.is_delta());
    let ctx = LightSampleContext {
        p: Vec3::new(0.3, -0.2, 1.0),
        n: Vec3::ZERO,
    };
    let mut rng = Pcg32::new(21, 5);
    let (mean, sigma) = mean_and_sigma((0..40_000).map(|_| {
        let s = light.sample_li(&ctx, rng.next_vec2(), &wl(), &[]);
        let Some(s) = s else { return 0.0 };
        assert!(!s.is_delta && s.l[0] > 0.0);
        let pdf = light.pdf_li(&ctx, s.wi, &[], None);
        assert!((pdf - s.pdf).abs() <= 1e-5 * s.pdf, "{pdf} vs {}", s.pdf);
        assert!((s.l[0] - light.le(s.wi, &wl())[0]).abs() == 0.0);
        (s.l[0] / s.pdf) as f64
    }));
    assert!(
        (mean - want).abs() <= 4.0 * sigma + 1e-4 * want,
        "{mean} vs {want} ± {sigma}"
    );
    // Importance sampling should beat uniform sampling by far on this map.
    assert!(sigma < 0.02 * want, "{sigma}");
}

#[test]
fn uniform_estimates_agree_with_le_and_pdf_normalisation() {
    // Independent of the sampler: E[4π le(d)] = ∫ L dω and E[4π pdf_li(d)] = 1 for uniform d.
    let (w, h) = (16, 8);
    let values = patchy(w, h);
    let light = map(w, h, &values, rotation());
    let mut rng = Pcg32::new(4, 4);
    let dirs: Vec<Vec3> = (0..100_000)
        .map(|_| square_to_uniform_sphere(rng.next_vec2()))
        .collect();
    let four_pi = 4.0 * std::f64::consts::PI;
    let (mean, sigma) =
        mean_and_sigma(dirs.iter().map(|&d| four_pi * light.le(d, &wl())[0] as f64));
    let want = quadrature(w, h, &values);
    assert!(
        (mean - want).abs() <= 4.0 * sigma,
        "{mean} vs {want} ± {sigma}"
    );
    let (mean, sigma) = mean_and_sigma(dirs.iter().map(|&d| four_pi * light.pdf_li(d) as f64));
    assert!((mean - 1.0).abs() <= 4.0 * sigma, "{mean} ± {sigma}");
}

#[test]
fn black_map_and_bad_images() {
    let light = map(4, 2, &[0.0; 8], Transform::IDENTITY);
    // All-zero weights fall back to uniform sampling; the radiance is zero.
    let ctx = LightSampleContext {
        p: Vec3::ZERO,
        n: Vec3::ZERO,
    };
    let s = light.sample_li(&ctx, Vec2::new(0.3, 0.6), &wl()).unwrap();
    assert!(s.l.is_black() && s.pdf > 0.0);
    assert_eq!(light.power(), 0.0);
    let empty = RgbImage {
        width: 0,
        height: 3,
        data: vec![],
    };
    assert!(matches!(
        EnvMapLight::new(empty, 1.0, Transform::IDENTITY),
        Err(EnvMapError::Empty { .. })
    ));
    let short = RgbImage {
        width: 2,
        height: 2,
        data: vec![[1.0; 3]; 3],
    };
    assert!(matches!(
        EnvMapLight::new(short, 1.0, Transform::IDENTITY),
        Err(EnvMapError::SizeMismatch { .. })
    ));
}

#[test]
fn rgb_texels_are_uplifted_as_illuminants() {
    let mut img = RgbImage::new(4, 2);
    img.data[1] = [0.8, 0.4, 0.1];
    let light = EnvMapLight::new(img, 2.0, Transform::IDENTITY).unwrap();
    let d = Vec3::new(0.5f32.sqrt(), 0.3, 0.5f32.sqrt());
    let want = Spectrum::rgb_illuminant([0.8, 0.4, 0.1]).sample(&wl()) * 2.0;
    let got = light.le(d, &wl());
    for i in 0..4 {
        assert!((got[i] - want[i]).abs() <= 1e-5 * want[i].abs().max(1e-3));
    }
}
