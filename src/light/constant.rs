//! Constant environment (Mitsuba `constant`): the same radiance L(λ) arrives from every
//! direction at infinity.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `radiance` | spectrum | 1.0 | W·m⁻²·sr⁻¹·nm⁻¹ | radiance from every direction (RGB and numbers: times D65) |
//!
//! Sampling: with a normal at the shading point, a defensive mixture (Hesterberg 1995) of 90 %
//! cosine-weighted hemisphere about the normal and 10 % uniform sphere, so that a diffuse surface
//! gets nearly zero variance while every direction (e.g. through a transmissive surface) keeps a
//! positive density; without a normal, the uniform sphere. Vertices whose BSDF is glossy, a
//! plastic or a closed-form coat (and Lambertian ones beside other lights) leave this light to
//! their BSDF samples and do not choose it for next-event estimation (see
//! [`crate::integrator::path`]).
//!
//! Known limits: the visibility point is placed beyond the scene's bounding sphere, so
//! [`super::Light::preprocess`] must be called first.

use super::infinite::InfiniteLight;
use super::Light;
use crate::plugin::{declare, Args, Param, SceneError};

declare!(PLUGIN: Vec<Light>, Option<u32> = Emitter "constant" []
    "uniform environment light"
    [&[
        Param::emission("radiance")
            .unit("W·m⁻²·sr⁻¹·nm⁻¹")
            .doc("radiance from every direction (RGB and numbers: times D65)"),
    ]] load);

fn load(a: &mut Args, _: Option<u32>) -> Result<Vec<Light>, SceneError> {
    let radiance = a.spectrum("radiance")?;
    Ok(vec![Light::Constant(ConstantLight::new(radiance).into())])
}
use crate::math::warp::{square_to_cosine_hemisphere, square_to_uniform_sphere};
use crate::math::{Frame, Vec2, Vec3, INV_4PI, INV_PI, PI};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

/// Share of cosine-weighted samples when a normal is known.
const COSINE_SHARE: f32 = 0.9;

/// A constant environment light.
#[derive(Clone, Debug)]
pub struct ConstantLight {
    pub radiance: Spectrum,
}

impl ConstantLight {
    /// A uniform environment of the given radiance.
    pub fn new(radiance: Spectrum) -> ConstantLight {
        ConstantLight { radiance }
    }
}

impl InfiniteLight for ConstantLight {
    fn sample_wi(&self, n: Vec3, u: Vec2) -> Option<Vec3> {
        let n = n.normalize_or_zero();
        let wi = if n == Vec3::ZERO {
            square_to_uniform_sphere(u)
        } else if u.x < COSINE_SHARE {
            let u = Vec2::new(u.x / COSINE_SHARE, u.y);
            Frame::from_z(n).to_world(square_to_cosine_hemisphere(u))
        } else {
            let u = Vec2::new((u.x - COSINE_SHARE) / (1.0 - COSINE_SHARE), u.y);
            square_to_uniform_sphere(u.min(Vec2::splat(crate::math::ONE_MINUS_EPSILON)))
        };
        Some(wi.normalize_or_zero())
    }

    fn pdf_li(&self, n: Vec3, wi: Vec3) -> f32 {
        let n = n.normalize_or_zero();
        if n == Vec3::ZERO {
            return INV_4PI;
        }
        COSINE_SHARE * n.dot(wi).max(0.0) * INV_PI + (1.0 - COSINE_SHARE) * INV_4PI
    }

    fn le(&self, _: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.radiance.sample(wl)
    }

    /// Power falling on the scene's bounding sphere: π r² · 4π L.
    fn power(&self, r: f32) -> f32 {
        4.0 * PI * PI * r * r * super::spectrum_mean(&self.radiance)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::{mean_and_sigma, wl};
    use super::super::LightSampleContext;
    use super::*;
    use crate::math::Pcg32;

    #[test]
    fn irradiance_estimate_is_pi_l() {
        // E[L max(0, cos θ) / pdf] = π L on a surface with normal n, for both strategies.
        let light = Light::Constant(ConstantLight::new(Spectrum::Constant(2.0)).into());
        assert!(light.is_infinite() && !light.is_delta());
        let n = Vec3::new(1.0, 2.0, -0.5).normalize();
        for ctx_n in [n, Vec3::ZERO] {
            let ctx = LightSampleContext {
                p: Vec3::ZERO,
                n: ctx_n,
            };
            let mut rng = Pcg32::new(17, 0);
            let (mean, sigma) = mean_and_sigma((0..50_000).map(|_| {
                let s = light.sample_li(&ctx, rng.next_vec2(), &wl(), &[]).unwrap();
                let pdf = light.pdf_li(&ctx, s.wi, &[], None);
                assert!((pdf - s.pdf).abs() <= 1e-5 * s.pdf);
                assert!((s.wi.length() - 1.0).abs() < 1e-4);
                (s.l[1] * s.wi.dot(n).max(0.0) / s.pdf) as f64
            }));
            let want = 2.0 * std::f64::consts::PI;
            assert!(
                (mean - want).abs() <= 4.0 * sigma + 1e-4,
                "{mean} vs {want} ± {sigma}"
            );
        }
        assert_eq!(light.le(Vec3::X, &wl())[3], 2.0);
    }
}
