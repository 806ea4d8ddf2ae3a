//! The single film's reflectance in SIMD lanes: [`film_r4`] at a path's four wavelengths and
//! [`film_r4x2`] at two cosines at once (eight lanes), for real indices — the fast path of the
//! BSDFs, which evaluate a film several times per path vertex.
//!
//! Where every lane's wave propagates in the film (or is totally reflected by the last medium,
//! R = 1: the media are lossless), the Airy sum of [`super::thinfilm`] reduces to real
//! amplitudes, R = (r01² + r12² + 2 r01 r12 cos 2δ) / (1 + r01² r12² + 2 r01 r12 cos 2δ)
//! (Born & Wolf, *Principles of Optics*, §7.6.1), and runs in lanes with one sine–cosine
//! polynomial for the phases ([`super::simd4`]); other cases (frustrated reflection: an
//! evanescent wave in the film with a propagating one beyond) take the complex path of
//! [`film_r`] lane by lane. Computed in f64, as the scalar path is; the lane code performs the
//! same operations per lane (Rust forms no fused multiply-adds), so each build the dispatchers
//! choose at run time (AVX-512, AVX2, baseline) gives the same bits (tested).

use super::simd4::F4;
use super::thinfilm::{airy_real, film_r};
use num_complex::Complex64 as C;

/// [`film_r`] at four wavelengths at once (a BSDF's hero wavelengths), for real indices: the
/// outside `n0`, the film `n1` and the base `n2`, lane by lane. Where every lane propagates
/// in the film, or is totally reflected by the last medium (R = 1), the Airy sum runs in four
/// lanes with one [`sincos4`](super::simd4::sincos4) for the phases; it agrees with `film_r`
/// to a few ulp (the cosine's rounding; tested). Other cases (an evanescent wave in the film
/// with a propagating one beyond it: frustrated reflection) take `film_r` lane by lane.
pub(crate) fn film_r4(cos_theta0: f64, n0: F4, n1: F4, d_nm: f64, n2: F4, lambda_nm: F4) -> F4 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above), the only requirement of
        // `film_r4_avx2`.
        return unsafe { film_r4_avx2(cos_theta0, n0, n1, d_nm, n2, lambda_nm) };
    }
    film_r4_lanes(cos_theta0, n0, n1, d_nm, n2, lambda_nm)
}

/// [`film_r4`] compiled for AVX2: the same operations, four lanes per instruction instead of
/// two. No fused multiply-adds are formed (Rust never contracts), so the results are bit for
/// bit those of the baseline build.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn film_r4_avx2(cos_theta0: f64, n0: F4, n1: F4, d_nm: f64, n2: F4, lambda_nm: F4) -> F4 {
    film_r4_lanes(cos_theta0, n0, n1, d_nm, n2, lambda_nm)
}

#[inline(always)]
fn film_r4_lanes(cos_theta0: f64, n0: F4, n1: F4, d_nm: f64, n2: F4, lambda_nm: F4) -> F4 {
    match film_r_lanes([cos_theta0; 4], n0, n1, d_nm, n2, lambda_nm) {
        Some(r) => r,
        None => film_r4_each(cos_theta0, n0, n1, d_nm, n2, lambda_nm),
    }
}

/// [`film_r`] lane by lane: [`film_r4`]'s answer where some lane is not the real case.
fn film_r4_each(cos_theta0: f64, n0: F4, n1: F4, d_nm: f64, n2: F4, lambda_nm: F4) -> F4 {
    let re = |x: f64| C::new(x, 0.0);
    let mut r = [0.0; 4];
    for i in 0..4 {
        r[i] = film_r(cos_theta0, n0[i], re(n1[i]), d_nm, re(n2[i]), lambda_nm[i]);
    }
    r
}

/// A film with real indices at a path's four wavelengths: the media before (`n0`) and after
/// (`n2`) it as light meets them, the film's index `n1` and thickness, and the wavelengths.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RealFilm {
    pub n0: F4,
    pub n1: F4,
    pub d_nm: f64,
    pub n2: F4,
    pub lambda_nm: F4,
}

/// [`film_r4`] at two cosines at once, `cos_a` and `cos_b`, for the same film and wavelengths:
/// `(film_r4(cos_a, …), film_r4(cos_b, …))` bit for bit (tested). The eight lanes run as one
/// chain of operations, so the two Airy sums' divisions and polynomials overlap instead of
/// following one another (a BSDF asks for pairs: the coat's transmittance at a direction and
/// its reflectance at the microfacet between it and the viewer).
pub(crate) fn film_r4x2(cos_a: f64, cos_b: f64, f: &RealFilm) -> (F4, F4) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU supports AVX-512F (checked just above), the only requirement.
            return unsafe { film_r4x2_avx512(cos_a, cos_b, f) };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2 (checked just above), the only requirement.
            return unsafe { film_r4x2_avx2(cos_a, cos_b, f) };
        }
    }
    film_r4x2_lanes(cos_a, cos_b, f)
}

/// [`film_r4x2`] compiled for an instruction set: AVX-512 holds the eight lanes in one
/// register, AVX2 in two.
macro_rules! film_r4x2_for {
    ($($name:ident: $feature:literal),*) => {$(
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        unsafe fn $name(cos_a: f64, cos_b: f64, f: &RealFilm) -> (F4, F4) {
            film_r4x2_lanes(cos_a, cos_b, f)
        }
    )*};
}
film_r4x2_for!(film_r4x2_avx512: "avx512f", film_r4x2_avx2: "avx2");

#[inline(always)]
fn film_r4x2_lanes(cos_a: f64, cos_b: f64, f: &RealFilm) -> (F4, F4) {
    let RealFilm {
        n0,
        n1,
        d_nm,
        n2,
        lambda_nm,
    } = *f;
    // Written with loops, not `array::from_fn`/`map`, which are not inlined into
    // `#[target_feature]` functions.
    let (mut cos, mut m0, mut m1, mut m2, mut l) =
        ([0.0; 8], [0.0; 8], [0.0; 8], [0.0; 8], [0.0; 8]);
    for i in 0..8 {
        cos[i] = if i < 4 { cos_a } else { cos_b };
        m0[i] = n0[i % 4];
        m1[i] = n1[i % 4];
        m2[i] = n2[i % 4];
        l[i] = lambda_nm[i % 4];
    }
    match film_r_lanes(cos, m0, m1, d_nm, m2, l) {
        Some(r) => ([r[0], r[1], r[2], r[3]], [r[4], r[5], r[6], r[7]]),
        None => (
            film_r4_lanes(cos_a, n0, n1, d_nm, n2, lambda_nm),
            film_r4_lanes(cos_b, n0, n1, d_nm, n2, lambda_nm),
        ),
    }
}

/// The Airy reflectance of every lane in real arithmetic, each at its own cosine, with one
/// [`sincos_lanes`](super::simd4::sincos_lanes) for the phases; `None` unless every lane is
/// the real case (light from above, positive indices, and a propagating wave in the film or
/// total reflection at the last medium).
#[inline(always)]
fn film_r_lanes<const L: usize>(
    cos_theta0: [f64; L],
    n0: [f64; L],
    n1: [f64; L],
    d_nm: f64,
    n2: [f64; L],
    lambda_nm: [f64; L],
) -> Option<[f64; L]> {
    let mut cos0 = [0.0; L];
    let mut c1 = [0.0; L];
    let mut c2 = [0.0; L];
    let mut c2sq = [0.0; L];
    let mut phase = [0.0; L];
    // A film of zero thickness takes this path too where the film's cosine is real: its phase
    // is 0, and the Airy sum with cos 2δ = 1 is the bare n0 | n2 interface (r02 = (r01 + r12)
    // / (1 + r01 r12)), to rounding. (The complex fallback, lane by lane, took half the render
    // time of a thin-film sphere with `film_thickness` = 0.)
    //
    // A lane whose wave cannot propagate in the last medium (cos² θ2 ≤ 0: total internal
    // reflection at the stack) reflects everything, R = 1: the media are lossless and an
    // evanescent wave carries no flux away, whatever the film does (frustrated reflection
    // needs a propagating medium beyond the film). The complex path, lane by lane, found the
    // same to ~1e-16 at several times the cost: it was 3 % of the flagship's render, whose
    // layered walk meets the film from inside the coat beyond the critical angle.
    let mut ok = true;
    for i in 0..L {
        cos0[i] = cos_theta0[i].min(1.0);
        let s2 = (n0[i] * n0[i]) * (1.0 - cos0[i] * cos0[i]);
        let c1sq = 1.0 - s2 / (n1[i] * n1[i]);
        c2sq[i] = 1.0 - s2 / (n2[i] * n2[i]);
        // Real cosines in the film, or total reflection at the last medium.
        let real = (c1sq > 0.0 && c2sq[i] > 0.0) || c2sq[i] <= 0.0;
        ok &= cos_theta0[i] > 0.0 && real && n1[i] > 0.0 && n2[i] > 0.0;
        c1[i] = c1sq.max(0.0).sqrt();
        c2[i] = c2sq[i].max(0.0).sqrt();
        phase[i] = 4.0 * std::f64::consts::PI * n1[i] * d_nm * c1[i] / lambda_nm[i];
    }
    if !ok {
        return None;
    }
    let (_, cos2d) = super::simd4::sincos_lanes(phase);
    let mut r = [0.0; L];
    for i in 0..L {
        let (r_s, r_p) = airy_real(n0[i], n1[i], n2[i], cos0[i], c1[i], c2[i], cos2d[i]);
        r[i] = if c2sq[i] > 0.0 {
            0.5 * (r_s + r_p)
        } else {
            1.0
        };
    }
    Some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn film_r4_is_the_same_with_and_without_avx2() {
        // The dispatcher takes the AVX2 build where the CPU has it; both builds run the same
        // operations (no contraction), so the baseline lanes must give the same bits.
        for (n0, n2) in [([1.0; 4], [1.5, 1.51, 1.52, 1.53]), ([1.45; 4], [1.0; 4])] {
            for d in [0.0, 330.0, 2000.0] {
                for k in 0..=40 {
                    let cos = k as f64 / 40.0;
                    let n1 = [1.56, 1.57, 1.58, 1.59];
                    let lambda = [380.0, 472.5, 601.25, 780.0];
                    let a = film_r4(cos, n0, n1, d, n2, lambda);
                    let b = film_r4_lanes(cos, n0, n1, d, n2, lambda);
                    assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "cos {cos}, d {d}");
                }
            }
        }
    }

    #[test]
    fn film_r4x2_is_two_film_r4_bit_for_bit_on_every_path() {
        // The pair's eight lanes run the four-lane path's operations, in whichever build the
        // dispatcher takes (AVX-512, AVX2, baseline); each is checked where the CPU has it, so
        // the fallbacks are exercised on any machine. Cosines include grazing, 0 and total
        // internal reflection (n0 = 1.45 over air), where one half falls back to `film_r`.
        let fine = |a: F4, b: F4| a.map(f64::to_bits) == b.map(f64::to_bits);
        type Pair = fn(f64, f64, &RealFilm) -> (F4, F4);
        let mut builds: Vec<(&str, Pair)> =
            vec![("dispatch", film_r4x2), ("lanes", film_r4x2_lanes)];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: AVX2 checked just above.
                builds.push(("avx2", |a, b, f| unsafe { film_r4x2_avx2(a, b, f) }));
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: AVX-512F checked just above.
                builds.push(("avx512", |a, b, f| unsafe { film_r4x2_avx512(a, b, f) }));
            }
        }
        let n1 = [1.56, 1.57, 1.58, 1.59];
        let lambda = [380.0, 472.5, 601.25, 780.0];
        for (n0, n2) in [([1.0; 4], [1.5, 1.51, 1.52, 1.53]), ([1.45; 4], [1.0; 4])] {
            for d in [0.0, 330.0, 2000.0] {
                for (ka, kb) in [(40, 3), (17, 0), (0, 0), (29, 31), (1, 40)] {
                    let (a, b) = (ka as f64 / 40.0, kb as f64 / 40.0);
                    let want = (
                        film_r4(a, n0, n1, d, n2, lambda),
                        film_r4(b, n0, n1, d, n2, lambda),
                    );
                    for (name, f) in &builds {
                        let film = RealFilm {
                            n0,
                            n1,
                            d_nm: d,
                            n2,
                            lambda_nm: lambda,
                        };
                        let got = f(a, b, &film);
                        assert!(
                            fine(got.0, want.0) && fine(got.1, want.1),
                            "{name}: cos {a}, {b}, d {d}: {got:?} vs {want:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn film_r4_agrees_with_film_r_lane_by_lane() {
        // Dispersive films and bases, both sides (n0 > n2 too, with total internal
        // reflection in some lanes), zero thickness, normal and grazing incidence.
        let mut worst = 0.0f64;
        let mut n = 0;
        for (n0, n1, n2) in [
            ([1.0; 4], [1.56, 1.57, 1.58, 1.59], [1.5, 1.51, 1.52, 1.53]),
            ([1.0; 4], [1.33; 4], [1.36; 4]),
            ([1.36, 1.37, 1.38, 1.39], [1.56; 4], [1.0; 4]),
            ([1.5; 4], [1.2, 1.3, 1.4, 1.6], [1.0; 4]),
        ] {
            for d in [0.0, 120.0, 330.0, 900.0, 20000.0] {
                for k in 0..=40 {
                    let cos = k as f64 / 40.0;
                    let lambda = [380.0, 472.5, 601.25, 780.0];
                    let r4 = film_r4(cos, n0, n1, d, n2, lambda);
                    for i in 0..4 {
                        let re = |x: f64| C::new(x, 0.0);
                        let r = film_r(cos, n0[i], re(n1[i]), d, re(n2[i]), lambda[i]);
                        let s2 = n0[i] * n0[i] * (1.0 - cos * cos);
                        if cos > 0.0 && s2 >= n2[i] * n2[i] {
                            // Total reflection at the last medium: exactly 1 in lanes; the
                            // complex path agrees but for its cancellation where the film's
                            // own cosine is 0 (n0 sin θ0 = n1: 1 − 1.2e-9 at cos 0.6 here).
                            assert_eq!(r4[i], 1.0, "cos {cos}, lane {i}, d {d}");
                            assert!((r - 1.0).abs() < 1e-8, "cos {cos}, lane {i}, d {d}: {r}");
                            n += 1;
                            continue;
                        }
                        worst = worst.max((r4[i] - r).abs());
                        n += 1;
                    }
                }
            }
        }
        // The phase of a 20 µm film is ~500 rad: its cosine differs from the C library's by a
        // few ulp of the argument, ~1e-13 in R.
        assert!(worst < 1e-12, "worst |ΔR| = {worst:e}");
        assert!(n > 3000);
    }
}
