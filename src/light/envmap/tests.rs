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

/// The map's radiance at (u, v), interpolated bilinearly between texel centres (u wraps, v
/// clamps), written independently of the light's own lookup.
fn bilinear(width: usize, height: usize, values: &[f32], u: f64, v: f64) -> f64 {
    let x = u * width as f64 - 0.5;
    let y = v * height as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: f64, j: f64| {
        let i = (i as i64).rem_euclid(width as i64) as usize;
        let j = (j as i64).clamp(0, height as i64 - 1) as usize;
        values[j * width + i] as f64
    };
    let top = at(x0, y0) * (1.0 - fx) + at(x0 + 1.0, y0) * fx;
    let bottom = at(x0, y0 + 1.0) * (1.0 - fx) + at(x0 + 1.0, y0 + 1.0) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// ∫ L dω of the bilinear radiance, by the midpoint rule on a grid 64 times finer than the
/// texels in each direction (relative error ~1e-4 for these maps).
fn quadrature(width: usize, height: usize, values: &[f32]) -> f64 {
    let pi = std::f64::consts::PI;
    let (nu, nv) = (64 * width, 64 * height);
    let mut sum = 0.0;
    for j in 0..nv {
        let v = (j as f64 + 0.5) / nv as f64;
        let band = (pi * j as f64 / nv as f64).cos() - (pi * (j + 1) as f64 / nv as f64).cos();
        for i in 0..nu {
            let u = (i as f64 + 0.5) / nu as f64;
            sum += bilinear(width, height, values, u, v) * band * 2.0 * pi / nu as f64;
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
    // Texel centres: the top row at θ = 45°, the bottom one at 135°.
    let (s, c) = (0.5f32, 0.5f32);
    let h = 0.5f32.sqrt();
    let dirs = [
        Vec3::new(s, h, -c),
        Vec3::new(s, h, c),
        Vec3::new(-s, h, c),
        Vec3::new(-s, h, -c),
    ];
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * b;
    for (i, d) in dirs.iter().enumerate() {
        assert!(
            close(light.le(*d, &wl())[0], values[i]),
            "top row, column {i}"
        );
        let below = Vec3::new(d.x, -d.y, d.z);
        assert!(
            close(light.le(below, &wl())[0], values[4 + i]),
            "bottom row, column {i}"
        );
    }
    // Halfway between two centres of the top row: their mean; above the top centres (towards
    // the pole) the row is held.
    let mid = uv_to_direction(Vec2::new(0.25, 0.25));
    assert!(
        close(light.le(mid, &wl())[0], 1.5),
        "{}",
        light.le(mid, &wl())[0]
    );
    let pole = uv_to_direction(Vec2::new(0.125, 0.05));
    assert!(close(light.le(pole, &wl())[0], 1.0));
    // Across the seam u = 0: the last and first columns blend.
    let seam = uv_to_direction(Vec2::new(0.0, 0.75));
    assert!(
        close(light.le(seam, &wl())[0], 12.5),
        "{}",
        light.le(seam, &wl())[0]
    );
    assert_eq!(direction_to_uv(Vec3::Y).y, 0.0);
    assert_eq!(direction_to_uv(-Vec3::Y).y, 1.0);
    // `to_world` rotates the map: the world direction R d sees what d saw before.
    let rotated = map(4, 2, &values, rotation());
    for d in dirs {
        let (a, b) = (
            rotated.le(rotation().vector(d), &wl())[0],
            light.le(d, &wl())[0],
        );
        assert!((a - b).abs() <= 1e-4 * b, "{a} {b}");
    }
}

#[test]
fn density_is_positive_wherever_the_interpolated_radiance_is() {
    // One bright texel among zeros: its bilinear footprint reaches into eight neighbours.
    let (w, h) = (8, 6);
    let mut values = vec![0.0; w * h];
    values[2 * w + 7] = 10.0;
    let light = Light::EnvMap(map(w, h, &values, Transform::IDENTITY));
    let ctx = LightSampleContext {
        p: Vec3::ZERO,
        n: Vec3::ZERO,
    };
    let mut rng = Pcg32::new(12, 3);
    let mut lit = 0;
    for _ in 0..100_000 {
        let d = square_to_uniform_sphere(rng.next_vec2());
        if light.le(d, &wl())[0] > 0.0 {
            lit += 1;
            assert!(light.pdf_li(&ctx, d, &[], None) > 0.0, "{d}");
        }
    }
    assert!(lit > 1000, "{lit}");
    // Light sampling alone then integrates the map.
    let want = quadrature(w, h, &values);
    let (mean, sigma) = mean_and_sigma((0..100_000).map(|_| {
        match light.sample_li(&ctx, rng.next_vec2(), &wl(), &[]) {
            Some(s) => (s.l[0] / s.pdf) as f64,
            None => 0.0,
        }
    }));
    assert!(
        (mean - want).abs() <= 4.0 * sigma + 1e-3 * want,
        "{mean} vs {want} ± {sigma}"
    );
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
    // The centre of texel 1 (top row, second column).
    let d = uv_to_direction(Vec2::new(0.375, 0.25));
    let want = Spectrum::rgb_illuminant([0.8, 0.4, 0.1]).sample(&wl()) * 2.0;
    let got = light.le(d, &wl());
    for i in 0..4 {
        assert!((got[i] - want[i]).abs() <= 1e-5 * want[i].abs().max(1e-3));
    }
}
