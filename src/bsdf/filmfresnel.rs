//! The Fresnel term of an interface that carries a thin film, per shading point: the reflectance
//! R(cos θ) at the path's four wavelengths and the probability with which the film BSDFs choose
//! reflection. Shared by `thinfilm`, `roughthinfilm`, `thinfilmconductor` and
//! `roughthinfilmconductor`.
//!
//! Two modes:
//!
//! - [`FilmMode::Spectral`] (default): the exact Airy reflectance of [`crate::optics::thinfilm`]
//!   at each hero wavelength. Reflection is chosen with probability P = mean over the four
//!   wavelengths of R, and each wavelength is weighted by R_λ/P (or (1 − R_λ)/(1 − P)): unbiased,
//!   and the weights stay close to 1, so no colour noise comes from the choice.
//! - [`FilmMode::Thesis`]: the film as the thesis computed it (Padrón-Griffe 2022; CEIG 2023,
//!   doi 10.2312/CEIG.20231143): point samples at 650/510/475 nm taken as linear-sRGB R, G, B,
//!   with its transmittance formula T = (n2 cos θ2 / n0 cos θ0) (t01 t12)² / (1 − 2a cos φ + a²),
//!   a = r10 r12, φ = 4π n1 d cos θ1 / λ + δ, where δ adds π for each of n1 < n0 and n1 < n2 —
//!   which double-counts the phase already in the signs of r10 and r12 (exact only for
//!   n0 = n2 < n1, the thesis's own stack), R = 1 − T clamped. The RGB reflectance is uplifted to a
//!   smooth spectrum (Jakob & Hanika 2019) and reflection is chosen with the thesis's
//!   probability F = mean(r, g, b). On a metal base the thesis formula has no meaning (complex
//!   amplitudes), so the point samples there use the exact Airy reflectance.
//!
//! From inside a dielectric base (cos θ < 0) the light meets the same film from the other side:
//! n0 = interior, n2 = exterior.

use crate::optics::thinfilm::{film_r, film_r4};
use crate::spectrum::rgb2spec::rgb_to_sigmoid;
use crate::spectrum::{SampledSpectrum, N};
use num_complex::Complex64 as C;
use std::cell::Cell;

/// Wavelengths (nm) of the thesis's R, G and B point samples.
pub const THESIS_LAMBDA: [f32; 3] = [650.0, 510.0, 475.0];

/// How the film's reflectance is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FilmMode {
    /// Exact, per hero wavelength.
    #[default]
    Spectral,
    /// The thesis's three point samples and phase term, uplifted from RGB.
    Thesis,
}

impl FilmMode {}

/// Optical constants of the stack at `K` wavelengths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmSamples<const K: usize> {
    pub lambda: [f32; K],
    /// Film index n1(λ).
    pub film: [f32; K],
    /// Base (interior) index n2(λ) = n + ik.
    pub base_n: [f32; K],
    pub base_k: [f32; K],
}

/// A film, an angle's bits and [`FilmFresnel::eval`]'s answer for them.
type Remembered = (FilmFresnel, u32, (SampledSpectrum, f32));

/// The film's Fresnel term at one shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmFresnel {
    /// Exterior index n0 (real).
    pub ext: f32,
    /// Film thickness (nm, ≥ 0).
    pub d_nm: f32,
    /// Constants at the path's wavelengths.
    pub spectral: FilmSamples<N>,
    /// Constants at [`THESIS_LAMBDA`] (used in thesis mode; zero indices in spectral mode, as
    /// `FilmSpec::fresnel` makes them).
    pub thesis: FilmSamples<3>,
    pub mode: FilmMode,
}

/// Reflectance at `cos0` for one wavelength sample: `cos0 < 0` means from inside the base.
fn exact(ext: f32, film: f32, n: f32, k: f32, d: f32, lambda: f32, cos0: f32) -> f64 {
    let (n0, n2) = if cos0 >= 0.0 {
        (ext as f64, C::new(n as f64, k as f64))
    } else {
        (n as f64, C::new(ext as f64, 0.0))
    };
    let r = film_r(
        (cos0 as f64).abs(),
        n0,
        C::new(film as f64, 0.0),
        d as f64,
        n2,
        lambda as f64,
    );
    finite_r(r)
}

/// A reflectance in [0, 1] (1 where the optics gave no number).
#[inline]
fn finite_r(r: f64) -> f64 {
    if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The thesis's film reflectance (see the module doc), reproduced on purpose with its δ term,
/// for real indices; `cos0` ∈ [0, 1]. Total internal reflection at either interface gives 1.
pub fn thesis_reflectance(cos0: f64, n0: f64, n1: f64, d_nm: f64, n2: f64, lambda_nm: f64) -> f64 {
    let c0 = cos0.clamp(0.0, 1.0);
    let s0 = n0 * (1.0 - c0 * c0).max(0.0).sqrt();
    let cos_in = |n: f64| {
        let s = s0 / n;
        let c2 = 1.0 - s * s;
        (c2 >= 0.0).then(|| c2.sqrt())
    };
    let (Some(c1), Some(c2)) = (cos_in(n1), cos_in(n2)) else {
        return 1.0;
    };
    if c0 == 0.0 {
        return 1.0;
    }
    let delta = std::f64::consts::PI * (((n1 < n0) as u8 + (n1 < n2) as u8) as f64);
    let phi = 4.0 * std::f64::consts::PI * n1 * d_nm * c1 / lambda_nm + delta;
    let ratio = n2 * c2 / (n0 * c0);
    // s and p amplitudes: reflection from the film side of the top interface (r10), at the
    // bottom interface (r12), and the two transmissions.
    let pol = |r10: f64, r12: f64, t01: f64, t12: f64| {
        let a = r10 * r12;
        let b = t01 * t12;
        ratio * b * b / (1.0 - 2.0 * a * phi.cos() + a * a)
    };
    let t_s = pol(
        (n1 * c1 - n0 * c0) / (n1 * c1 + n0 * c0),
        (n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2),
        2.0 * n0 * c0 / (n0 * c0 + n1 * c1),
        2.0 * n1 * c1 / (n1 * c1 + n2 * c2),
    );
    let t_p = pol(
        (n0 * c1 - n1 * c0) / (n0 * c1 + n1 * c0),
        (n2 * c1 - n1 * c2) / (n2 * c1 + n1 * c2),
        2.0 * n0 * c0 / (n1 * c0 + n0 * c1),
        2.0 * n1 * c1 / (n2 * c1 + n1 * c2),
    );
    let t = 0.5 * (t_s + t_p);
    if t.is_finite() {
        1.0 - t.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

impl FilmFresnel {
    /// Whether the base absorbs (a metal): then only reflection exists.
    pub(crate) fn is_conductor(&self) -> bool {
        self.spectral.base_k.iter().any(|&k| k > 0.0)
    }

    /// The thesis's (r, g, b) reflectance at `cos0` (signed as in [`FilmFresnel::eval`]).
    pub(crate) fn thesis_rgb(&self, cos0: f32) -> [f32; 3] {
        let t = &self.thesis;
        std::array::from_fn(|i| {
            if t.base_k[i] > 0.0 {
                return exact(
                    self.ext,
                    t.film[i],
                    t.base_n[i],
                    t.base_k[i],
                    self.d_nm,
                    t.lambda[i],
                    cos0,
                ) as f32;
            }
            let (n0, n2) = if cos0 >= 0.0 {
                (self.ext, t.base_n[i])
            } else {
                (t.base_n[i], self.ext)
            };
            thesis_reflectance(
                cos0.abs() as f64,
                n0 as f64,
                t.film[i] as f64,
                self.d_nm as f64,
                n2 as f64,
                t.lambda[i] as f64,
            ) as f32
        })
    }

    /// Reflectance R_λ at the path's wavelengths for light meeting the film at `cos0` (measured
    /// against the normal on the exterior side; negative: from inside the base), and the
    /// probability of choosing reflection.
    ///
    /// A BSDF often asks the same film at the same angle twice in a row (its value and its
    /// sampling density both need the Fresnel term at one half-vector; in the flagship 43 % of
    /// the calls repeat the one before), so each thread keeps its last answer with the film and
    /// angle it was for, compared bit for bit.
    #[inline]
    pub fn eval(&self, cos0: f32) -> (SampledSpectrum, f32) {
        thread_local! {
            static LAST: Cell<Option<Remembered>> = const { Cell::new(None) };
        }
        if let Some((film, cos, answer)) = LAST.get() {
            if cos == cos0.to_bits() && film.same_bits(self) {
                return answer;
            }
        }
        let answer = self.compute(cos0);
        LAST.set(Some((*self, cos0.to_bits(), answer)));
        answer
    }

    /// Whether `o` holds the same bits as `self` (not `==`, for which 0 and −0 are equal).
    #[inline]
    fn same_bits(&self, o: &FilmFresnel) -> bool {
        // Loops, not `map` and array `==`: those became calls (`try_map`, `memcmp`) that took
        // 3 % of the flagship's render.
        fn same<const K: usize>(a: &FilmSamples<K>, b: &FilmSamples<K>) -> bool {
            let mut same = true;
            for i in 0..K {
                same &= a.lambda[i].to_bits() == b.lambda[i].to_bits()
                    && a.film[i].to_bits() == b.film[i].to_bits()
                    && a.base_n[i].to_bits() == b.base_n[i].to_bits()
                    && a.base_k[i].to_bits() == b.base_k[i].to_bits();
            }
            same
        }
        self.mode == o.mode
            && self.ext.to_bits() == o.ext.to_bits()
            && self.d_nm.to_bits() == o.d_nm.to_bits()
            && same(&self.spectral, &o.spectral)
            && same(&self.thesis, &o.thesis)
    }

    /// [`FilmFresnel::eval`] without the memory of the last call.
    fn compute(&self, cos0: f32) -> (SampledSpectrum, f32) {
        match self.mode {
            FilmMode::Spectral => {
                let s = &self.spectral;
                let r = if s.base_k.iter().all(|&k| k == 0.0) {
                    // Real indices: the four wavelengths in one pass of 4-lane arithmetic.
                    let lane = |a: &[f32; N]| std::array::from_fn(|i| a[i] as f64);
                    let (ext, film, base) = ([self.ext as f64; N], lane(&s.film), lane(&s.base_n));
                    let (n0, n2) = if cos0 >= 0.0 {
                        (ext, base)
                    } else {
                        (base, ext)
                    };
                    let r4 = film_r4(
                        (cos0 as f64).abs(),
                        n0,
                        film,
                        self.d_nm as f64,
                        n2,
                        lane(&s.lambda),
                    );
                    SampledSpectrum::from_fn(|i| finite_r(r4[i]) as f32)
                } else {
                    SampledSpectrum::from_fn(|i| {
                        exact(
                            self.ext,
                            s.film[i],
                            s.base_n[i],
                            s.base_k[i],
                            self.d_nm,
                            s.lambda[i],
                            cos0,
                        ) as f32
                    })
                };
                (r, r.average())
            }
            FilmMode::Thesis => {
                let rgb = self.thesis_rgb(cos0);
                let poly = rgb_to_sigmoid(rgb);
                let lambda = self.spectral.lambda;
                let r = SampledSpectrum::from_fn(|i| poly.eval(lambda[i]));
                (r, (rgb[0] + rgb[1] + rgb[2]) / 3.0)
            }
        }
    }
}

impl super::fresnel::Fresnel for FilmFresnel {
    #[inline]
    fn reflectance(&self, cos: f32) -> (SampledSpectrum, f32) {
        self.eval(cos)
    }
    fn transmission(&self) -> super::fresnel::Transmission {
        if self.is_conductor() {
            super::fresnel::Transmission::Absorbed
        } else {
            super::fresnel::Transmission::Refract {
                eta: self.spectral.base_n[0] / self.ext,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film(d_nm: f32, base: f32, k: f32, mode: FilmMode) -> FilmFresnel {
        let samples = |lambda: [f32; N]| FilmSamples {
            lambda,
            film: lambda.map(|l| 1.532 + 5890.0 / (l * l)),
            base_n: [base; N],
            base_k: [k; N],
        };
        let thesis = FilmSamples {
            lambda: THESIS_LAMBDA,
            film: [1.56; 3],
            base_n: [base; 3],
            base_k: [k; 3],
        };
        FilmFresnel {
            ext: 1.0,
            d_nm,
            spectral: samples([420.0, 510.0, 600.0, 690.0]),
            thesis,
            mode,
        }
    }

    #[test]
    fn the_remembered_answer_is_given_only_for_the_same_film_and_angle() {
        // Films differing in one value each (thickness, also 0 against −0; base; absorption;
        // mode), asked at shared angles in an interleaved order, repeats included: every answer
        // must be a fresh computation's, bit for bit.
        let films = [
            film(330.0, 1.45, 0.0, FilmMode::Spectral),
            film(331.0, 1.45, 0.0, FilmMode::Spectral),
            film(0.0, 1.45, 0.0, FilmMode::Spectral),
            film(-0.0, 1.45, 0.0, FilmMode::Spectral),
            film(330.0, 1.5, 0.0, FilmMode::Spectral),
            film(330.0, 1.45, 0.3, FilmMode::Spectral),
            film(330.0, 1.45, 0.0, FilmMode::Thesis),
        ];
        let bits = |(r, p): (SampledSpectrum, f32)| {
            (
                std::array::from_fn::<u32, N, _>(|i| r[i].to_bits()),
                p.to_bits(),
            )
        };
        for cos in [1.0f32, 0.7, -0.4, 0.0, -0.0, 0.05] {
            for round in 0..2 {
                for (k, f) in films.iter().enumerate() {
                    let want = bits(f.compute(cos));
                    assert_eq!(bits(f.eval(cos)), want, "film {k} at {cos}, round {round}");
                    assert_eq!(bits(f.eval(cos)), want, "film {k} at {cos} again");
                }
            }
        }
    }
}
