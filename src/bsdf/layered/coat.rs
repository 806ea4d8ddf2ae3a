//! The coat of a coated diffuse stack: its reflectance at the path's wavelengths — a bare
//! dielectric (Fresnel), or a dielectric under a thin film, whose Airy sum runs for the four
//! wavelengths in one pass of 4-lane arithmetic ([`crate::optics::thinfilm::film_r4`]; the
//! BSDF remembers its last answers, `CoatedDiffuse::outside`). The integrals of its internal
//! reflections are in `integrals.rs`.

use crate::bsdf::fresnel::fresnel_dielectric;
use crate::optics::thinfilm::{film_r4, film_r4x2, RealFilm};
use crate::spectrum::{SampledSpectrum, N};

/// The reflectance of the smooth coat: a bare dielectric, or a dielectric under a thin film.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CoatOptics {
    /// Bare interface of relative index `eta` (coat / outside).
    Dielectric { eta: f32 },
    /// A film of relative index `film_ior` (per wavelength, for dispersive films such as
    /// keratin) and thickness `thickness_nm` on a coat of relative index `eta`, at the path's
    /// wavelengths `lambda` (nm, in the outer medium).
    Film {
        eta: f32,
        film_ior: [f32; N],
        thickness_nm: f32,
        lambda: [f32; N],
    },
}

impl CoatOptics {
    /// Relative index of the coat.
    pub fn eta(&self) -> f32 {
        match *self {
            CoatOptics::Dielectric { eta } | CoatOptics::Film { eta, .. } => eta,
        }
    }

    /// Reflectance per wavelength for light arriving from outside with cosine `mu` ≥ 0.
    pub fn outside(&self, mu: f32) -> SampledSpectrum {
        self.reflectance(mu, false)
    }

    /// [`CoatOptics::outside`] at two cosines: a film coat's eight Airy sums in one pass
    /// ([`film_r4x2`]), the same values bit for bit.
    pub fn outside2(&self, mu_a: f32, mu_b: f32) -> (SampledSpectrum, SampledSpectrum) {
        match *self {
            CoatOptics::Dielectric { .. } => (self.outside(mu_a), self.outside(mu_b)),
            CoatOptics::Film {
                eta,
                film_ior,
                thickness_nm,
                lambda,
            } => {
                let lane = |a: [f32; N]| [a[0] as f64, a[1] as f64, a[2] as f64, a[3] as f64];
                let film = RealFilm {
                    n0: [1.0; N],
                    n1: lane(film_ior),
                    d_nm: thickness_nm as f64,
                    n2: [eta as f64; N],
                    lambda_nm: lane(lambda),
                };
                let (a, b) = film_r4x2(mu_a as f64, mu_b as f64, &film);
                let sp = |r: [f64; N]| {
                    SampledSpectrum([r[0] as f32, r[1] as f32, r[2] as f32, r[3] as f32])
                };
                (sp(a), sp(b))
            }
        }
    }

    /// Reflectance per wavelength for light arriving from inside the coat with cosine `mu`.
    pub fn inside(&self, mu: f32) -> SampledSpectrum {
        self.reflectance(mu, true)
    }

    /// Reflectance per wavelength from inside the coat (`inside`) or from outside.
    fn reflectance(&self, mu: f32, inside: bool) -> SampledSpectrum {
        match *self {
            CoatOptics::Dielectric { eta } => {
                SampledSpectrum::splat(fresnel_dielectric(if inside { -mu } else { mu }, eta))
            }
            CoatOptics::Film { .. } => self.film(mu, inside),
        }
    }

    /// A film coat's η, film indices, thickness and wavelengths.
    pub(super) fn film_parts(&self) -> (f32, [f32; N], f32, [f32; N]) {
        match *self {
            CoatOptics::Film {
                eta,
                film_ior,
                thickness_nm,
                lambda,
            } => (eta, film_ior, thickness_nm, lambda),
            CoatOptics::Dielectric { .. } => unreachable!("called for film coats only"),
        }
    }

    /// A film coat's reflectance at the four wavelengths in one pass of 4-lane arithmetic
    /// ([`film_r4`]: the Airy sum of [`crate::optics::thinfilm::film_rt`] to a few ulp).
    fn film(&self, mu: f32, inside: bool) -> SampledSpectrum {
        let (eta, film_ior, thickness_nm, lambda) = self.film_parts();
        // Indices of the media before and after the film, as the light meets them.
        let (n0, n2) = if inside {
            (eta as f64, 1.0)
        } else {
            (1.0, eta as f64)
        };
        let lane = |a: [f32; N]| a.map(|x| x as f64);
        let r = film_r4(
            mu as f64,
            [n0; N],
            lane(film_ior),
            thickness_nm as f64,
            [n2; N],
            lane(lambda),
        );
        SampledSpectrum(r.map(|x| x as f32))
    }
}
