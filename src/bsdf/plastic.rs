//! Plastic: a diffuse substrate under a dielectric coating that is smooth (Mitsuba's
//! `plastic`) or rough (`roughplastic`), after Weidlich & Wilkie 2007, "Arbitrarily Layered
//! Micro-Facet Surfaces", with the substrate's internal reflections summed as in Kelemen &
//! Szirmay-Kalos 2001, and Walter et al. 2007 microfacets for the rough coat.
//!
//! Specular part: smooth, a delta lobe of weight `specular_reflectance`·F(cos θo); rough, the
//! microfacet reflection F(wo·wm) D G / (4 cos θo cos θi) times `specular_reflectance` (GGX or
//! Beckmann, isotropic, height-correlated Smith G). Diffuse part:
//!
//! f_d = (1 − F(cos θo)) (1 − F(cos θi)) ρ' / (π η²),
//! ρ' = ρ / (1 − F̄ᵢ) (linear) or ρ / (1 − ρ F̄ᵢ) (`nonlinear`),
//!
//! where F̄ᵢ is the cosine-weighted average of the interface's internal reflectance
//! ([`super::fresnel::fresnel_diffuse_reflectance`] of 1/η, by quadrature). With ρ = 1 the
//! smooth model conserves energy exactly (albedo 1), which the tests check.
//!
//! Sampling picks the specular lobe with probability F·s / (F·s + (1 − F)(1 − s)), where
//! s = mean(specular_reflectance) / (mean(specular) + mean(diffuse_reflectance)) is Mitsuba's
//! specular sampling weight (visible normals for the rough coat), and the cosine-weighted
//! diffuse lobe otherwise; `pdf` is the mixture of both.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `diffuse_reflectance` (0.6: `diffuseReflectance`) | spectrum or texture | 0.5 | — | albedo of the substrate |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//! | `int_ior` (0.6: `intIOR`) | float or IOR name | 1.49 | — | index of the coating (polypropylene) |
//! | `ext_ior` (0.6: `extIOR`) | float or IOR name | `air` | — | index of the exterior |
//! | `nonlinear` | boolean | false | — | account for the substrate's colour in the internal reflections |
//!
//! `roughplastic` adds `distribution` and `alpha` (isotropic, as in Mitsuba).
//!
//! Known limits: one-sided; no absorption or multiple scattering in the coating. The rough
//! coat's transmittance is approximated by the smooth-interface Fresnel factor (Mitsuba 3
//! tabulates the rough interface's), so with a white substrate the albedo is not exactly 1:
//! measured with ρ = 1, η = 1.5, it is 0.98–1.003 up to θo = 45° and drops at grazing angles
//! (0.68 at 80° for GGX α = 0.6) where the microfacet lobe loses energy to shadowing.

use super::fresnel::{fresnel_dielectric, fresnel_diffuse_reflectance};
use super::material::PlasticMaterial;
use super::microfacet::{MicrofacetDistribution, MicrofacetType};
use super::params::{EXT_IOR, INT_IOR, SPECULAR_REFLECTANCE};
use super::{BsdfSample, BxdfFlags, Material};
use crate::math::{reflect, warp, Vec2, Vec3, INV_PI};
use crate::plugin::{declare, Args, DefaultValue, Param, SceneError};
use crate::spectrum::SampledSpectrum;
use crate::texture::FloatTexture;

/// The parameters both plastics take.
pub(crate) const PLASTIC: &[Param] = &[
    Param::reflectance("diffuse_reflectance", 0.5)
        .v06("diffuseReflectance")
        .doc("albedo of the substrate"),
    SPECULAR_REFLECTANCE,
    INT_IOR
        .default(DefaultValue::Float(1.49))
        .doc("index of the coating (polypropylene)"),
    EXT_IOR,
    Param::bool("nonlinear", false)
        .doc("account for the substrate's colour in the internal reflections"),
];

declare!(PLUGIN: Material = Bsdf "plastic" []
    "diffuse substrate under a smooth dielectric coating"
    [PLASTIC] |a, _| load_plastic(a, None));

/// Reads a plastic, smooth or with the given rough coat.
pub(crate) fn load_plastic(
    a: &mut Args,
    rough: Option<(MicrofacetType, FloatTexture)>,
) -> Result<Material, SceneError> {
    let eta = a.ior("int_ior")? / a.ior("ext_ior")?;
    Ok(Material::Plastic(Box::new(PlasticMaterial {
        rough,
        eta,
        diffuse_reflectance: a.spectrum_texture("diffuse_reflectance")?,
        specular_reflectance: a.spectrum_texture("specular_reflectance")?,
        nonlinear: a.bool("nonlinear")?,
        fdr_int: fresnel_diffuse_reflectance(1.0 / eta),
    })))
}

/// Plastic with a smooth (`coat: None`) or rough coat.
#[derive(Clone, Debug)]
pub struct PlasticBxdf {
    /// The coat's microfacet distribution; `None`: smooth.
    pub coat: Option<MicrofacetDistribution>,
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
    /// Plastic of relative index `eta`, substrate albedo `rho`, internal diffuse Fresnel
    /// reflectance `fdr_int` (see the module doc), smooth or with a rough `coat`.
    pub fn new(
        coat: Option<MicrofacetDistribution>,
        eta: f32,
        rho: SampledSpectrum,
        r_s: SampledSpectrum,
        fdr_int: f32,
        nonlinear: bool,
    ) -> Self {
        PlasticBxdf {
            coat,
            eta,
            kd: substrate(rho, eta, fdr_int, nonlinear),
            r_s,
            spec_weight: specular_weight(r_s, rho),
        }
    }

    /// Lobe flags.
    pub(crate) fn flags(&self) -> BxdfFlags {
        let specular = match self.coat {
            None => BxdfFlags::SPECULAR_REFLECTION,
            Some(_) => BxdfFlags::GLOSSY_REFLECTION,
        };
        specular | BxdfFlags::DIFFUSE_REFLECTION
    }

    /// BSDF value of the non-delta lobes.
    pub fn f(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let t =
            (1.0 - fresnel_dielectric(wo.z, self.eta)) * (1.0 - fresnel_dielectric(wi.z, self.eta));
        let mut f = self.kd * (t * INV_PI);
        if let Some(d) = &self.coat {
            let wm = wo + wi;
            if wm.length_squared() > 0.0 {
                let wm = wm.normalize();
                let spec = fresnel_dielectric(wo.dot(wm), self.eta) * d.d(wm) * d.g(wo, wi)
                    / (4.0 * wo.z * wi.z);
                f += self.r_s * spec;
            }
        }
        f
    }

    /// Density of the non-delta lobes.
    pub(crate) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let ps = specular_probability(fresnel_dielectric(wo.z, self.eta), self.spec_weight);
        let mut p = (1.0 - ps) * warp::square_to_cosine_hemisphere_pdf(wi);
        if let Some(d) = &self.coat {
            let wm = wo + wi;
            if wm.length_squared() > 0.0 {
                let wm = wm.normalize();
                p += ps * d.pdf(wo, wm) / (4.0 * wo.dot(wm));
            }
        }
        p
    }

    /// Samples the specular or the diffuse lobe.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let f_o = fresnel_dielectric(wo.z, self.eta);
        let ps = specular_probability(f_o, self.spec_weight);
        let specular = uc < ps;
        let wi = match (&self.coat, specular) {
            (None, true) => {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                let w = self.r_s * (f_o / ps);
                return Some(BsdfSample::new(
                    w / wi.z,
                    wi,
                    1.0,
                    BxdfFlags::SPECULAR_REFLECTION,
                ));
            }
            (Some(d), true) => reflect(wo, d.sample_wm(wo, u)),
            (_, false) => warp::square_to_cosine_hemisphere(u),
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let flags = if specular {
            BxdfFlags::GLOSSY_REFLECTION
        } else {
            BxdfFlags::DIFFUSE_REFLECTION
        };
        Some(BsdfSample::new(self.f(wo, wi), wi, pdf, flags))
    }
}
