//! Rough conductor: the Cook–Torrance microfacet BRDF (Cook & Torrance 1982) in the form of
//! Walter et al. 2007, f = F(wo·wm) D(wm) G(wo, wi) / (4 cos θo cos θi), with the exact conductor
//! Fresnel term, GGX or Beckmann normals (anisotropic), height-correlated Smith G and
//! visible-normal sampling (see [`super::microfacet`]).
//!
//! | Mitsuba parameter      | type     | default | unit |
//! |------------------------|----------|---------|------|
//! | `distribution`         | string   | `beckmann` | `ggx` or `beckmann` |
//! | `alpha`                | float/texture | 0.1 | RMS slope (α) |
//! | `alpha_u`, `alpha_v`   | float/texture | `alpha` | α along tangent / bitangent |
//! | `material`             | string   | `none` | preset name |
//! | `eta`, `k`             | spectrum | from `material` | complex index |
//! | `ext_ior`              | float or name | 1.000277 | refractive index |
//! | `specular_reflectance` | spectrum/texture | 1.0 | factor |
//!
//! Plugin name `roughconductor` (0.6: `alphaU`/`alphaV` upgraded by the loader; 0.6's `phong`
//! and `as` distributions are not supported). `sample_visible` is always on. One-sided.
//! Known limits: single scattering only, so energy is lost at high roughness.

use super::fresnel::ConductorFresnel;
use super::microfacet::MicrofacetDistribution;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{reflect, Pcg32, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// Rough conductor.
#[derive(Clone, Debug)]
pub struct RoughConductorBxdf {
    pub distrib: MicrofacetDistribution,
    pub fresnel: ConductorFresnel,
    pub r_s: SampledSpectrum,
}

impl RoughConductorBxdf {
    /// A rough conductor.
    pub fn new(
        distrib: MicrofacetDistribution,
        fresnel: ConductorFresnel,
        r_s: SampledSpectrum,
    ) -> Self {
        RoughConductorBxdf {
            distrib,
            fresnel,
            r_s,
        }
    }
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::GLOSSY_REFLECTION
    }
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> SampledSpectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return SampledSpectrum::ZERO;
        }
        let wm = wm.normalize();
        let d = self.distrib.d(wm);
        let g = self.distrib.g(wo, wi);
        self.r_s * self.fresnel.eval(wo.dot(wm)) * (d * g / (4.0 * wo.z * wi.z))
    }
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = wm.normalize();
        // Jacobian of the reflection map wm → wi: 1 / (4 |wo·wm|).
        self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm))
    }
    pub fn sample_f(
        &self,
        wo: Vec3,
        _uc: f32,
        u: Vec2,
        mode: TransportMode,
        rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wm = self.distrib.sample_wm(wo, u);
        let wi = reflect(wo, wm);
        if wi.z <= 0.0 {
            return None;
        }
        // Evaluate from wi so that sampling and evaluation agree to the last bit.
        let pdf = self.pdf(wo, wi, mode, rng);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = self.f(wo, wi, mode, rng);
        Some(BsdfSample::new(f, wi, pdf, BxdfFlags::GLOSSY_REFLECTION))
    }
}
