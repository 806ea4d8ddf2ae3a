//! The sky part of `sunsky` (and Mitsuba 0.6's `sky`): Preetham's clear sky as an environment
//! light at infinity, evaluated analytically per direction and importance-sampled from a
//! lat–long luminance grid baked at construction.

use super::preetham::{PreethamSky, LUMINOUS_EFFICACY};
use crate::light::envmap::uv_to_direction;
use crate::light::infinite::{latlong_pdf, InfiniteLight};
use crate::light::Distribution2D;
use crate::math::{Transform, Vec2, Vec3, PI};
use crate::spectrum::cie::CIE_Y_INTEGRAL;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Columns and rows of the sampling grid (the envmap's lat–long mapping, +y at the top row).
const GRID_W: usize = 128;
const GRID_H: usize = 64;
/// Sub-samples per grid cell and axis when baking the luminance.
const BAKE_SUB: usize = 2;

/// Preetham's sky as a light.
#[derive(Clone, Debug)]
pub struct SkyLight {
    /// `None` when the sun is below the horizon: the model has no twilight, so the sky is black.
    model: Option<PreethamSky>,
    scale: f32,
    to_world: Transform,
    to_local: Transform,
    dist: Distribution2D,
    /// ∫ luminance dω over the sky (cd/m² · sr, before `scale`).
    luminance_integral: f32,
}

impl SkyLight {
    /// A sky of turbidity `turbidity` with the sun along `sun_local` (the sky's frame, +y up),
    /// radiance multiplied by `scale`, turned into the world by `to_world` (a rotation).
    pub fn new(turbidity: f32, sun_local: Vec3, scale: f32, to_world: Transform) -> SkyLight {
        let model = PreethamSky::new(turbidity, sun_local);
        let mut weights = vec![0.0f32; GRID_W * GRID_H];
        let mut integral = 0.0f64;
        if let Some(m) = &model {
            let d_phi = 2.0 * std::f64::consts::PI / GRID_W as f64;
            // Only the upper half of the grid sees the sky; the lower rows stay zero.
            for y in 0..GRID_H / 2 {
                let sin_theta = (PI * (y as f32 + 0.5) / GRID_H as f32).sin();
                let t0 = std::f64::consts::PI * y as f64 / GRID_H as f64;
                let t1 = std::f64::consts::PI * (y + 1) as f64 / GRID_H as f64;
                let solid_angle = d_phi * (t0.cos() - t1.cos());
                for x in 0..GRID_W {
                    let mut lum = 0.0;
                    for sy in 0..BAKE_SUB {
                        for sx in 0..BAKE_SUB {
                            let uv = Vec2::new(
                                (x as f32 + (sx as f32 + 0.5) / BAKE_SUB as f32) / GRID_W as f32,
                                (y as f32 + (sy as f32 + 0.5) / BAKE_SUB as f32) / GRID_H as f32,
                            );
                            lum += m.luminance(uv_to_direction(uv));
                        }
                    }
                    let lum = lum / (BAKE_SUB * BAKE_SUB) as f32;
                    weights[y * GRID_W + x] = lum * sin_theta;
                    integral += lum as f64 * solid_angle;
                }
            }
            // A floor keeps every sky direction samplable (pdf > 0 wherever radiance may be).
            let max = weights.iter().copied().fold(0.0, f32::max);
            for (i, w) in weights.iter_mut().enumerate().take(GRID_W * GRID_H / 2) {
                let sin_theta = (PI * ((i / GRID_W) as f32 + 0.5) / GRID_H as f32).sin();
                *w = w.max(1e-4 * max * sin_theta);
            }
        }
        let scale = if scale.is_finite() {
            scale.max(0.0)
        } else {
            0.0
        };
        SkyLight {
            model,
            scale,
            to_world,
            to_local: to_world.inverse(),
            dist: Distribution2D::new(&weights, GRID_W, GRID_H),
            luminance_integral: integral as f32,
        }
    }

    /// The sky model (`None` with the sun below the horizon).
    pub fn model(&self) -> Option<&PreethamSky> {
        self.model.as_ref()
    }

    fn local(&self, dir: Vec3) -> Vec3 {
        self.to_local.vector(dir).normalize_or_zero()
    }
}

impl InfiniteLight for SkyLight {
    fn sample_wi(&self, _: Vec3, u: Vec2) -> Option<Vec3> {
        self.model.as_ref()?;
        let (uv, _, _) = self.dist.sample(u);
        Some(
            self.to_world
                .vector(uv_to_direction(uv))
                .normalize_or_zero(),
        )
    }

    fn pdf_li(&self, _: Vec3, wi: Vec3) -> f32 {
        if self.model.is_none() {
            return 0.0;
        }
        latlong_pdf(self.local(wi), |uv| self.dist.pdf(uv))
    }

    fn le(&self, dir: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let Some(m) = &self.model else {
            return SampledSpectrum::ZERO;
        };
        if self.scale == 0.0 {
            return SampledSpectrum::ZERO;
        }
        SampledSpectrum(m.radiance(self.local(dir), wl.lambda)) * self.scale
    }

    /// Power falling on the scene's bounding sphere, π r² ∫ L dω, with the spectrum reduced to
    /// the flat spectrum of the same luminance.
    fn power(&self, r: f32) -> f32 {
        let mean_radiance = self.luminance_integral / (LUMINOUS_EFFICACY * CIE_Y_INTEGRAL);
        PI * r * r * mean_radiance * self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::{mean_and_sigma, wl};
    use super::*;
    use crate::light::{Light, LightSampleContext};
    use crate::math::Pcg32;

    fn sun_at(zenith_deg: f32, azimuth_deg: f32) -> Vec3 {
        let (sz, cz) = zenith_deg.to_radians().sin_cos();
        let (sa, ca) = azimuth_deg.to_radians().sin_cos();
        Vec3::new(sz * sa, cz, -sz * ca)
    }

    /// ∫ L(λ) dω over the upper hemisphere by midpoint quadrature in (cos θ, φ).
    fn quadrature(sky: &SkyLight, lambda: usize, n: usize) -> f64 {
        let mut sum = 0.0;
        for i in 0..n {
            let ct = (i as f32 + 0.5) / n as f32;
            let st = (1.0 - ct * ct).sqrt();
            for j in 0..2 * n {
                let phi = PI * (j as f32 + 0.5) / n as f32;
                let d = Vec3::new(st * phi.cos(), ct, st * phi.sin());
                sum += sky.le(d, &wl())[lambda] as f64;
            }
        }
        sum * (1.0 / n as f64) * (std::f64::consts::PI / n as f64)
    }

    #[test]
    fn radiance_is_positive_continuous_and_black_below_the_horizon() {
        let sky = SkyLight::new(3.0, sun_at(40.0, 120.0), 1.0, Transform::IDENTITY);
        let mut rng = Pcg32::new(3, 0);
        for _ in 0..2000 {
            let d = crate::math::warp::square_to_uniform_sphere(rng.next_vec2());
            let l = sky.le(d, &wl());
            if d.y > 1e-3 {
                assert!(l.min_value() > 0.0 && l.is_finite(), "{d} {l:?}");
                // A 1e-3 rad step changes radiance by at most a few per mille.
                let e = (d + Vec3::new(1e-3, 0.0, 0.0)).normalize();
                let l2 = sky.le(e, &wl());
                if e.y > 1e-3 {
                    for i in 0..4 {
                        assert!((l2[i] - l[i]).abs() <= 0.01 * l[i], "{d} {l:?} {l2:?}");
                    }
                }
            } else if d.y < 0.0 {
                assert!(l.is_black());
            }
        }
        // The sun below the horizon switches the sky off.
        let night = SkyLight::new(3.0, sun_at(95.0, 0.0), 1.0, Transform::IDENTITY);
        assert!(night.le(Vec3::Y, &wl()).is_black() && night.pdf_li(Vec3::ZERO, Vec3::Y) == 0.0);
    }

    #[test]
    fn hazy_sky_is_brightest_around_the_sun_and_blue_far_from_it() {
        let sun = sun_at(50.0, 90.0);
        let sky = SkyLight::new(8.0, sun, 1.0, Transform::IDENTITY);
        let m = sky.model().unwrap();
        let near = m.luminance((sun + Vec3::new(0.0, 0.0, 0.05)).normalize());
        let mut rng = Pcg32::new(9, 0);
        for _ in 0..500 {
            let d = crate::math::warp::square_to_uniform_sphere(rng.next_vec2());
            if d.y > 0.0 && d.dot(sun) < 0.9 {
                assert!(m.luminance(d) < near, "{d}");
            }
        }
        // Clear sky: far from the sun (near the zenith, opposite side) blue exceeds red.
        let clear = SkyLight::new(2.5, sun_at(60.0, 90.0), 1.0, Transform::IDENTITY);
        let l = clear.le(sun_at(30.0, 270.0), &wl());
        assert!(l[0] > l[3], "{l:?}");
    }

    #[test]
    fn importance_sampling_integrates_the_sky_and_matches_pdf() {
        let rot = Transform::rotate(Vec3::new(0.3, 0.2, 1.0), 25.0).unwrap();
        let sky = SkyLight::new(4.0, sun_at(35.0, 200.0), 2.0, rot);
        let light = Light::Sky(sky.clone().into());
        assert!(light.is_infinite() && !light.is_delta());
        // ∫ L dω in the sky's own frame (the rotation does not change the integral).
        let unrotated = SkyLight::new(4.0, sun_at(35.0, 200.0), 2.0, Transform::IDENTITY);
        let want = quadrature(&unrotated, 1, 400);
        let ctx = LightSampleContext {
            p: Vec3::ZERO,
            n: Vec3::ZERO,
        };
        let mut rng = Pcg32::new(21, 0);
        let (mean, sigma) = mean_and_sigma((0..100_000).map(|_| {
            let Some(s) = light.sample_li(&ctx, rng.next_vec2(), &wl(), &[]) else {
                return 0.0;
            };
            let pdf = light.pdf_li(&ctx, s.wi, &[], None);
            assert!((pdf - s.pdf).abs() <= 1e-4 * s.pdf, "{pdf} vs {}", s.pdf);
            assert_eq!(light.le(s.wi, &wl())[1], s.l[1]);
            (s.l[1] / s.pdf) as f64
        }));
        // Quadrature error of the 400 × 800 midpoint rule is far below σ.
        assert!(
            (mean - want).abs() <= 4.0 * sigma,
            "{mean} vs {want} ± {sigma}"
        );
        // Importance sampling pays off: relative σ per sample well below uniform sampling's.
        assert!(sigma * (100_000f64).sqrt() < 0.5 * mean);
    }

    #[test]
    fn pdf_integrates_to_one() {
        let sky = SkyLight::new(3.0, sun_at(20.0, 0.0), 1.0, Transform::IDENTITY);
        let n = 300;
        let mut sum = 0.0f64;
        for i in 0..n {
            let ct = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
            let st = (1.0 - ct * ct).sqrt();
            for j in 0..2 * n {
                let phi = PI * (j as f32 + 0.5) / n as f32;
                let d = Vec3::new(st * phi.cos(), ct, st * phi.sin());
                sum += sky.pdf_li(Vec3::ZERO, d) as f64;
            }
        }
        let total = sum * (2.0 / n as f64) * (std::f64::consts::PI / n as f64);
        assert!((total - 1.0).abs() < 0.01, "{total}");
    }
}
