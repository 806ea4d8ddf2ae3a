//! A microfacet interface, generic over its [`Fresnel`] term: `roughdielectric`,
//! `roughconductor`, `roughthinfilm` and `roughthinfilmconductor` are this surface with
//! different terms. The model is Walter et al. 2007, "Microfacet Models for Refraction through
//! Rough Surfaces" (EGSR), with GGX or Beckmann normals, height-correlated Smith G and
//! visible-normal sampling ([`super::microfacet`]); a thin film replaces the Fresnel term of
//! each microfacet by the film's reflectance at wo·wm, as Belcour & Barla 2017 do (TOG 36(4)).
//!
//! With η' the index of the wi side over the wo side, the generalised half vector is
//! wm ∝ η' wi + wo (oriented to +z); reflection is F D G / (4 |cos θo cos θi|) and refraction
//! (1 − F) D G |wi·wm| |wo·wm| / (|cos θo cos θi| (wi·wm + wo·wm/η')²), divided by η'² in
//! radiance mode only. Sampling picks reflection with the term's probability P(wo·wm) (for a
//! dielectric F itself), so that the importance-mode weight is G/G1(wo) ≤ 1, and `pdf`
//! includes that choice. A caller that knows the transmitted light is worth less than that
//! (a coat over a dark base) can scale the choice with [`Rough::sample_f_weighted`]: reflection
//! with P′ = P / (P + (1 − P) t), the density changing with it, so the estimate stays
//! unbiased for every t > 0. Terms whose light is absorbed (metals) only reflect and are
//! one-sided. Known limits: single scattering between microfacets (energy is lost at high
//! roughness); refraction needs a real relative index.

use super::fresnel::{Fresnel, Transmission};
use super::microfacet::MicrofacetDistribution;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{reflect, refract, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// A rough surface with Fresnel term `F`.
#[derive(Clone, Debug)]
pub struct Rough<F: Fresnel> {
    pub distrib: MicrofacetDistribution,
    pub fresnel: F,
    pub r_s: SampledSpectrum,
    pub t_s: SampledSpectrum,
}

/// The microfacet normal joining a pair of directions, with the index ratio and whether the
/// pair is a reflection; `None` for degenerate pairs and back-facing microfacets.
fn half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<(Vec3, f32, bool)> {
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

/// The reflection half vector of an upper-hemisphere pair (one-sided surfaces).
fn reflection_half(wo: Vec3, wi: Vec3) -> Option<Vec3> {
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return None;
    }
    let wm = wo + wi;
    (wm.length_squared() > 0.0).then(|| wm.normalize())
}

/// The probability of choosing reflection when the term's own probability is `p` and
/// transmission is weighted by `t_weight` > 0 (exactly `p` for a weight of 1).
#[inline]
pub fn weighted_choice(p: f32, t_weight: f32) -> f32 {
    if t_weight == 1.0 {
        p
    } else {
        p / (p + (1.0 - p) * t_weight)
    }
}

impl<F: Fresnel> Rough<F> {
    /// A rough surface.
    pub fn new(
        distrib: MicrofacetDistribution,
        fresnel: F,
        r_s: SampledSpectrum,
        t_s: SampledSpectrum,
    ) -> Self {
        Rough {
            distrib,
            fresnel,
            r_s,
            t_s,
        }
    }

    /// The relative index light refracts into, or `None` for a reflector.
    pub(crate) fn eta(&self) -> Option<f32> {
        match self.fresnel.transmission() {
            Transmission::Refract { eta } => Some(eta),
            _ => None,
        }
    }

    /// Its reflection alone, for a mixture density ([`super::layered`]): `wo` reflected about a
    /// visible microfacet normal drawn with `u`, if that stays above the surface.
    pub(crate) fn sample_reflection(&self, wo: Vec3, u: Vec2) -> Option<Vec3> {
        if !(wo.z > 0.0) {
            return None;
        }
        let wi = reflect(wo, self.distrib.sample_wm(wo, u));
        (wi.z > 0.0).then_some(wi)
    }

    /// The density of [`Rough::sample_reflection`] (0 outside the upper hemisphere).
    pub(crate) fn reflection_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match reflection_half(wo, wi) {
            Some(wm) => self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm)),
            None => 0.0,
        }
    }

    /// Lobe flags.
    pub fn flags(&self) -> BxdfFlags {
        match self.eta() {
            Some(_) => BxdfFlags::GLOSSY_REFLECTION | BxdfFlags::GLOSSY_TRANSMISSION,
            None => BxdfFlags::GLOSSY_REFLECTION,
        }
    }

    /// BSDF value (no cosine).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        let Some(eta) = self.eta() else {
            let Some(wm) = reflection_half(wo, wi) else {
                return SampledSpectrum::ZERO;
            };
            let d = self.distrib.d(wm);
            let g = self.distrib.g(wo, wi);
            let (r, _) = self.fresnel.reflectance(wo.dot(wm));
            return self.r_s * r * (d * g / (4.0 * wo.z * wi.z));
        };
        let Some((wm, etap, is_reflection)) = half_vector(wo, wi, eta) else {
            return SampledSpectrum::ZERO;
        };
        let d = self.distrib.d(wm);
        let g = self.distrib.g(wo, wi);
        let (r, _) = self.fresnel.microfacet(wo, wi, wm);
        if is_reflection {
            return self.r_s * r * (d * g / (4.0 * wo.z * wi.z).abs());
        }
        let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
        let mut ft = d * g * (wi.dot(wm) * wo.dot(wm) / (wi.z * wo.z * denom)).abs();
        if mode == TransportMode::Radiance {
            ft /= etap * etap;
        }
        self.t_s * (SampledSpectrum::ONE - r) * ft
    }

    /// Solid-angle density with which `sample_f` picks `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.pdf_weighted(wo, wi, 1.0).0
    }

    /// Solid-angle density with which [`Rough::sample_f_weighted`] picks `wi`, and its
    /// probability of reflection at the pair's microfacet (1 for a reflector).
    pub fn pdf_weighted(&self, wo: Vec3, wi: Vec3, t_weight: f32) -> (f32, f32) {
        let Some(eta) = self.eta() else {
            let Some(wm) = reflection_half(wo, wi) else {
                return (0.0, 1.0);
            };
            // Jacobian of the reflection map wm → wi: 1 / (4 |wo·wm|).
            return (self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm)), 1.0);
        };
        let Some((wm, etap, is_reflection)) = half_vector(wo, wi, eta) else {
            return (0.0, 0.5);
        };
        let (_, p) = self.fresnel.microfacet(wo, wi, wm);
        let p = weighted_choice(p, t_weight);
        let pm = self.distrib.pdf(wo, wm);
        let pdf = if is_reflection {
            pm / (4.0 * wo.dot(wm).abs()) * p
        } else {
            // Jacobian of the refraction map wm → wi (Walter et al. 2007, eq. 17).
            let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
            pm * wi.dot(wm).abs() / denom * (1.0 - p)
        };
        (pdf, p)
    }

    /// Samples a visible microfacet normal, then reflection or refraction about it.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        self.sample_f_weighted(wo, uc, u, mode, 1.0)
    }

    /// [`Rough::sample_f`] with the choice between reflection and refraction scaled by
    /// `t_weight` > 0 (see the module doc); 1 is `sample_f` itself.
    pub fn sample_f_weighted(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        t_weight: f32,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 || !wo.z.is_finite() {
            return None;
        }
        let (wi, flags, etap) = match self.eta() {
            None => {
                if wo.z < 0.0 {
                    return None;
                }
                let wi = reflect(wo, self.distrib.sample_wm(wo, u));
                if wi.z <= 0.0 {
                    return None;
                }
                (wi, BxdfFlags::GLOSSY_REFLECTION, 1.0)
            }
            Some(eta) => {
                let wm = self.distrib.sample_wm(wo, u);
                let cos_om = wo.dot(wm);
                let (_, p) = self.fresnel.reflectance(cos_om);
                let (wi, flags, etap) = if uc < weighted_choice(p, t_weight) {
                    (reflect(wo, wm), BxdfFlags::GLOSSY_REFLECTION, 1.0)
                } else {
                    // Refract about the microfacet normal on wo's side.
                    let (n, etap) = if cos_om > 0.0 {
                        (wm, eta)
                    } else {
                        (-wm, 1.0 / eta)
                    };
                    (refract(wo, n, etap)?, BxdfFlags::GLOSSY_TRANSMISSION, etap)
                };
                let is_reflection = flags == BxdfFlags::GLOSSY_REFLECTION;
                if (wi.z * wo.z > 0.0) != is_reflection || wi.z == 0.0 {
                    return None;
                }
                (wi, flags, etap)
            }
        };
        // Evaluate from wi so that sampling and evaluation agree to the last bit.
        let pdf = self.pdf_weighted(wo, wi, t_weight).0;
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = self.f(wo, wi, mode);
        Some(BsdfSample {
            eta: etap,
            ..BsdfSample::new(f, wi, pdf, flags)
        })
    }
}
