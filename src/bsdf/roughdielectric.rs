//! Rough dielectric interface: microfacet reflection and refraction of Walter et al. 2007,
//! "Microfacet Models for Refraction through Rough Surfaces" (EGSR), with GGX or Beckmann
//! normals, height-correlated Smith G and visible-normal sampling (see [`super::microfacet`]).
//!
//! With η' the index of the wi side over the wo side, the generalised half vector is
//! wm ∝ η' wi + wo (oriented to +z); reflection is F D G / (4 |cos θo cos θi|) and refraction
//! (1 − F) D G |wi·wm| |wo·wm| / (|cos θo cos θi| (wi·wm + wo·wm/η')²), divided by η'² in
//! radiance mode only. Sampling picks reflection with probability F(wo·wm), so that the
//! importance-mode weight is G/G1(wo) ≤ 1.
//!
//! | Mitsuba parameter        | type     | default | unit |
//! |--------------------------|----------|---------|------|
//! | `distribution`           | string   | `beckmann` | `ggx` or `beckmann` |
//! | `alpha`                  | float/texture | 0.1 | RMS slope |
//! | `alpha_u`, `alpha_v`     | float/texture | `alpha` | anisotropic α |
//! | `int_ior`, `ext_ior`     | float or name | 1.5046, 1.000277 | refractive index |
//! | `specular_reflectance`   | spectrum/texture | 1.0 | factor |
//! | `specular_transmittance` | spectrum/texture | 1.0 | factor |
//!
//! Plugin name `roughdielectric`; two-sided by nature (wo.z < 0 is inside).
//! Known limits: single scattering between microfacets (energy loss at high roughness); real
//! index only.

use super::fresnel::fresnel_dielectric;
use super::microfacet::MicrofacetDistribution;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{reflect, refract, Pcg32, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// Rough dielectric with relative index `eta` (interior / exterior).
#[derive(Clone, Debug)]
pub struct RoughDielectricBxdf {
    pub distrib: MicrofacetDistribution,
    pub eta: f32,
    pub r_s: SampledSpectrum,
    pub t_s: SampledSpectrum,
}

/// The microfacet normal joining a pair of directions, with the index ratio, or `None` for
/// degenerate pairs and back-facing microfacets.
pub(super) fn half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<(Vec3, f32, bool)> {
    if wo.z == 0.0 || wi.z == 0.0 {
        return None;
    }
    let reflect = wo.z * wi.z > 0.0;
    let etap = if reflect {
        1.0
    } else if wo.z > 0.0 {
        eta
    } else {
        1.0 / eta
    };
    let wm = wi * etap + wo;
    if wm.length_squared() == 0.0 {
        return None;
    }
    let mut wm = wm.normalize();
    if wm.z < 0.0 {
        wm = -wm;
    }
    // Each direction must see the microfacet from its own side of the macrosurface.
    if wm.dot(wi) * wi.z < 0.0 || wm.dot(wo) * wo.z < 0.0 {
        return None;
    }
    Some((wm, etap, reflect))
}

/// Fresnel reflectance of the microfacet for the pair. Mathematically F(wo·wm) = F(wi·wm) for a
/// refraction pair; evaluating it from the optically thinner side avoids the cancellation in
/// cos θt near total internal reflection, which keeps f reciprocal to f32 precision.
fn microfacet_fresnel(wo: Vec3, wi: Vec3, wm: Vec3, eta: f32) -> f32 {
    let w = if (wo.z > 0.0) == (eta >= 1.0) { wo } else { wi };
    fresnel_dielectric(w.dot(wm), eta)
}

impl RoughDielectricBxdf {
    /// A rough interface.
    pub fn new(
        distrib: MicrofacetDistribution,
        eta: f32,
        r_s: SampledSpectrum,
        t_s: SampledSpectrum,
    ) -> Self {
        RoughDielectricBxdf {
            distrib,
            eta,
            r_s,
            t_s,
        }
    }
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::GLOSSY_REFLECTION | BxdfFlags::GLOSSY_TRANSMISSION
    }
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode, _rng: &mut Pcg32) -> SampledSpectrum {
        let Some((wm, etap, is_reflection)) = half_vector(wo, wi, self.eta) else {
            return SampledSpectrum::ZERO;
        };
        let d = self.distrib.d(wm);
        let g = self.distrib.g(wo, wi);
        let fr = microfacet_fresnel(wo, wi, wm, self.eta);
        if is_reflection {
            return self.r_s * (fr * d * g / (4.0 * wo.z * wi.z).abs());
        }
        let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
        let mut ft = (1.0 - fr) * d * g * (wi.dot(wm) * wo.dot(wm) / (wi.z * wo.z * denom)).abs();
        if mode == TransportMode::Radiance {
            ft /= etap * etap;
        }
        self.t_s * ft
    }
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> f32 {
        let Some((wm, etap, is_reflection)) = half_vector(wo, wi, self.eta) else {
            return 0.0;
        };
        let fr = microfacet_fresnel(wo, wi, wm, self.eta);
        let pm = self.distrib.pdf(wo, wm);
        if is_reflection {
            pm / (4.0 * wo.dot(wm).abs()) * fr
        } else {
            // Jacobian of the refraction map wm → wi (Walter et al. 2007, eq. 17).
            let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
            pm * wi.dot(wm).abs() / denom * (1.0 - fr)
        }
    }
    pub fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let wm = self.distrib.sample_wm(wo, u);
        let cos_om = wo.dot(wm);
        let fr = fresnel_dielectric(cos_om, self.eta);
        let (wi, flags, etap) = if uc < fr {
            (reflect(wo, wm), BxdfFlags::GLOSSY_REFLECTION, 1.0)
        } else {
            // Refract about the microfacet normal on wo's side.
            let (n, etap) = if cos_om > 0.0 {
                (wm, self.eta)
            } else {
                (-wm, 1.0 / self.eta)
            };
            (refract(wo, n, etap)?, BxdfFlags::GLOSSY_TRANSMISSION, etap)
        };
        let is_reflection = flags == BxdfFlags::GLOSSY_REFLECTION;
        if (wi.z * wo.z > 0.0) != is_reflection || wi.z == 0.0 {
            return None;
        }
        // Evaluate from wi so that sampling and evaluation agree.
        let pdf = self.pdf(wo, wi, mode, rng);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = self.f(wo, wi, mode, rng);
        Some(BsdfSample {
            eta: etap,
            ..BsdfSample::new(f, wi, pdf, flags)
        })
    }
}
