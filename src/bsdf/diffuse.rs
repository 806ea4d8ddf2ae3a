//! Lambertian reflection (Lambert 1760): f = ρ/π on the upper hemisphere, cosine-weighted
//! sampling (Malley's method through the concentric disk).
//!
//! | Mitsuba parameter | type     | default | unit |
//! |-------------------|----------|---------|------|
//! | `reflectance`     | spectrum/texture | 0.5 | albedo in [0, 1] |
//!
//! Plugin names: `diffuse` (Mitsuba 0.6 and 3); the 0.6 alias `lambertian` is left to the
//! loader. One-sided as in Mitsuba 3: black when either direction is below the surface (wrap in
//! `twosided` for both sides). Known limits: none.

use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{warp, Pcg32, Vec2, Vec3, INV_PI};
use crate::spectrum::SampledSpectrum;

/// Lambertian BSDF with reflectance `r`.
#[derive(Clone, Debug)]
pub struct DiffuseBxdf {
    pub r: SampledSpectrum,
}

impl DiffuseBxdf {
    /// A Lambertian surface of reflectance `r`.
    pub fn new(r: SampledSpectrum) -> Self {
        DiffuseBxdf { r }
    }
    pub fn flags(&self) -> BxdfFlags {
        if self.r.is_black() {
            BxdfFlags::NONE
        } else {
            BxdfFlags::DIFFUSE_REFLECTION
        }
    }
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> SampledSpectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.r * INV_PI
    }
    pub fn sample_f(
        &self,
        wo: Vec3,
        _uc: f32,
        u: Vec2,
        _mode: TransportMode,
        _rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = warp::square_to_cosine_hemisphere(u);
        let pdf = warp::square_to_cosine_hemisphere_pdf(wi);
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample::new(
            self.r * INV_PI,
            wi,
            pdf,
            BxdfFlags::DIFFUSE_REFLECTION,
        ))
    }
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        warp::square_to_cosine_hemisphere_pdf(wi)
    }
}
