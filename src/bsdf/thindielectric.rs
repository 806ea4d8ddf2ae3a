//! Thin dielectric sheet (a window pane, a soap film without interference): the two parallel
//! interfaces of a slab of relative index η, with all internal reflections summed incoherently.
//! With single-interface reflectance R = F(|cos θ|, η) and T = 1 − R, the sheet reflects
//! R' = R + T²R / (1 − R²) and transmits T' = 1 − R'; transmitted light continues undeviated
//! (wi = −wo), as in Mitsuba's `thindielectric`.
//!
//! | Mitsuba parameter        | type     | default    | unit |
//! |--------------------------|----------|------------|------|
//! | `int_ior`                | float or name | 1.5046 (`bk7`) | refractive index |
//! | `ext_ior`                | float or name | 1.000277 (`air`) | refractive index |
//! | `specular_reflectance`   | spectrum/texture | 1.0 | factor |
//! | `specular_transmittance` | spectrum/texture | 1.0 | factor |
//!
//! Plugin name `thindielectric`. Two-sided; no η² scaling (the ray leaves into the medium it
//! came from). Known limits: no absorption inside the sheet, no thin-film interference (see the
//! thin-film BSDFs for that).

use super::fresnel::fresnel_dielectric;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Pcg32, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// Thin dielectric sheet with relative index `eta`.
#[derive(Clone, Debug)]
pub struct ThinDielectricBxdf {
    pub eta: f32,
    pub r_s: SampledSpectrum,
    pub t_s: SampledSpectrum,
}

impl ThinDielectricBxdf {
    /// A sheet of relative index `eta` with reflectance and transmittance factors.
    pub fn new(eta: f32, r_s: SampledSpectrum, t_s: SampledSpectrum) -> Self {
        ThinDielectricBxdf { eta, r_s, t_s }
    }
    /// Reflectance of the sheet including interreflections.
    pub fn reflectance(&self, cos_theta: f32) -> f32 {
        let r = fresnel_dielectric(cos_theta.abs(), self.eta);
        if r < 1.0 {
            let t = 1.0 - r;
            r + t * t * r / (1.0 - r * r)
        } else {
            1.0
        }
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
        _mode: TransportMode,
        _rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let r = self.reflectance(wo.z);
        let (wi, w, flags) = if uc < r {
            (
                Vec3::new(-wo.x, -wo.y, wo.z),
                self.r_s,
                BxdfFlags::SPECULAR_REFLECTION,
            )
        } else {
            (-wo, self.t_s, BxdfFlags::SPECULAR_TRANSMISSION)
        };
        Some(BsdfSample::new(w / wi.z.abs(), wi, 1.0, flags))
    }
}
