//! Smooth dielectric interface: specular reflection and refraction weighted by the exact
//! unpolarised Fresnel equations (see [`super::fresnel`]); e.g. glass, water.
//!
//! | Mitsuba parameter        | type     | default    | unit |
//! |--------------------------|----------|------------|------|
//! | `int_ior`                | float or name | 1.5046 (`bk7`) | refractive index |
//! | `ext_ior`                | float or name | 1.000277 (`air`) | refractive index |
//! | `specular_reflectance`   | spectrum/texture | 1.0 | factor (not physical) |
//! | `specular_transmittance` | spectrum/texture | 1.0 | factor (not physical) |
//!
//! The BSDF uses the relative index `eta = int_ior / ext_ior`. Plugin name `dielectric`;
//! Mitsuba 0.6 `intIOR`/`extIOR` are upgraded by the loader.
//!
//! Sampling picks reflection with probability F and transmission with 1 − F, so the path weight
//! is exactly `specular_reflectance` or `specular_transmittance` (R + T = 1 for white factors).
//! Radiance crossing into a medium of relative index η is scaled by 1/η² (radiance mode only;
//! importance is not scaled). Two-sided by nature: wo.z < 0 means the ray is inside.
//! Known limits: the index is a single real number (no dispersion, no absorption).

use super::fresnel::fresnel_dielectric_cos_t;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Pcg32, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// Smooth dielectric with relative index `eta` (interior / exterior).
#[derive(Clone, Debug)]
pub struct DielectricBxdf {
    pub eta: f32,
    pub r_s: SampledSpectrum,
    pub t_s: SampledSpectrum,
}

impl DielectricBxdf {
    /// A smooth interface of relative index `eta` with reflectance and transmittance factors.
    pub fn new(eta: f32, r_s: SampledSpectrum, t_s: SampledSpectrum) -> Self {
        DielectricBxdf { eta, r_s, t_s }
    }
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::SPECULAR_REFLECTION | BxdfFlags::SPECULAR_TRANSMISSION
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
        uc: f32,
        _u: Vec2,
        mode: TransportMode,
        _rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let (r, cos_t) = fresnel_dielectric_cos_t(wo.z, self.eta);
        if uc < r || r >= 1.0 {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample::new(
                self.r_s / wi.z.abs(),
                wi,
                1.0,
                BxdfFlags::SPECULAR_REFLECTION,
            ));
        }
        // Relative index seen by the ray: n(wi side) / n(wo side).
        let etap = if wo.z > 0.0 { self.eta } else { 1.0 / self.eta };
        let wi = Vec3::new(-wo.x / etap, -wo.y / etap, cos_t).normalize();
        let mut w = self.t_s;
        if mode == TransportMode::Radiance {
            w /= etap * etap;
        }
        Some(BsdfSample {
            eta: etap,
            ..BsdfSample::new(w / wi.z.abs(), wi, 1.0, BxdfFlags::SPECULAR_TRANSMISSION)
        })
    }
}
