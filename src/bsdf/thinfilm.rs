//! Smooth dielectric interface carrying a thin film (soap bubble, oil on water, the keratin
//! film of a snake scale): specular reflection with the film's reflectance R_film(λ, θ) and
//! refraction with 1 − R_film, per hero wavelength. The film is exact: the Airy sum of complex
//! Fresnel amplitudes for s and p (Born & Wolf, *Principles of Optics*, §7.6.1), see
//! [`crate::optics::thinfilm`] and [`super::filmfresnel`]; the film is infinitely thin
//! geometrically, so it changes colours, not directions (refraction obeys Snell's law between
//! `ext_ior` and `int_ior`).
//!
//! | XML parameter            | type     | default | unit |
//! |--------------------------|----------|---------|------|
//! | `int_ior`                | float or name | 1.5046 (`bk7`) | refractive index |
//! | `ext_ior`                | float or name | 1.000277 (`air`) | refractive index |
//! | `film_ior`               | float, `keratin` or name | 1.4 (OpenPBR's default) | refractive index |
//! | `film_thickness`         | float/texture | 500 | nm (OpenPBR's 0.5 µm) |
//! | `mode`                   | string   | `spectral` | `spectral` or `thesis` |
//! | `specular_reflectance`   | spectrum/texture | 1.0 | factor (not physical) |
//! | `specular_transmittance` | spectrum/texture | 1.0 | factor (not physical) |
//!
//! `film_ior = "keratin"` is the Cauchy fit n(λ) = 1.532 + 5890/λ² (Leertouwer, Wilts & Stavenga
//! 2011, Opt. Express 19:24061), evaluated per wavelength.
//!
//! Plugin name `thinfilm`; the seed's `dielectricThinFilm` loads as an alias with its own
//! names and defaults (`intIOR` → `int_ior` = diamond, `extIOR` → `ext_ior` = air,
//! `mediumIOR` → `medium_ior` = film index, bk7; `thickness` = 400 nm). Either spelling of the
//! film parameters (`film_ior`/`medium_ior`, `film_thickness`/`thickness`) is accepted by both.
//!
//! Sampling: the four wavelengths share one path, so reflection is chosen with P = mean_λ R_λ
//! and wavelength λ is weighted R_λ/P (reflection) or (1 − R_λ)/(1 − P) (refraction); in thesis
//! mode P is the thesis's mean(r, g, b). Radiance crossing into a medium of relative index η is
//! scaled by 1/η² (radiance mode only). Two-sided by nature: wo.z < 0 is inside, where the film
//! is computed with n0 = `int_ior`, n2 = `ext_ior`.
//!
//! Known limits: real, non-dispersive `int_ior`/`ext_ior` (the film index may disperse); no
//! absorption in the film; the thickness is not filtered over the pixel footprint.

use super::filmfresnel::FilmFresnel;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Pcg32, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

/// Smooth film-coated dielectric with relative index `eta` (interior / exterior).
#[derive(Clone, Debug)]
pub struct ThinFilmBxdf {
    pub film: FilmFresnel,
    pub eta: f32,
    pub r_s: SampledSpectrum,
    pub t_s: SampledSpectrum,
}

impl ThinFilmBxdf {
    /// A smooth coated interface.
    pub fn new(film: FilmFresnel, eta: f32, r_s: SampledSpectrum, t_s: SampledSpectrum) -> Self {
        ThinFilmBxdf {
            film,
            eta,
            r_s,
            t_s,
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

    /// The exact path weights (f·|cos θi|/pdf) of the two lobes at `wo`, with the probability
    /// of reflection: (reflection weight, refraction weight, P). For tests and tools.
    pub fn lobe_weights(&self, wo_z: f32) -> (SampledSpectrum, SampledSpectrum, f32) {
        let (r, p) = self.film.eval(wo_z);
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

    pub fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        _u: Vec2,
        mode: TransportMode,
        _rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 || !wo.z.is_finite() {
            return None;
        }
        let (wr, wt, p) = self.lobe_weights(wo.z);
        // Relative index seen by the ray: n(wi side) / n(wo side).
        let etap = if wo.z > 0.0 { self.eta } else { 1.0 / self.eta };
        let sin2_t = (1.0 - wo.z * wo.z).max(0.0) / (etap * etap);
        // Total internal reflection makes R = 1; the f32 test guards P rounding just below 1.
        if uc < p || p >= 1.0 || sin2_t >= 1.0 {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            let w = if p >= 1.0 || sin2_t >= 1.0 {
                self.film.eval(wo.z).0
            } else {
                wr
            };
            return Some(BsdfSample::new(
                self.r_s * w / wi.z.abs(),
                wi,
                1.0,
                BxdfFlags::SPECULAR_REFLECTION,
            ));
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
