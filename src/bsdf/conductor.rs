//! Smooth conductor (polished metal, or an ideal mirror): specular reflection weighted by the
//! exact Fresnel reflectance of a complex index η + iκ per wavelength (see [`super::fresnel`]).
//!
//! | Mitsuba parameter      | type     | default | unit |
//! |------------------------|----------|---------|------|
//! | `material`             | string   | `none` (Mitsuba 3; 0.6 used `Cu`) | preset name |
//! | `eta`, `k`             | spectrum | from `material` | real / imaginary index |
//! | `ext_ior`              | float or name | 1.000277 (`air`) | refractive index |
//! | `specular_reflectance` | spectrum/texture | 1.0 | factor |
//!
//! The BSDF takes η and κ already divided by the exterior index; `material = "none"` is
//! [`ConductorFresnel::Mirror`] (F = 1). Plugin name `conductor`. One-sided as in Mitsuba 3.
//! Known limits: unpolarised light only.

use super::fresnel::ConductorFresnel;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Pcg32, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// Smooth conductor.
#[derive(Clone, Debug)]
pub struct ConductorBxdf {
    pub fresnel: ConductorFresnel,
    pub r_s: SampledSpectrum,
}

impl ConductorBxdf {
    /// A polished conductor with the given Fresnel term and reflectance factor.
    pub fn new(fresnel: ConductorFresnel, r_s: SampledSpectrum) -> Self {
        ConductorBxdf { fresnel, r_s }
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
        if wo.z <= 0.0 {
            return None;
        }
        let wi = Vec3::new(-wo.x, -wo.y, wo.z);
        let f = self.r_s * self.fresnel.eval(wo.z) / wi.z;
        Some(BsdfSample::new(f, wi, 1.0, BxdfFlags::SPECULAR_REFLECTION))
    }
}
