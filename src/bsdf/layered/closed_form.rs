//! Closed form of a smooth coat over a non-scattering absorbing slab over a Lambertian base —
//! the zero-variance fast path of [`super::LayeredBxdf`] and the oracle of its random walk.
//!
//! Derivation (research/layered.md §3.1; the τ = 0 case is the `nonlinear` plastic of
//! Weidlich & Wilkie 2007 / Kelemen & Szirmay-Kalos 2001). The Lambertian base turns every
//! direction into a cosine distribution, so light inside the coat forms a geometric series:
//! with η the coat's relative index, F(μ) the coat's reflectance seen from outside, F_int(μ′)
//! from inside (1 beyond the critical angle), μ′(μ) = √(1 − (1 − μ²)/η²) the refracted cosine,
//! ρ the base albedo and τ the slab's optical depth,
//!
//! - escape fraction  E   = ∫₀¹ 2μ′ e^{−τ/μ′} (1 − F_int(μ′)) dμ′,
//! - return fraction  R_r = ∫₀¹ 2μ′ e^{−2τ/μ′} F_int(μ′) dμ′,
//! - diffuse part     f   = (1 − F(μo))(1 − F(μi)) e^{−τ/μ′o} e^{−τ/μ′i} ρ / (π η² (1 − ρ R_r)),
//! - albedo           R(μ) = F(μ) + (1 − F(μ)) e^{−τ/μ′} ρ E / (1 − ρ R_r),
//!
//! plus a delta reflection of weight F(μ). (Flux leaving the base is cosine-distributed inside;
//! étendue η² μ′ dω′ = μ dω maps it outside, and 1 − F_int(μ′) = 1 − F(μ) for a lossless coat.)
//! The same formulas hold per wavelength for a thin-film coat (research/layered.md §3.2) with F
//! the film stack's Airy reflectance ([`crate::optics::thinfilm::film_rt`]).
//! f is symmetric, so radiance and importance modes agree.
//!
//! Sampling (exact pdf, §3.3 with the λ-averaged coat): the delta lobe with probability
//! P = F̄(μo)/R̄(μo), its share of the directional albedo (means over the path's wavelengths,
//! weight F_λ/P), so that over a dark base the visible reflection gets the samples (choosing
//! it with F̄ alone gave it ~4 % of them, and a constant sky seen in it a relative variance of
//! ~1/F̄ per sample); otherwise a direction with density
//! p(ωi) = (1 − P) T̄(μi) μi / (π K), K = ∫₀¹ 2μ T̄(μ) dμ, T̄ = 1 − F̄, drawn by cosine
//! sampling and accepting with probability T̄(μi) (acceptance ≈ 0.9 for η = 1.5).
//!
//! A rough coat (`rough_coat` = `plastic`, [`CoatedDiffuse::with_rough`]) keeps the diffuse
//! part and its sampling and replaces the delta lobe, chosen with the same probability P, by
//! the microfacet reflection F(wo·wm) D G / (4 μo μi), sampled by visible normals; the pdf is
//! the mixture P · D_wo(wm) / (4 wo·wm) + (1 − P) p(ωi). This is the plastic approximation of
//! Weidlich & Wilkie 2007 (Mitsuba's `roughplastic`), not exact (see [`super`]).
//!
//! Integrals: Gauss–Legendre in the cosine with the substitution μ = μc + (1 − μc)s² past the
//! critical cosine μc, which removes the square-root kink of the Fresnel terms there.
//! Known limits: coat factors `specular_reflectance`/`specular_transmittance` must be 1 (other
//! stacks use the random walk); the quadrature (48 nodes; for a film top ~200 Airy evaluations,
//! ≈ 33 µs) is memoised per thread for the last 8 (coat, τ) — a hit for constant materials with
//! a plain coat, a miss for film coats, whose wavelengths change per path.

use crate::bsdf::fresnel::fresnel_dielectric;
use crate::bsdf::microfacet::MicrofacetDistribution;
use crate::bsdf::{BsdfSample, BxdfFlags};
use crate::math::{reflect, warp, Pcg32, Vec2, Vec3, INV_PI};
use crate::optics::thinfilm::{film_r4, film_rt};
use crate::spectrum::{SampledSpectrum, N};
use num_complex::Complex64;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::OnceLock;

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
        type Remembered = ([u32; 4 + 2 * N], SampledSpectrum);
        thread_local! {
            static LAST: std::cell::Cell<[Option<Remembered>; 4]> =
                const { std::cell::Cell::new([None; 4]) };
        }
        let key = self.film_key(mu, inside);
        // Compared by folding the differences (`==` on the array calls `memcmp`).
        let same = |k: &[u32; 4 + 2 * N]| k.iter().zip(&key).fold(0, |d, (a, b)| d | (a ^ b)) == 0;
        let last = LAST.get();
        for (k, answer) in last.iter().flatten() {
            if same(k) {
                return *answer;
            }
        }
        let answer = self.film(mu, inside);
        LAST.set([Some((key, answer)), last[0], last[1], last[2]]);
        answer
    }

    /// A film coat's η, film indices, thickness and wavelengths.
    fn film_parts(&self) -> (f32, [f32; N], f32, [f32; N]) {
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

/// Gauss–Legendre nodes and weights on [0, 1].
fn gauss_legendre() -> &'static [(f64, f64)] {
    const M: usize = 24;
    static NODES: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    NODES.get_or_init(|| {
        let mut out = Vec::with_capacity(M);
        for i in 0..M {
            // Newton on P_M from the Chebyshev-like initial guess.
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (M as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=M {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = M as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            out.push((0.5 * (1.0 - x), 0.5 * w));
        }
        out
    })
}

/// Quadrature nodes (μ, weight) of ∫₀¹ · dμ for integrands with a kink at `mu_c` (0: none):
/// Gauss–Legendre on [0, μc] and, with μ = μc + (1 − μc)s², on [μc, 1].
pub(crate) fn kinked_nodes(mu_c: f64) -> impl Iterator<Item = (f64, f64)> {
    let gl = gauss_legendre();
    let below = gl
        .iter()
        .filter(move |_| mu_c > 0.0)
        .map(move |&(x, w)| (mu_c * x, w * mu_c));
    let above = gl
        .iter()
        .map(move |&(x, w)| (mu_c + (1.0 - mu_c) * x * x, w * 2.0 * (1.0 - mu_c) * x));
    below.chain(above)
}

/// Cosine of the refracted direction inside a coat of relative index `eta` (0 under total
/// internal reflection).
#[inline]
pub(crate) fn refracted_cos(mu: f32, eta: f32) -> f32 {
    (1.0 - (1.0 - mu * mu) / (eta * eta)).max(0.0).sqrt()
}

/// The critical cosines of a coat of relative index `eta`: inside, below which light cannot
/// leave (0 when η ≤ 1), and outside, below which it cannot enter (0 when η ≥ 1).
fn critical_cosines(eta: f64) -> (f64, f64) {
    let inside = if eta > 1.0 {
        (1.0 - 1.0 / (eta * eta)).sqrt()
    } else {
        0.0
    };
    let outside = if eta < 1.0 {
        (1.0 - eta * eta).sqrt()
    } else {
        0.0
    };
    (inside, outside)
}

/// E, R_r and K (see the module header) of a film coat at one wavelength, by quadrature.
pub(crate) fn film_integrals_1(
    eta: f64,
    film: f64,
    d_nm: f64,
    lambda: f64,
    tau: f64,
) -> (f64, f64, f64) {
    let (mu_c_in, mu_c_out) = critical_cosines(eta);
    let n_film = Complex64::new(film, 0.0);
    let (mut e, mut r) = (0.0, 0.0);
    for (mu, w) in kinked_nodes(mu_c_in) {
        let fi = film_rt(mu, eta, n_film, d_nm, Complex64::new(1.0, 0.0), lambda)
            .r()
            .clamp(0.0, 1.0);
        if mu > 0.0 {
            e += w * 2.0 * mu * (-tau / mu).exp() * (1.0 - fi);
            r += w * 2.0 * mu * (-2.0 * tau / mu).exp() * fi;
        }
    }
    let k = kinked_nodes(mu_c_out)
        .map(|(mu, w)| {
            w * 2.0
                * mu
                * (1.0 - film_rt(mu, 1.0, n_film, d_nm, Complex64::new(eta, 0.0), lambda).r())
        })
        .sum::<f64>();
    (e, r, k)
}

/// The film-integral table's hasher: its keys are a few small integers made by the renderer,
/// not by an adversary, so SipHash's protection is not needed, and its cost was a tenth of a
/// thin-film render (16 lookups per shading point). Each word is folded in by a rotate, xor
/// and odd multiply (the multiply spreads low bits upwards; `finish` mixes the high half
/// back down, since the table takes its bucket from the low bits).
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    #[inline]
    fn write_u32(&mut self, x: u32) {
        self.write_u64(x as u64);
    }
    #[inline]
    fn write_i32(&mut self, x: i32) {
        self.write_u64(x as u32 as u64);
    }
    #[inline]
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(26) ^ x).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
    #[inline]
    fn finish(&self) -> u64 {
        self.0 ^ (self.0 >> 29)
    }
}

/// Film-coat integrals at the path's wavelengths, interpolated bilinearly from a per-thread
/// table on a 1 nm × 1 nm grid of (thickness, wavelength).
///
/// A film coat's wavelengths change with every path (and its thickness may change from scale to
/// scale), so memoising whole (coat, τ) tuples never hits; evaluating the quadrature each time
/// costs ~50 µs per shading point. The integrals are smooth in λ and d (fringe periods are tens
/// of nm for films up to a few µm), so linear interpolation over 1 nm errs by ~(2π·1/P)²/8
/// relative, P the fringe period: < 1e-3 for P ≥ 70 nm. The film index is rounded to 1e-4
/// for the table key (a phase change below 2e-3 rad for d ≤ 2 µm) and the optical depth τ to
/// 1e-3 (|ΔE/E| ≤ 5e-4 · E[1/μ] ≈ 1e-3 for the cosine-weighted escape integral).
fn film_integrals_tabulated(
    coat: CoatOptics,
    tau: SampledSpectrum,
) -> (SampledSpectrum, SampledSpectrum, f32) {
    use std::collections::HashMap;
    /// (η bits, film index × 1e4, τ × 1e3, thickness nm): one row of the table.
    type Key = (u32, i32, u32, i32);
    /// E, R_r, K at every integer wavelength 0 … ROW − 1 nm (NaN: not computed yet).
    type Row = [[f32; 3]; ROW];
    const ROW: usize = 1024;
    type Table = HashMap<Key, Box<Row>, BuildHasherDefault<KeyHasher>>;
    thread_local! {
        static TABLE: std::cell::RefCell<Table> = std::cell::RefCell::new(Table::default());
    }
    let CoatOptics::Film {
        eta,
        film_ior,
        thickness_nm,
        lambda,
    } = coat
    else {
        unreachable!("called for film coats only")
    };
    let d = thickness_nm.max(0.0);
    let (d0, fd) = (d.floor(), d - d.floor());
    // Per wavelength: the row key's film index and τ, the grid wavelength and the weights.
    let film_q: [i32; N] = std::array::from_fn(|i| (film_ior[i] * 1e4).round() as i32);
    // τ usually varies with λ (an RGB σ is uplifted to a smooth spectrum), so it is rounded
    // to 1e-3 for the key, or the table would never hit.
    let tau_q: [u32; N] = std::array::from_fn(|i| (tau[i].max(0.0) * 1e3).round() as u32);
    let value = |dd: f32, i: usize, l: i32| {
        let (e, r, k) = film_integrals_1(
            eta as f64,
            film_q[i] as f64 * 1e-4,
            (d0 + dd) as f64,
            l as f64,
            tau_q[i] as f64 * 1e-3,
        );
        [e as f32, r as f32, k as f32]
    };
    let mut acc = [[0.0f32; 3]; N];
    TABLE.with(|t| {
        let mut t = t.borrow_mut();
        // Bound the memory a long, varied render can take (12 KiB a row).
        if t.len() > 1024 {
            t.clear();
        }
        for (dd, wd) in [(0.0, 1.0 - fd), (1.0, fd)] {
            // The wavelengths usually share one row (one film index and τ): look it up once.
            let mut cur: Option<(Key, &mut Box<Row>)> = None;
            for i in 0..N {
                let l = lambda[i];
                let (l0, fl) = (l.floor(), l - l.floor());
                let key = (eta.to_bits(), film_q[i], tau_q[i], (d0 + dd) as i32);
                if cur.as_ref().is_none_or(|c| c.0 != key) {
                    let row = t
                        .entry(key)
                        .or_insert_with(|| Box::new([[f32::NAN; 3]; ROW]));
                    cur = Some((key, row));
                }
                let row = &mut cur.as_mut().expect("looked up above").1;
                for (dl, wl) in [(0.0, 1.0 - fl), (1.0, fl)] {
                    let w = wd * wl;
                    if w == 0.0 {
                        continue;
                    }
                    let li = (l0 + dl) as i32;
                    let v = match usize::try_from(li).ok().filter(|&j| j < ROW) {
                        Some(j) => {
                            if row[j][0].is_nan() {
                                row[j] = value(dd, i, li);
                            }
                            row[j]
                        }
                        // Outside the row (an exterior index far from 1): not remembered.
                        None => value(dd, i, li),
                    };
                    for c in 0..3 {
                        acc[i][c] += w * v[c];
                    }
                }
            }
        }
    });
    let escape = SampledSpectrum(std::array::from_fn(|i| acc[i][0]));
    let ret = SampledSpectrum(std::array::from_fn(|i| acc[i][1]));
    let mut k_sum = 0.0f32;
    for a in &acc {
        k_sum += a[2];
    }
    (escape, ret, k_sum / N as f32)
}

/// The smooth coat + absorbing slab + Lambertian base, evaluated in closed form.
#[derive(Clone, Debug)]
pub struct CoatedDiffuse {
    pub coat: CoatOptics,
    /// Base albedo ρ.
    pub rho: SampledSpectrum,
    /// Optical depth τ of the slab.
    pub tau: SampledSpectrum,
    /// Escape fraction E per wavelength.
    pub escape: SampledSpectrum,
    /// Return fraction R_r per wavelength.
    pub ret: SampledSpectrum,
    /// Sampling normalisation K = ∫ 2μ T̄(μ) dμ.
    pub k_norm: f32,
    /// A rough coat's microfacets (`None`: smooth). See [`CoatedDiffuse::with_rough`].
    pub rough: Option<MicrofacetDistribution>,
}

impl CoatedDiffuse {
    /// Precomputes the internal-reflection integrals for this coat, base and slab. The
    /// integrals do not depend on ρ; the last few (coat, τ) of each thread are memoised, so a
    /// material with constant parameters pays the quadrature once rather than per shading point.
    pub fn new(coat: CoatOptics, rho: SampledSpectrum, tau: SampledSpectrum) -> CoatedDiffuse {
        type Entry = Option<(
            CoatOptics,
            SampledSpectrum,
            SampledSpectrum,
            SampledSpectrum,
            f32,
        )>;
        thread_local! {
            static MEMO: std::cell::RefCell<([Entry; 8], usize)> =
                const { std::cell::RefCell::new(([None; 8], 0)) };
        }
        let (escape, ret, k_norm) = if let CoatOptics::Film { .. } = coat {
            film_integrals_tabulated(coat, tau)
        } else {
            let hit = MEMO.with(|m| {
                m.borrow()
                    .0
                    .iter()
                    .flatten()
                    .find(|e| e.0 == coat && e.1 == tau)
                    .copied()
            });
            match hit {
                Some((_, _, e, r, k)) => (e, r, k),
                None => {
                    let v = Self::integrals(coat, tau);
                    MEMO.with(|m| {
                        let mut m = m.borrow_mut();
                        let slot = m.1;
                        m.0[slot] = Some((coat, tau, v.0, v.1, v.2));
                        m.1 = (slot + 1) % 8;
                    });
                    v
                }
            }
        };
        CoatedDiffuse {
            coat,
            rho,
            tau,
            escape,
            ret,
            k_norm,
            rough: None,
        }
    }

    /// The same stack under a rough coat, approximated as Mitsuba's `roughplastic` is
    /// (Weidlich & Wilkie 2007): the delta reflection becomes the microfacet reflection
    /// F(wo·wm) D G / (4 μo μi), F the coat's (film's) reflectance at the microfacet, and
    /// the diffuse part keeps the smooth coat's transmittances. Exact as α → 0; for larger α it
    /// ignores the light the rough interface scatters into and out of the base at other
    /// angles (and the lobe's own shadowing loss), see the module doc of
    /// [`super`] for the measured difference from the random walk.
    pub fn with_rough(mut self, d: MicrofacetDistribution) -> CoatedDiffuse {
        self.rough = Some(d);
        self
    }

    /// E, R_r per wavelength and the sampling normalisation K, by quadrature.
    fn integrals(
        coat: CoatOptics,
        tau: SampledSpectrum,
    ) -> (SampledSpectrum, SampledSpectrum, f32) {
        let eta = coat.eta() as f64;
        let (mu_c_in, mu_c_out) = critical_cosines(eta);
        let mut escape = [0.0f64; N];
        let mut ret = [0.0f64; N];
        for (mu, w) in kinked_nodes(mu_c_in) {
            // F_int once per node for all wavelengths.
            let f_int = coat.inside(mu as f32);
            for i in 0..N {
                let t = tau[i] as f64;
                let (e1, e2) = if mu > 0.0 {
                    ((-t / mu).exp(), (-2.0 * t / mu).exp())
                } else {
                    (0.0, 0.0)
                };
                let fi = (f_int[i] as f64).clamp(0.0, 1.0);
                escape[i] += w * 2.0 * mu * e1 * (1.0 - fi);
                ret[i] += w * 2.0 * mu * e2 * fi;
            }
        }
        let k_norm = kinked_nodes(mu_c_out)
            .map(|(mu, w)| w * 2.0 * mu * (1.0 - coat.outside(mu as f32).average() as f64))
            .sum::<f64>() as f32;
        (
            SampledSpectrum(escape.map(|v| v as f32)),
            SampledSpectrum(ret.map(|v| v as f32)),
            k_norm,
        )
    }

    /// Lobes: a delta reflection off the coat and the diffuse part.
    pub(crate) fn flags(&self) -> BxdfFlags {
        let coat = match self.rough {
            None => BxdfFlags::SPECULAR_REFLECTION,
            Some(_) => BxdfFlags::GLOSSY_REFLECTION,
        };
        coat | BxdfFlags::DIFFUSE_REFLECTION
    }

    /// Slab transmittance e^{−τ/μ′} for an outside cosine `mu`.
    fn slab(&self, mu: f32) -> SampledSpectrum {
        let mt = refracted_cos(mu, self.coat.eta());
        if mt <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        (-self.tau / mt).exp()
    }

    /// The diffuse part's constant ρ / (π η² (1 − ρ R_r)).
    fn diffuse_scale(&self) -> SampledSpectrum {
        let eta = self.coat.eta();
        self.rho * INV_PI / ((SampledSpectrum::ONE - self.rho * self.ret) * (eta * eta))
    }

    /// Directional albedo R(μ) including the delta reflection (of the smooth coat; a rough
    /// coat's reflection has the same albedo only in the limit α → 0).
    pub fn albedo(&self, mu: f32) -> SampledSpectrum {
        let f = self.coat.outside(mu);
        f + self.diffuse_albedo(f, mu)
    }

    /// The diffuse part's share of the albedo at μ, given the coat's reflectance `f` there.
    fn diffuse_albedo(&self, f: SampledSpectrum, mu: f32) -> SampledSpectrum {
        (SampledSpectrum::ONE - f) * self.slab(mu) * self.rho * self.escape
            / (SampledSpectrum::ONE - self.rho * self.ret)
    }

    /// The diffuse part of the BSDF (no cosine).
    pub fn f(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let t_o = SampledSpectrum::ONE - self.coat.outside(wo.z);
        let t_i = SampledSpectrum::ONE - self.coat.outside(wi.z);
        let diffuse = t_o * t_i * self.slab(wo.z) * self.slab(wi.z) * self.diffuse_scale();
        match self.microfacet(wo, wi) {
            Some((wm, d)) => {
                let spec = d.d(wm) * d.g(wo, wi) / (4.0 * wo.z * wi.z);
                diffuse + self.coat.outside(wo.dot(wm)) * spec
            }
            None => diffuse,
        }
    }

    /// A rough coat's microfacet normal for the reflection pair (wo, wi), both above.
    fn microfacet(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, &MicrofacetDistribution)> {
        let d = self.rough.as_ref()?;
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return None;
        }
        Some((wm.normalize(), d))
    }

    /// The probability of the delta lobe at μo: F̄/R̄ (module doc), F̄ itself where the
    /// albedo is not positive.
    fn spec_choice(&self, f_o: SampledSpectrum, mu: f32) -> f32 {
        let f = f_o.average();
        let r = f + self.diffuse_albedo(f_o, mu).average();
        let p = if r > 0.0 { f / r } else { f };
        if p.is_finite() {
            p.clamp(0.0, 1.0)
        } else {
            f
        }
    }

    /// Exact density of the non-delta samples.
    pub(crate) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 || self.k_norm <= 0.0 {
            return 0.0;
        }
        let p_spec = self.spec_choice(self.coat.outside(wo.z), wo.z);
        let t_bar = 1.0 - self.coat.outside(wi.z).average();
        let diffuse = (1.0 - p_spec) * t_bar * wi.z * INV_PI / self.k_norm;
        match self.microfacet(wo, wi) {
            Some((wm, d)) => diffuse + p_spec * d.pdf(wo, wm) / (4.0 * wo.dot(wm)),
            None => diffuse,
        }
    }

    /// Samples the delta lobe or the diffuse part (see the module doc).
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, rng: &mut Pcg32) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let f_o = self.coat.outside(wo.z);
        let p_spec = self.spec_choice(f_o, wo.z);
        if let (true, Some(d)) = (uc < p_spec, &self.rough) {
            let wi = reflect(wo, d.sample_wm(wo, u));
            if wi.z <= 0.0 {
                return None;
            }
            let pdf = self.pdf(wo, wi);
            if pdf.is_nan() || pdf <= 0.0 {
                return None;
            }
            let f = self.f(wo, wi);
            return Some(BsdfSample::new(f, wi, pdf, BxdfFlags::GLOSSY_REFLECTION));
        }
        if uc < p_spec {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample::new(
                f_o / (p_spec * wi.z),
                wi,
                1.0,
                BxdfFlags::SPECULAR_REFLECTION,
            ));
        }
        let mut uu = u;
        for _ in 0..64 {
            let wi = warp::square_to_cosine_hemisphere(uu);
            let t_bar = 1.0 - self.coat.outside(wi.z).average();
            if wi.z > 0.0 && rng.next_f32() < t_bar {
                let pdf = self.pdf(wo, wi);
                if pdf.is_nan() || pdf <= 0.0 {
                    return None;
                }
                let f = self.f(wo, wi);
                return Some(BsdfSample::new(f, wi, pdf, BxdfFlags::DIFFUSE_REFLECTION));
            }
            uu = rng.next_vec2();
        }
        None
    }
}
