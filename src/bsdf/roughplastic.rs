//! Rough plastic: a diffuse substrate under a rough dielectric coating, after Mitsuba's
//! `roughplastic` (Weidlich & Wilkie 2007 layering; Walter et al. 2007 microfacets). Specular
//! part: the microfacet reflection F(wo·wm) D G / (4 cos θo cos θi) times
//! `specular_reflectance`, with GGX or Beckmann (isotropic) and height-correlated Smith G.
//! Diffuse part: the smooth-plastic substrate term (see [`super::plastic`]),
//!
//! f_d = (1 − F(cos θo)) (1 − F(cos θi)) ρ' / (π η²),  ρ' = ρ/(1 − F̄ᵢ) or ρ/(1 − ρF̄ᵢ),
//!
//! i.e. the coating's transmittance is approximated by the smooth-interface Fresnel factor.
//!
//! Sampling picks the specular lobe with probability F(cos θo)·s / (F·s + (1 − F)(1 − s))
//! (s: Mitsuba's specular sampling weight from the mean reflectances), sampling visible
//! normals, and the cosine-weighted diffuse lobe otherwise; `pdf` is the mixture of both.
//!
//! | Mitsuba parameter      | type     | default | unit |
//! |------------------------|----------|---------|------|
//! | `distribution`         | string   | `beckmann` | `ggx` or `beckmann` |
//! | `alpha`                | float/texture | 0.1 | RMS slope |
//! | `diffuse_reflectance`  | spectrum/texture | 0.5 | albedo |
//! | `specular_reflectance` | spectrum/texture | 1.0 | factor |
//! | `int_ior`, `ext_ior`   | float or name | 1.49, 1.000277 | refractive index |
//! | `nonlinear`            | boolean  | false | — |
//!
//! Plugin name `roughplastic`. One-sided. Known limits: Mitsuba 3 replaces the smooth Fresnel
//! transmittance of the substrate term by the rough interface's tabulated transmittance; ophis
//! does not, so with a white substrate the albedo is not exactly 1: measured with ρ = 1,
//! η = 1.5, it is 0.98–1.003 up to θo = 45° and drops at grazing angles (0.68 at 80° for GGX
//! α = 0.6) where the microfacet lobe loses energy to shadowing. The specular lobe is
//! single-scattering. Roughness is isotropic (`alpha` only), as in Mitsuba.

use super::fresnel::fresnel_dielectric;
use super::microfacet::MicrofacetDistribution;
use super::plastic::{specular_probability, specular_weight, substrate};
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{reflect, warp, Pcg32, Vec2, Vec3, INV_PI};
use crate::spectrum::SampledSpectrum;

/// Rough plastic.
#[derive(Clone, Debug)]
pub struct RoughPlasticBxdf {
    pub distrib: MicrofacetDistribution,
    pub eta: f32,
    /// Diffuse substrate term ρ'/η².
    pub kd: SampledSpectrum,
    pub r_s: SampledSpectrum,
    pub spec_weight: f32,
}

impl RoughPlasticBxdf {
    /// Rough plastic (see the module doc for the parameters).
    pub fn new(
        distrib: MicrofacetDistribution,
        eta: f32,
        rho: SampledSpectrum,
        r_s: SampledSpectrum,
        fdr_int: f32,
        nonlinear: bool,
    ) -> Self {
        RoughPlasticBxdf {
            distrib,
            eta,
            kd: substrate(rho, eta, fdr_int, nonlinear),
            r_s,
            spec_weight: specular_weight(r_s, rho),
        }
    }
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::GLOSSY_REFLECTION | BxdfFlags::DIFFUSE_REFLECTION
    }
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> SampledSpectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let t =
            (1.0 - fresnel_dielectric(wo.z, self.eta)) * (1.0 - fresnel_dielectric(wi.z, self.eta));
        let mut f = self.kd * (t * INV_PI);
        let wm = wo + wi;
        if wm.length_squared() > 0.0 {
            let wm = wm.normalize();
            let spec = fresnel_dielectric(wo.dot(wm), self.eta)
                * self.distrib.d(wm)
                * self.distrib.g(wo, wi)
                / (4.0 * wo.z * wi.z);
            f += self.r_s * spec;
        }
        f
    }
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let ps = specular_probability(fresnel_dielectric(wo.z, self.eta), self.spec_weight);
        let mut p = (1.0 - ps) * warp::square_to_cosine_hemisphere_pdf(wi);
        let wm = wo + wi;
        if wm.length_squared() > 0.0 {
            let wm = wm.normalize();
            p += ps * self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm));
        }
        p
    }
    pub fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let ps = specular_probability(fresnel_dielectric(wo.z, self.eta), self.spec_weight);
        let wi = if uc < ps {
            reflect(wo, self.distrib.sample_wm(wo, u))
        } else {
            warp::square_to_cosine_hemisphere(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi, mode, rng);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = self.f(wo, wi, mode, rng);
        let flags = if uc < ps {
            BxdfFlags::GLOSSY_REFLECTION
        } else {
            BxdfFlags::DIFFUSE_REFLECTION
        };
        Some(BsdfSample::new(f, wi, pdf, flags))
    }
}
