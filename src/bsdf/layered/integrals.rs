//! The integrals of a coated diffuse stack's internal reflections that
//! [`super::closed_form`] needs: E, R_r and the sampling normalisation K of its module doc.
//!
//! Gauss–Legendre in the cosine with the substitution μ = μc + (1 − μc)s² past the critical
//! cosine μc, which removes the square-root kink of the Fresnel terms there. For a film coat
//! whose index and τ do not change with wavelength they come from a per-thread table on a
//! 1 nm × 1 nm grid of (thickness, wavelength), held in rows of wavelengths per (coat, film
//! index, τ, thickness) and interpolated bilinearly; otherwise (keratin, an RGB σ: a row per
//! wavelength, never met twice) from a 4-lane quadrature sized by the film's fringes.

use super::coat::CoatOptics;
use crate::optics::thinfilm::{film_r4, film_rt};
use crate::spectrum::{SampledSpectrum, N};
use num_complex::Complex64;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::OnceLock;

/// Gauss–Legendre nodes and weights on [0, 1]: the 24-point rule.
fn gauss_legendre() -> &'static [(f64, f64)] {
    gauss_legendre_n(3)
}

/// The rules with [`RULE_SIZES`]`[k]` points.
const RULE_SIZES: [usize; 4] = [8, 12, 16, 24];

/// Gauss–Legendre nodes and weights on [0, 1] with `RULE_SIZES[k]` points.
fn gauss_legendre_n(k: usize) -> &'static [(f64, f64)] {
    static NODES: [OnceLock<Vec<(f64, f64)>>; 4] = [const { OnceLock::new() }; 4];
    let m = RULE_SIZES[k];
    NODES[k].get_or_init(|| {
        let mut out = Vec::with_capacity(m);
        for i in 0..m {
            // Newton on P_m from the Chebyshev-like initial guess.
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (m as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=m {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = m as f64 * (x * p1 - p0) / (x * x - 1.0);
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
    kinked_nodes_by(mu_c, gauss_legendre())
}

/// [`kinked_nodes`] with the rule `gl` on each side of the kink.
fn kinked_nodes_by(mu_c: f64, gl: &'static [(f64, f64)]) -> impl Iterator<Item = (f64, f64)> {
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
pub(crate) fn critical_cosines(eta: f64) -> (f64, f64) {
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

/// E, R_r and K of a film coat at the path's four wavelengths at once, by quadrature in
/// 4-lane arithmetic: one [`film_r4`] per node serves all wavelengths, and below the critical
/// cosine (total internal reflection, F = 1) no film is evaluated at all. The rule's size
/// follows the fringes: the film's phase 4π n d cos θ_f / λ changes by 4π n d (1 − cos θ_f,min)
/// / λ across the cosines, sin θ_f ≤ 1 / n wherever light crosses the film, and the rule takes
/// 8 points and 6 more per fringe (24, the table's rule, beyond 2.7 fringes; a 330 nm keratin
/// film takes 12). `film_integrals_direct_matches_a_fine_sum` bounds its error (< 1e-4).
///
/// For films whose index or optical depth changes with wavelength (keratin, an RGB σ), where
/// the table's rows — one per index and τ — would rarely be met twice.
pub(crate) fn film_integrals_direct(
    coat: CoatOptics,
    tau: SampledSpectrum,
) -> (SampledSpectrum, SampledSpectrum, f32) {
    let (eta, film_ior, thickness_nm, lambda) = coat.film_parts();
    let (eta, d) = (eta as f64, thickness_nm.max(0.0) as f64);
    let lane = |a: [f32; N]| a.map(|x| x as f64);
    let (film, lambda, tau) = (
        lane(film_ior),
        lane(lambda),
        lane(tau.0.map(|t| t.max(0.0))),
    );
    // Fringes across the cosines that cross the film.
    let mut fringes = 0.0f64;
    for i in 0..N {
        let s = (1.0 / film[i]).min(1.0);
        let c_min = (1.0 - s * s).sqrt();
        fringes = fringes.max(2.0 * film[i] * d * (1.0 - c_min) / lambda[i]);
    }
    let rule = RULE_SIZES
        .iter()
        .position(|&m| m as f64 >= 6.0 * fringes + 8.0)
        .unwrap_or(RULE_SIZES.len() - 1);
    let gl = gauss_legendre_n(rule);
    let (mu_c_in, mu_c_out) = critical_cosines(eta);
    let (mut e, mut r) = ([0.0f64; N], [0.0f64; N]);
    for (mu, w) in kinked_nodes_by(mu_c_in, gl) {
        if mu <= 0.0 {
            continue;
        }
        let f = if mu < mu_c_in {
            [1.0; N]
        } else {
            film_r4(mu, [eta; N], film, d, [1.0; N], lambda)
        };
        for i in 0..N {
            let a = (-tau[i] / mu).exp();
            let fi = f[i].clamp(0.0, 1.0);
            e[i] += w * 2.0 * mu * a * (1.0 - fi);
            r[i] += w * 2.0 * mu * a * a * fi;
        }
    }
    let mut k = 0.0;
    for (mu, w) in kinked_nodes_by(mu_c_out, gl) {
        let f = film_r4(mu, [1.0; N], film, d, [eta; N], lambda);
        let mean = f.iter().sum::<f64>() / N as f64;
        k += w * 2.0 * mu * (1.0 - mean);
    }
    (
        SampledSpectrum(e.map(|v| v as f32)),
        SampledSpectrum(r.map(|v| v as f32)),
        k as f32,
    )
}

/// E, R_r and K of a film coat: from the per-thread table where its row serves all four
/// wavelengths (a film index and optical depth that do not change with wavelength, rounded as
/// the table's key rounds them), else by the 4-lane quadrature.
pub(crate) fn film_integrals(
    coat: CoatOptics,
    tau: SampledSpectrum,
) -> (SampledSpectrum, SampledSpectrum, f32) {
    let (_, film_ior, _, _) = coat.film_parts();
    let (film_q, tau_q) = (film_index_key(film_ior), tau_key(tau));
    if film_q.iter().all(|&q| q == film_q[0]) && tau_q.iter().all(|&q| q == tau_q[0]) {
        film_integrals_tabulated(coat, film_q[0], tau_q[0])
    } else {
        film_integrals_direct(coat, tau)
    }
}

/// The table's key for the film index: rounded to 1e-4 (a phase change below 2e-3 rad for
/// d ≤ 2 µm).
fn film_index_key(film_ior: [f32; N]) -> [i32; N] {
    // Saturating, as `f32 as i32` did (an `i64 as i32` would wrap).
    let k = |n: f32| round_half_up(n * 1e4).clamp(i32::MIN as i64, i32::MAX as i64) as i32;
    [
        k(film_ior[0]),
        k(film_ior[1]),
        k(film_ior[2]),
        k(film_ior[3]),
    ]
}

/// `x.floor()` for x ≥ 0 (a thickness, a wavelength) by the truncating conversion, not the
/// C library's `floorf` (the baseline build has no `roundss`), bit for bit; beyond 2²⁴, where
/// every f32 is an integer, x itself.
#[inline]
fn floor_nonneg(x: f32) -> f32 {
    if x < 16_777_216.0 {
        (x as i32) as f32
    } else {
        x.floor()
    }
}

/// `x.round()` for x ≥ 0 (halves up, as `round` takes them away from zero), without the C
/// library's `roundf`, which the baseline x86-64 build calls (no SSE4.1 `roundss`) and which
/// was 0.8 % of a render of the thin-film benchmark sphere: x + ½ is exact in f64 and the
/// truncating conversion (one instruction, unlike `trunc`) is its floor. Negative x (no index
/// or depth here) round halves towards zero instead; NaN gives 0, as `round` then `as` does.
#[inline]
fn round_half_up(x: f32) -> i64 {
    (x as f64 + 0.5) as i64
}

/// The table's key for the optical depth: rounded to 1e-3 (|ΔE/E| ≤ 1e-3); saturates at 2³² − 1
/// (τ ≈ 4·10⁶, opaque).
fn tau_key(tau: SampledSpectrum) -> [u32; N] {
    // Saturating, as `f32 as u32` did: an opaque slab's τ · 1e3 can pass 2³².
    let k = |t: f32| round_half_up(t.max(0.0) * 1e3).clamp(0, u32::MAX as i64) as u32;
    [k(tau[0]), k(tau[1]), k(tau[2]), k(tau[3])]
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

/// (η bits, film index × 1e4, τ × 1e3, thickness nm): one row of the film-integral table.
type RowKey = (u32, i32, u32, i32);
/// E, R_r, K at every integer wavelength 0 … ROW − 1 nm (NaN: not computed yet).
type Row = [[f32; 3]; ROW];
const ROW: usize = 1024;

/// The per-thread film-integral table: rows found by key, and the last two rows found, which
/// a coat of one thickness (or of slowly varying thickness) asks for again at every shading
/// point, checked before hashing.
#[derive(Default)]
struct FilmTable {
    index: std::collections::HashMap<RowKey, usize, BuildHasherDefault<KeyHasher>>,
    rows: Vec<Box<Row>>,
    recent: [Option<(RowKey, usize)>; 2],
}

impl FilmTable {
    /// The row for `key`, made (all NaN) if new.
    fn row(&mut self, key: RowKey) -> &mut Row {
        let found = self
            .recent
            .iter()
            .flatten()
            .find(|r| r.0 == key)
            .map(|r| r.1);
        let at = match found {
            Some(at) => at,
            None => {
                // Bound the memory a long, varied render can take (12 KiB a row).
                if self.rows.len() >= 1024 {
                    *self = FilmTable::default();
                }
                let rows = &mut self.rows;
                let at = *self.index.entry(key).or_insert_with(|| {
                    rows.push(Box::new([[f32::NAN; 3]; ROW]));
                    rows.len() - 1
                });
                self.recent = [Some((key, at)), self.recent[0]];
                at
            }
        };
        &mut self.rows[at]
    }
}

thread_local! {
    static FILM_TABLE: std::cell::RefCell<FilmTable> = std::cell::RefCell::new(FilmTable::default());
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
///
/// `film_q` and `tau_q` are the table keys of the film index and τ, which [`film_integrals`]
/// has checked all four wavelengths share.
fn film_integrals_tabulated(
    coat: CoatOptics,
    film_q: i32,
    tau_q: u32,
) -> (SampledSpectrum, SampledSpectrum, f32) {
    let (eta, _, thickness_nm, lambda) = coat.film_parts();
    let d = thickness_nm.max(0.0);
    let d0 = floor_nonneg(d);
    let fd = d - d0;
    let value = |dd: f32, l: i32| {
        let (e, r, k) = film_integrals_1(
            eta as f64,
            film_q as f64 * 1e-4,
            (d0 + dd) as f64,
            l as f64,
            tau_q as f64 * 1e-3,
        );
        [e as f32, r as f32, k as f32]
    };
    let mut acc = [[0.0f32; 3]; N];
    FILM_TABLE.with(|t| {
        let mut t = t.borrow_mut();
        for (dd, wd) in [(0.0, 1.0 - fd), (1.0, fd)] {
            // A whole number of nanometres (a constant film's usual thickness) needs one row.
            if wd == 0.0 {
                continue;
            }
            let row = t.row((eta.to_bits(), film_q, tau_q, (d0 + dd) as i32));
            for i in 0..N {
                let l = lambda[i];
                let l0 = floor_nonneg(l);
                let fl = l - l0;
                for (dl, wl) in [(0.0, 1.0 - fl), (1.0, fl)] {
                    let w = wd * wl;
                    if w == 0.0 {
                        continue;
                    }
                    let li = (l0 + dl) as i32;
                    let v = match usize::try_from(li).ok().filter(|&j| j < ROW) {
                        Some(j) => {
                            if row[j][0].is_nan() {
                                row[j] = value(dd, li);
                            }
                            row[j]
                        }
                        // Outside the row (an exterior index far from 1): not remembered.
                        None => value(dd, li),
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

#[cfg(test)]
mod key_tests {
    use super::*;

    #[test]
    fn keys_and_floors_are_the_library_roundings() {
        // The table's keys and its interpolation's floors, computed without the C library,
        // equal `round`/`floor` then a saturating cast on the values they take (non-negative),
        // halves included, and saturate where those did.
        let mut next = crate::math::rng::uniform_f64s(5);
        let mut xs: Vec<f32> = (0..20000).map(|_| (next() * 3000.0) as f32).collect();
        xs.extend([
            0.0,
            0.5,
            1.5,
            2.5,
            1e4 + 0.5,
            0.499_999_97,
            16_777_215.0,
            3e7,
            1e12,
        ]);
        for x in xs {
            assert_eq!(floor_nonneg(x).to_bits(), x.floor().to_bits(), "floor {x}");
            let want_i = (x * 1e4).round() as i32;
            assert_eq!(film_index_key([x; N])[0], want_i, "index key {x}");
            let want_u = (x * 1e3).round() as u32;
            assert_eq!(tau_key(SampledSpectrum::splat(x))[0], want_u, "tau key {x}");
        }
        assert_eq!(tau_key(SampledSpectrum::splat(f32::NAN))[0], 0);
    }
}
