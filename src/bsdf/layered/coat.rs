//! The coat of a coated diffuse stack: its reflectance at the path's wavelengths — a bare
//! dielectric (Fresnel), or a dielectric under a thin film, whose Airy sum runs for the four
//! wavelengths in one pass of 4-lane arithmetic ([`crate::optics::thinfilm::film_r4`]) and is
//! remembered per thread for the last four (coat, cosine, side), since the BSDF asks the same
//! angles in `f`, `pdf` and `sample_f` (the memo is borrowed in place and its keys compared
//! whole: copying it cost 10 %). The integrals of its internal reflections are in
//! `integrals.rs`.

use crate::bsdf::fresnel::fresnel_dielectric;
use crate::optics::thinfilm::film_r4;
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
            CoatOptics::Film { .. } => self.film_memo(mu, inside),
        }
    }

    /// A film coat's reflectance, remembered: the BSDF asks for the coat at μo and μi (and a
    /// rough coat at wo·wm) in `f`, again in `pdf` and in `sample_f`, so each thread keeps its
    /// last four answers with the coat, cosine and side they were for, compared bit for bit
    /// (an answer is a pure function of those, so a remembered one is the one
    /// [`CoatOptics::film`] would give).
    fn film_memo(&self, mu: f32, inside: bool) -> SampledSpectrum {
        type Key = [u32; 4 + 2 * N];
        /// Keys, answers, and the slot the next answer takes. An unused slot's key is all
        /// ones, which no coat makes (its side word is 0 or 1).
        struct Memo {
            keys: [Key; 4],
            answers: [SampledSpectrum; 4],
            next: usize,
        }
        thread_local! {
            // Borrowed in place: a `Cell` would copy it all in and out on every call.
            static LAST: std::cell::RefCell<Memo> = const {
                std::cell::RefCell::new(Memo {
                    keys: [[u32::MAX; 4 + 2 * N]; 4],
                    answers: [SampledSpectrum([0.0; N]); 4],
                    next: 0,
                })
            };
        }
        let key = self.film_key(mu, inside);
        LAST.with(|last| {
            let mut last = last.borrow_mut();
            // Each key compared whole, by folding the differences (no early exit, no memcmp).
            for (k, answer) in last.keys.iter().zip(&last.answers) {
                if k.iter().zip(&key).fold(0, |d, (a, b)| d | (a ^ b)) == 0 {
                    return *answer;
                }
            }
            let answer = self.film(mu, inside);
            let slot = last.next;
            last.keys[slot] = key;
            last.answers[slot] = answer;
            last.next = (slot + 1) % 4;
            answer
        })
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

    /// The bits a film coat's answer depends on: η, thickness, the side and cosine, and the
    /// film index and wavelength of each lane.
    fn film_key(&self, mu: f32, inside: bool) -> [u32; 4 + 2 * N] {
        let (eta, film_ior, thickness_nm, lambda) = self.film_parts();
        let mut k = [0u32; 4 + 2 * N];
        k[0] = eta.to_bits();
        k[1] = thickness_nm.to_bits();
        k[2] = mu.to_bits();
        k[3] = inside as u32;
        for i in 0..N {
            k[4 + i] = film_ior[i].to_bits();
            k[4 + N + i] = lambda[i].to_bits();
        }
        k
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
