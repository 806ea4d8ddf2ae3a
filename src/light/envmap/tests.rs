use super::super::test_util::{mean_and_sigma, wl};
use super::super::{AtInfinity, Light, LightSampleContext};
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

/// The map's radiance at (u, v), interpolated bilinearly between texel centres ((i + ½)/W in
/// u, wrapping; j/(H − 1) in v), written independently of the light's own lookup.
fn bilinear(width: usize, height: usize, values: &[f32], u: f64, v: f64) -> f64 {
    let x = u * width as f64 - 0.5;
    let y = v * (height - 1) as f64;
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
    // Texel centres of a 4 × 3 map: columns at φ = 45°, 135°, 225°, 315° from −z towards +x,
    // rows on the poles and the equator (Mitsuba 3's convention).
    let values = [
        1.0, 2.0, 3.0, 4.0, 11.0, 12.0, 13.0, 14.0, 21.0, 22.0, 23.0, 24.0,
    ];
    let light = map(4, 3, &values, Transform::IDENTITY);
    let h = 0.5f32.sqrt();
    let dirs = [
        Vec3::new(h, 0.0, -h),
        Vec3::new(h, 0.0, h),
        Vec3::new(-h, 0.0, h),
        Vec3::new(-h, 0.0, -h),
    ];
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * b;
    let le = |d: Vec3| light.le(d, &wl())[0];
    for (i, d) in dirs.iter().enumerate() {
        assert!(
            close(le(*d), values[4 + i]),
            "equator, column {i}: {}",
            le(*d)
        );
    }
    // Halfway between two column centres on the equator: their mean; across the seam u = 0:
    // the last and first columns; halfway to a pole: the mean of the two rows.
    assert!(close(le(uv_to_direction(Vec2::new(0.25, 0.5))), 11.5));
    assert!(close(le(uv_to_direction(Vec2::new(0.0, 0.5))), 12.5));
    assert!(close(le(uv_to_direction(Vec2::new(0.125, 0.25))), 6.0));
    assert!(close(le(uv_to_direction(Vec2::new(0.375, 0.75))), 17.0));
    assert_eq!(direction_to_uv(Vec3::Y).y, 0.0);
    assert_eq!(direction_to_uv(-Vec3::Y).y, 1.0);
    // `to_world` rotates the map: the world direction R d sees what d saw before.
    let rotated = map(4, 3, &values, rotation());
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
    let light = Light::EnvMap(map(w, h, &values, Transform::IDENTITY).into());
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
    let light = Light::EnvMap(map(w, h, &values, rotation()).into());
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
    let (mean, sigma) = mean_and_sigma(
        dirs.iter()
            .map(|&d| four_pi * light.pdf_li(Vec3::ZERO, d) as f64),
    );
    assert!((mean - 1.0).abs() <= 4.0 * sigma, "{mean} ± {sigma}");
}

#[test]
fn black_map_and_bad_images() {
    let light = AtInfinity::from(map(4, 2, &[0.0; 8], Transform::IDENTITY));
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
    // Texel 1 (top row, second column) lies on the pole; halfway to the (black) bottom row
    // under column 1, half of its spectrum times half of its scale: a quarter (Mitsuba 3.9
    // gives the same, measured through its Python API).
    let d = uv_to_direction(Vec2::new(0.375, 0.5));
    let black = match Spectrum::rgb_illuminant([0.0; 3]) {
        Spectrum::RgbIlluminant { poly, .. } => poly,
        other => panic!("{other:?}"),
    };
    let (scale, poly) = match Spectrum::rgb_illuminant([0.8, 0.4, 0.1]) {
        Spectrum::RgbIlluminant { scale, poly } => (scale, poly),
        other => panic!("{other:?}"),
    };
    let want = crate::spectrum::SampledSpectrum::from_fn(|k| {
        let l = wl().lambda[k];
        0.5 * (poly.eval(l) + black.eval(l)) * 0.5 * scale * 2.0 * crate::spectrum::cie::d65(l)
    });
    let got = light.le(d, &wl());
    for i in 0..4 {
        assert!((got[i] - want[i]).abs() <= 1e-5 * want[i].abs().max(1e-3));
    }
}

#[test]
fn spectra_and_scales_are_blended_separately_as_in_mitsuba() {
    // Two rows of different hue and brightness: halfway, the blend of the normalised spectra
    // times the blend of the scales.
    let (blue, warm) = ([0.1f32, 0.2, 0.6], [0.5f32, 0.3, 0.2]);
    let mut img = RgbImage::new(4, 3);
    for x in 0..4 {
        img.data[x] = blue;
        img.data[4 + x] = blue;
        img.data[8 + x] = warm;
    }
    let light = EnvMapLight::new(img, 1.0, Transform::IDENTITY).unwrap();
    let got = light.le(uv_to_direction(Vec2::new(0.3, 0.75)), &wl());
    let parts = |c: [f32; 3]| match Spectrum::rgb_illuminant(c) {
        Spectrum::RgbIlluminant { scale, poly } => (scale, poly),
        other => panic!("{other:?}"),
    };
    let ((fa, pa), (fb, pb)) = (parts(blue), parts(warm));
    for (k, &l) in wl().lambda.iter().enumerate() {
        let want = 0.5 * (pa.eval(l) + pb.eval(l)) * 0.5 * (fa + fb) * crate::spectrum::cie::d65(l);
        assert!(
            (got[k] - want).abs() <= 1e-5 * want,
            "{l}: {} vs {want}",
            got[k]
        );
    }
}
