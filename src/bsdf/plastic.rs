//! Smooth plastic: a diffuse substrate under a smooth dielectric coating, the model of
//! Mitsuba's `plastic` (after Weidlich & Wilkie 2007, "Arbitrarily Layered Micro-Facet
//! Surfaces", with the substrate's internal reflections summed as in Kelemen & Szirmay-Kalos
//! 2001). Specular part: a delta lobe of weight `specular_reflectance`·F(cos θo). Diffuse part:
//!
//! f = (1 − F(cos θo)) (1 − F(cos θi)) ρ' / (π η²),
//! ρ' = ρ / (1 − F̄ᵢ) (linear) or ρ / (1 − ρ F̄ᵢ) (`nonlinear`),
//!
//! where F̄ᵢ is the cosine-weighted average of the interface's internal reflectance
//! ([`super::fresnel::fresnel_diffuse_reflectance`] of 1/η, by quadrature). With ρ = 1 the model
//! conserves energy exactly (albedo 1), which the tests check.
//!
//! Sampling picks the specular lobe with probability F·s / (F·s + (1 − F)(1 − s)), where
//! s = mean(specular_reflectance) / (mean(specular) + mean(diffuse_reflectance)) is Mitsuba's
//! specular sampling weight, and the diffuse lobe by cosine sampling otherwise.
//!
//! | Mitsuba parameter      | type     | default | unit |
//! |------------------------|----------|---------|------|
//! | `diffuse_reflectance`  | spectrum/texture | 0.5 | albedo |
//! | `specular_reflectance` | spectrum/texture | 1.0 | factor |
//! | `int_ior`              | float or name | 1.49 (`polypropylene`) | refractive index |
//! | `ext_ior`              | float or name | 1.000277 (`air`) | refractive index |
//! | `nonlinear`            | boolean  | false | — |
//!
//! Plugin name `plastic` (0.6 `diffuseReflectance`, `intIOR` … upgraded by the loader).
//! One-sided. Known limits: no absorption in the coating, no multiple scattering in it.

use super::fresnel::fresnel_dielectric;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{warp, Pcg32, Vec2, Vec3, INV_PI};
use crate::spectrum::SampledSpectrum;

/// Smooth plastic.
#[derive(Clone, Debug)]
pub struct PlasticBxdf {
    /// Relative index of the coating.
    pub eta: f32,
    /// Diffuse substrate term ρ' / η² (internal reflections and the solid-angle compression
    /// already applied).
    pub kd: SampledSpectrum,
    pub r_s: SampledSpectrum,
    /// Probability weight s of the specular lobe (before the Fresnel factor).
    pub spec_weight: f32,
}

/// The substrate factor ρ'/η² shared by the smooth and rough plastics.
pub(crate) fn substrate(
    rho: SampledSpectrum,
    eta: f32,
    fdr_int: f32,
    nonlinear: bool,
) -> SampledSpectrum {
    let rho_p = if nonlinear {
        rho / (1.0 - rho * fdr_int)
    } else {
        rho / (1.0 - fdr_int)
    };
    rho_p / (eta * eta)
}

/// Mitsuba's specular sampling weight from the mean reflectances.
pub(crate) fn specular_weight(r_s: SampledSpectrum, rho: SampledSpectrum) -> f32 {
    let (s, d) = (r_s.average().max(0.0), rho.average().max(0.0));
    if s + d > 0.0 {
        s / (s + d)
    } else {
        0.5
    }
}

/// Probability of picking the specular lobe given the Fresnel reflectance at wo.
pub(crate) fn specular_probability(f_o: f32, spec_weight: f32) -> f32 {
    let ps = f_o * spec_weight;
    let pd = (1.0 - f_o) * (1.0 - spec_weight);
    if ps + pd > 0.0 {
        ps / (ps + pd)
    } else {
        0.0
    }
}

impl PlasticBxdf {
    /// Smooth plastic of relative index `eta`, substrate albedo `rho`, internal diffuse Fresnel
    /// reflectance `fdr_int` (see the module doc).
    pub fn new(
        eta: f32,
        rho: SampledSpectrum,
        r_s: SampledSpectrum,
        fdr_int: f32,
        nonlinear: bool,
    ) -> Self {
        PlasticBxdf {
            eta,
            kd: substrate(rho, eta, fdr_int, nonlinear),
            r_s,
            spec_weight: specular_weight(r_s, rho),
        }
    }
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::SPECULAR_REFLECTION | BxdfFlags::DIFFUSE_REFLECTION
    }
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> SampledSpectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let t =
            (1.0 - fresnel_dielectric(wo.z, self.eta)) * (1.0 - fresnel_dielectric(wi.z, self.eta));
        self.kd * (t * INV_PI)
    }
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let ps = specular_probability(fresnel_dielectric(wo.z, self.eta), self.spec_weight);
        (1.0 - ps) * warp::square_to_cosine_hemisphere_pdf(wi)
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
        let f_o = fresnel_dielectric(wo.z, self.eta);
        let ps = specular_probability(f_o, self.spec_weight);
        if uc < ps {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            let w = self.r_s * (f_o / ps);
            return Some(BsdfSample::new(
                w / wi.z,
                wi,
                1.0,
                BxdfFlags::SPECULAR_REFLECTION,
            ));
        }
        let wi = warp::square_to_cosine_hemisphere(u);
        let pdf = self.pdf(wo, wi, mode, rng);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = self.f(wo, wi, mode, rng);
        Some(BsdfSample::new(f, wi, pdf, BxdfFlags::DIFFUSE_REFLECTION))
    }
}
