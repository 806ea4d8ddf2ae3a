//! A smooth interface (Dirac reflection and, where the interface lets light on, refraction or
//! straight transmission), generic over its [`Fresnel`] term: `dielectric`, `thindielectric`,
//! `conductor`, `thinfilm` and `thinfilmconductor` are this surface with different terms.
//!
//! Sampling chooses reflection with the term's probability P (for a dielectric the Fresnel
//! reflectance itself, so the weight is exactly the `specular_reflectance` factor; for a film
//! the mean of its reflectances over the four wavelengths) and weights wavelength λ by R_λ/P or
//! (1 − R_λ)/(1 − P): unbiased, and close to 1, so the choice adds no colour noise. Refraction
//! follows Snell's law, and radiance crossing into a medium of relative index η is scaled by
//! 1/η² (radiance mode only; importance is not). Surfaces whose light is absorbed (metals) are
//! one-sided, as Mitsuba's conductors; the others work from both sides (wo.z < 0 is inside).

use super::fresnel::{Fresnel, Transmission};
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::Vec3;
use crate::spectrum::SampledSpectrum;

/// A smooth surface with Fresnel term `F` and non-physical reflectance/transmittance factors.
#[derive(Clone, Debug)]
pub struct Smooth<F: Fresnel> {
    pub fresnel: F,
    pub r_s: SampledSpectrum,
    pub t_s: SampledSpectrum,
}

impl<F: Fresnel> Smooth<F> {
    /// A smooth surface.
    pub fn new(fresnel: F, r_s: SampledSpectrum, t_s: SampledSpectrum) -> Self {
        Smooth { fresnel, r_s, t_s }
    }

    /// Lobe flags.
    pub fn flags(&self) -> BxdfFlags {
        match self.fresnel.transmission() {
            Transmission::Absorbed => BxdfFlags::SPECULAR_REFLECTION,
            _ => BxdfFlags::SPECULAR_REFLECTION | BxdfFlags::SPECULAR_TRANSMISSION,
        }
    }

    /// The exact path weights (f·|cos θi|/pdf) of the two lobes at `wo_z`, with the
    /// probability of reflection: (reflection weight, transmission weight, P). For tests and
    /// tools.
    pub fn lobe_weights(&self, wo_z: f32) -> (SampledSpectrum, SampledSpectrum, f32) {
        let (r, p) = self.fresnel.reflectance(wo_z);
        let wr = if p > 0.0 {
            r / p
        } else {
            SampledSpectrum::ZERO
        };
        let wt = if p < 1.0 {
            (SampledSpectrum::ONE - r) / (1.0 - p)
        } else {
            SampledSpectrum::ZERO
        };
        (wr, wt, p)
    }

    /// Samples the reflected or transmitted direction.
    pub fn sample_f(&self, wo: Vec3, uc: f32, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 || !wo.z.is_finite() {
            return None;
        }
        let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
        let reflect = |w: SampledSpectrum| {
            Some(BsdfSample::new(
                self.r_s * w / wo.z.abs(),
                mirror,
                1.0,
                BxdfFlags::SPECULAR_REFLECTION,
            ))
        };
        match self.fresnel.transmission() {
            Transmission::Absorbed => {
                if wo.z < 0.0 {
                    return None;
                }
                reflect(self.fresnel.reflectance(wo.z).0)
            }
            Transmission::Straight => {
                let (wr, wt, p) = self.lobe_weights(wo.z);
                if uc < p {
                    return reflect(wr);
                }
                Some(BsdfSample::new(
                    self.t_s * wt / wo.z.abs(),
                    -wo,
                    1.0,
                    BxdfFlags::SPECULAR_TRANSMISSION,
                ))
            }
            Transmission::Refract { eta } => {
                let (wr, wt, p) = self.lobe_weights(wo.z);
                // Relative index seen by the ray: n(wi side) / n(wo side).
                let etap = if wo.z > 0.0 { eta } else { 1.0 / eta };
                let sin2_t = (1.0 - wo.z * wo.z).max(0.0) / (etap * etap);
                // Total internal reflection makes R = 1; the f32 test guards P rounding just
                // below 1.
                if uc < p || p >= 1.0 || sin2_t >= 1.0 {
                    let w = if p >= 1.0 || sin2_t >= 1.0 {
                        self.fresnel.reflectance(wo.z).0
                    } else {
                        wr
                    };
                    return reflect(w);
                }
                let cos_t = (1.0 - sin2_t).sqrt() * -wo.z.signum();
                let wi = Vec3::new(-wo.x / etap, -wo.y / etap, cos_t).normalize();
                let mut w = self.t_s * wt;
                if mode == TransportMode::Radiance {
                    w /= etap * etap;
                }
                Some(BsdfSample {
                    eta: etap,
                    ..BsdfSample::new(w / wi.z.abs(), wi, 1.0, BxdfFlags::SPECULAR_TRANSMISSION)
                })
            }
        }
    }
}
