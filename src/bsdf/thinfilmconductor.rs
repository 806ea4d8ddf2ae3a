//! A thin dielectric film over a metal, smooth (`thinfilmconductor`) and rough
//! (`roughthinfilmconductor`): oxide layers on steel or titanium, tempered colours, a
//! film-coated mirror. Reflectance is the exact Airy sum with a complex base index n + ik
//! (Born & Wolf, *Principles of Optics*, §1.6.4 and §13.4; see [`crate::optics::thinfilm`] and
//! [`super::filmfresnel`]); the rough version puts it in the Cook–Torrance microfacet BRDF
//! (Walter et al. 2007) at wo·wm, as Belcour & Barla 2017 (TOG 36(4):65) do.
//!
//! | XML parameter          | type     | default | unit |
//! |------------------------|----------|---------|------|
//! | `material`             | string   | `Cu` (Mitsuba 0.6's default) | preset metal |
//! | `eta`, `k`             | spectrum | from `material` | complex index of the metal |
//! | `ext_ior`              | float or name | 1.000277 (`air`) | refractive index |
//! | `film_ior`             | float, `keratin` or name | 1.4 | refractive index |
//! | `film_thickness`       | float/texture | 500 | nm |
//! | `mode`                 | string   | `spectral` | `spectral` or `thesis` |
//! | `specular_reflectance` | spectrum/texture | 1.0 | factor |
//! | `distribution`, `alpha`, `alpha_u`, `alpha_v` | (rough only) | `beckmann`, 0.1 | as `roughconductor` |
//!
//! The seed's `conductorThinFilm` (`material`, `eta`, `k`, `thickness`, `mediumIOR` →
//! `medium_ior`, default film index bk7 and 400 nm) loads as an alias of `thinfilmconductor`.
//! `material = "none"` (a perfect mirror) has no complex index and is refused.
//!
//! Only reflection exists; the power not reflected, 1 − R, enters the metal and is absorbed.
//! One-sided, as Mitsuba's conductors. In thesis mode the three point samples use the exact
//! Airy reflectance (the thesis's real-amplitude phase formula has no meaning over a metal).
//! Known limits: single scattering between microfacets (rough); no absorption in the film.

use super::filmfresnel::FilmFresnel;
use super::microfacet::MicrofacetDistribution;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{reflect, Pcg32, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// Smooth film-coated metal.
#[derive(Clone, Debug)]
pub struct ThinFilmConductorBxdf {
    pub film: FilmFresnel,
    pub r_s: SampledSpectrum,
}

impl ThinFilmConductorBxdf {
    /// A polished coated metal.
    pub fn new(film: FilmFresnel, r_s: SampledSpectrum) -> Self {
        ThinFilmConductorBxdf { film, r_s }
    }
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::SPECULAR_REFLECTION
    }
    pub fn f(&self, _wo: Vec3, _wi: Vec3, _m: TransportMode, _rng: &mut Pcg32) -> SampledSpectrum {
        SampledSpectrum::ZERO
    }
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3, _m: TransportMode, _rng: &mut Pcg32) -> f32 {
        0.0
    }
    pub fn sample_f(
        &self,
        wo: Vec3,
        _uc: f32,
        _u: Vec2,
        _mode: TransportMode,
        _rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        if wo.z.is_nan() || wo.z <= 0.0 {
            return None;
        }
        let wi = Vec3::new(-wo.x, -wo.y, wo.z);
        let f = self.r_s * self.film.eval(wo.z).0 / wi.z;
        Some(BsdfSample::new(f, wi, 1.0, BxdfFlags::SPECULAR_REFLECTION))
    }
}

/// Rough film-coated metal.
#[derive(Clone, Debug)]
pub struct RoughThinFilmConductorBxdf {
    pub distrib: MicrofacetDistribution,
    pub film: FilmFresnel,
    pub r_s: SampledSpectrum,
}

impl RoughThinFilmConductorBxdf {
    /// A rough coated metal.
    pub fn new(distrib: MicrofacetDistribution, film: FilmFresnel, r_s: SampledSpectrum) -> Self {
        RoughThinFilmConductorBxdf { distrib, film, r_s }
    }
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::GLOSSY_REFLECTION
    }
    fn half(wo: Vec3, wi: Vec3) -> Option<Vec3> {
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return None;
        }
        let wm = wo + wi;
        (wm.length_squared() > 0.0).then(|| wm.normalize())
    }
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> SampledSpectrum {
        let Some(wm) = Self::half(wo, wi) else {
            return SampledSpectrum::ZERO;
        };
        let d = self.distrib.d(wm);
        let g = self.distrib.g(wo, wi);
        self.r_s * self.film.eval(wo.dot(wm)).0 * (d * g / (4.0 * wo.z * wi.z))
    }
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> f32 {
        let Some(wm) = Self::half(wo, wi) else {
            return 0.0;
        };
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
        if wo.z.is_nan() || wo.z <= 0.0 {
            return None;
        }
        let wm = self.distrib.sample_wm(wo, u);
        let wi = reflect(wo, wm);
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi, mode, rng);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = self.f(wo, wi, mode, rng);
        Some(BsdfSample::new(f, wi, pdf, BxdfFlags::GLOSSY_REFLECTION))
    }
}
