//! The density the hero wavelengths are drawn from: proportional to |r̄| + |ḡ| + |b̄|, the
//! absolute linear-sRGB colour-matching functions (the CIE 1931 x̄, ȳ, z̄ through the
//! XYZ → sRGB matrix), tabulated piecewise constant on 1 nm bins over 360–830 nm.
//!
//! Why this density: a pixel's colour is ∫ L(λ) (r̄, ḡ, b̄)(λ) dλ estimated from the path's
//! wavelengths, so the noise of each channel depends on how well the density follows that
//! channel's curve. pbrt-v4's visible density (sech², centred on 538 nm; ophis's until
//! 2026-12) follows ȳ and leaves the blue channel, whose z̄ peaks at 445 nm, undersampled:
//! for a D65-white sky seen directly through four hero wavelengths the per-sample relative
//! variance is 0.017 / 0.0009 / 0.33 in R / G / B (by simulation; ophis measured 0.023 / 0.0009 /
//! 0.33); with this density it is 0.055 / 0.024 / 0.027 (ophis: 0.060 / 0.027 / 0.020), a third
//! of the sum. Among the densities
//! tried in that simulation (x̄ + ȳ + z̄, D65-weighted versions, √(r̄² + ḡ² + b̄²),
//! max(|r̄|, |ḡ|, |b̄|)) this one gave the lowest total, with one and with several samples per
//! pixel. The idea of sampling by the colour-matching functions rather than by luminance is
//! Radziszewski, Boryczko & Alda 2009, "An improved technique for full spectral rendering"
//! (JWSCG 17).
//!
//! Every rendered channel stays unbiased: the density is positive over all of 360–830 nm
//! (|r̄| + |ḡ| + |b̄| ≥ (x̄ + ȳ + z̄) / ‖XYZ_TO_SRGB⁻¹‖₁ > 0 on the table, ‖·‖₁ the largest
//! column sum), so x̄/p, ȳ/p,
//! z̄/p stay bounded.
//!
//! Sampling inverts the tabulated CDF exactly: a branch-free binary search (nine halving steps
//! over the 470 bins) finds the bin, and within it the wavelength is linear in u. In SIMD
//! lanes, where each step is a gather, a guide table first narrows the search: u in
//! [j/G, (j+1)/G) lies in a bin between `guide[j]` and `guide[j + 1]` (the last bins whose
//! CDF is ≤ j/G and ≤ (j+1)/G), and the halving steps start from the width of that range:
//! none in 86 % of the 2048 buckets, one in 13 %, so a chunk of lanes takes one or two instead
//! of nine. Both searches find the same bin (the last with cdf ≤ u), so the lanes give the
//! scalar code's bits. (Equally likely cells read without a search were tried: their density
//! jumps at 4096 cell edges instead of 470 bin edges, and at hundreds of samples per pixel
//! that broke the Sobol sampler's convergence in the red channel,
//! the relative variance of a white sky's red channel 13× worse at 256 spp.)

use super::cie::{srgb_bar_node, NODES};
use super::{LAMBDA_MAX, LAMBDA_MIN};
use std::sync::OnceLock;

/// Bins: one per nm.
const BINS: usize = NODES - 1;
/// The binary search's first step: the largest power of two below [`BINS`].
const TOP_STEP: usize = 256;
/// Buckets of u in the guide table (a power of two, so that u · GUIDE is exact).
const GUIDE: usize = 2048;

struct Table {
    /// CDF at the bin edges: cdf[0] = 0, cdf[BINS] = 1.
    cdf: [f32; BINS + 1],
    /// Density (1/nm) in each bin.
    pdf: [f32; BINS],
    /// `guide[j]`: the last bin k (< BINS) with cdf[k] ≤ j / GUIDE.
    guide: [u32; GUIDE + 1],
}

fn table() -> &'static Table {
    static T: OnceLock<Box<Table>> = OnceLock::new();
    T.get_or_init(|| {
        let w = |k: usize| srgb_bar_node(k).iter().map(|v| v.abs() as f64).sum::<f64>();
        // Bin weight: the trapezoid of the curve over the bin.
        let weights: Vec<f64> = (0..BINS).map(|k| 0.5 * (w(k) + w(k + 1))).collect();
        let total: f64 = weights.iter().sum();
        let mut t = Box::new(Table {
            cdf: [0.0; BINS + 1],
            pdf: [0.0; BINS],
            guide: [0; GUIDE + 1],
        });
        let mut acc = 0.0f64;
        for (k, &wk) in weights.iter().enumerate() {
            t.pdf[k] = (wk / total) as f32;
            acc += wk;
            t.cdf[k + 1] = (acc / total) as f32;
        }
        t.cdf[BINS] = 1.0;
        let mut k = 0;
        for (j, g) in t.guide.iter_mut().enumerate() {
            let x = j as f32 / GUIDE as f32;
            while k + 1 < BINS && t.cdf[k + 1] <= x {
                k += 1;
            }
            *g = k as u32;
        }
        t
    })
}

/// A wavelength (nm) for `u` in [0, 1) and its density (1/nm).
#[inline]
pub fn sample_response_wavelength(u: f32) -> (f32, f32) {
    sample_in(table(), u)
}

/// Where in the response's CDF the i-th of the path's wavelengths lies for `u`: (u + i)/N.
///
/// The N positions are evenly spaced, each in its own 1/N of the CDF, offset together by u/N;
/// so each wavelength, and the set, has the density of the response (the estimator is the
/// same as with u + i/N mod 1, which makes the same sets). The offset takes u's leading
/// digits, not its trailing ones (u + i/N mod 1 offsets the set by u mod 1/N): with
/// low-discrepancy samples, n samples of a pixel, whose leading digits are stratified first,
/// then spread the pixel's n·N wavelengths over n·N strata instead of repeating the N strata
/// each sample already covers (a white sky at 4 spp: Sobol gained nothing over independent
/// samples before).
#[inline(always)]
pub(crate) fn hero_position(u: f32, i: usize) -> f32 {
    (u + i as f32) * (1.0 / super::N as f32)
}

/// The hero wavelengths for `u`: the i-th at [`hero_position`], with their densities (the
/// table fetched once for all of them).
#[inline]
pub(crate) fn sample_hero(u: f32) -> ([f32; super::N], [f32; super::N]) {
    let t = table();
    let mut lambda = [0.0; super::N];
    let mut pdf = [0.0; super::N];
    for i in 0..super::N {
        (lambda[i], pdf[i]) = sample_in(t, hero_position(u, i));
    }
    (lambda, pdf)
}

#[inline(always)]
fn sample_in(t: &Table, u: f32) -> (f32, f32) {
    let u = u.clamp(0.0, super::super::math::ONE_MINUS_EPSILON);
    // The last bin k with cdf[k] ≤ u (cdf[0] = 0 ≤ u).
    let mut k = 0usize;
    let mut step = TOP_STEP;
    while step > 0 {
        let probe = (k + step).min(BINS - 1);
        if t.cdf[probe] <= u {
            k = probe;
        }
        step /= 2;
    }
    let (c0, c1) = (t.cdf[k], t.cdf[k + 1]);
    let f = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
    let lambda = (LAMBDA_MIN + k as f32 + f.clamp(0.0, 1.0)).min(LAMBDA_MAX);
    (lambda, t.pdf[k])
}

/// [`sample_response_wavelength`] on lanes, the same bin (by the guided search of the module
/// notes) and then the same operations in the same order (so the same bits): `u` in [0, 1).
#[inline(always)]
pub(crate) fn sample_lanes<F: crate::simd::Float>(u: F) -> (F, F) {
    use crate::simd::{Int, Mask};
    let t = table();
    let u = u.clamp(0.0, super::super::math::ONE_MINUS_EPSILON);
    // u < 1, so j ≤ GUIDE − 1; j / GUIDE ≤ u < (j + 1) / GUIDE exactly (a power of two).
    let j = (u * F::splat(GUIDE as f32)).to_int();
    let lo = F::I::gather(&t.guide, j);
    let hi = F::I::gather(&t.guide, j + F::I::splat(1));
    // The bin is in [lo, hi]: halving steps from the largest power of two ≤ hi − lo (its
    // float's exponent bits alone; 0 for an empty range) reach every bin up to lo + 2·step − 1.
    let span = F::from_int(hi - lo).to_bits() & F::I::splat(0x7f80_0000);
    let mut step = F::from_bits(span).to_int();
    let (zero, last) = (F::I::splat(0), F::I::splat(BINS as i32 - 1));
    let mut k = lo;
    while step.gt(zero).any() {
        let probe = k + step;
        let probe = F::I::select(probe.gt(last), last, probe);
        k = F::I::select(F::gather(&t.cdf, probe).le(u), probe, k);
        step = step.shr::<1>();
    }
    let c0 = F::gather(&t.cdf, k);
    let c1 = F::gather(&t.cdf, k + F::I::splat(1));
    let f = F::select(c1.gt(c0), (u - c0) / (c1 - c0), F::splat(0.5));
    let lambda =
        (F::splat(LAMBDA_MIN) + F::from_int(k) + f.clamp(0.0, 1.0)).min(F::splat(LAMBDA_MAX));
    (lambda, F::gather(&t.pdf, k))
}

/// The density (1/nm) of [`sample_response_wavelength`] at `lambda`; 0 outside 360–830 nm.
pub fn response_wavelength_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let k = ((lambda - LAMBDA_MIN) as usize).min(BINS - 1);
    table().pdf[k]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;
    use crate::spectrum::cie::{d65, xyz_bar, xyz_to_linear_srgb};
    use crate::spectrum::SampledWavelengths;

    #[test]
    fn density_is_positive_normalised_and_inverted() {
        let t = table();
        assert!(t.pdf.iter().all(|&p| p > 0.0));
        let sum: f64 = t.pdf.iter().map(|&p| p as f64).sum();
        assert!((sum - 1.0).abs() < 1e-5, "{sum}");
        // CDF(sample(u)) = u: the sample's bin and position within it.
        for i in 0..=1000 {
            let u = (i as f32 / 1000.0).min(crate::math::ONE_MINUS_EPSILON);
            let (l, p) = sample_response_wavelength(u);
            assert!((LAMBDA_MIN..=LAMBDA_MAX).contains(&l), "u {u}: {l}");
            assert_eq!(
                p,
                response_wavelength_pdf(l.min(LAMBDA_MAX - 1e-3)),
                "u {u}: λ {l}"
            );
            let k = ((l - LAMBDA_MIN) as usize).min(BINS - 1);
            let c = t.cdf[k] + (l - LAMBDA_MIN - k as f32) * t.pdf[k];
            assert!((c - u).abs() < 2e-5, "u {u}: λ {l}, cdf {c}");
        }
    }

    /// The lanes' guided search against the scalar binary search, bit for bit, at u on every
    /// guide bucket's edge and just beside it, on every bin's CDF value and beside it, and at
    /// random; also that the guide bounds the bin as the module notes say.
    fn lanes_match_scalar<F: crate::simd::Float>() {
        let t = table();
        let mut us = vec![0.0f32, crate::math::ONE_MINUS_EPSILON, 1.0, -0.5, 1.5];
        let beside = |x: f32| {
            [
                x,
                f32::from_bits(x.to_bits().saturating_sub(1)),
                x.next_up(),
            ]
        };
        for j in 0..=GUIDE {
            us.extend(beside(j as f32 / GUIDE as f32));
        }
        for &c in &t.cdf {
            us.extend(beside(c));
        }
        let mut rng = Pcg32::new(7, 9);
        us.extend((0..4096).map(|_| rng.next_f32()));
        for chunk in us.chunks(F::LANES) {
            let u = F::from_fn(|i| chunk[i % chunk.len()]);
            let (l, p) = sample_lanes(u);
            for (i, &x) in chunk.iter().enumerate() {
                let (ls, ps) = sample_response_wavelength(x);
                assert_eq!(
                    (l.lane(i).to_bits(), p.lane(i).to_bits()),
                    (ls.to_bits(), ps.to_bits()),
                    "u {x}"
                );
            }
        }
        for j in 0..GUIDE {
            let (lo, hi) = (t.guide[j] as usize, t.guide[j + 1] as usize);
            assert!(lo <= hi && hi < BINS && t.cdf[lo] <= j as f32 / GUIDE as f32);
        }
    }

    #[test]
    fn guided_search_in_lanes_finds_the_scalar_bin() {
        lanes_match_scalar::<f32>();
        #[cfg(target_arch = "x86_64")]
        {
            if is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma") {
                #[target_feature(enable = "avx2,fma")]
                fn avx2() {
                    lanes_match_scalar::<crate::simd::F8>();
                }
                // SAFETY: the features were detected above.
                unsafe { avx2() }
            }
            if crate::accel::Isa::Avx512.supported() {
                #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma")]
                fn avx512() {
                    lanes_match_scalar::<crate::simd::F16>();
                }
                // SAFETY: the features were detected above.
                unsafe { avx512() }
            }
        }
    }

    /// Mean and per-sample relative variance of the linear-sRGB channels (in units of white)
    /// of a D65-white emitter seen through four hero wavelengths, from `n` independent u.
    fn white_stats(n: usize) -> ([f64; 3], [f64; 3]) {
        let mut rng = Pcg32::new(5, 5);
        let (mut s, mut s2) = ([0.0f64; 3], [0.0f64; 3]);
        for _ in 0..n {
            let wl = SampledWavelengths::sample_visible(rng.next_f32());
            let mut xyz = [0.0f32; 3];
            for j in 0..4 {
                let b = xyz_bar(wl.lambda[j]);
                for c in 0..3 {
                    xyz[c] += d65(wl.lambda[j]) * b[c] / wl.pdf[j] / 4.0;
                }
            }
            let rgb = xyz_to_linear_srgb(xyz);
            for c in 0..3 {
                let v = rgb[c] as f64 / crate::spectrum::cie::CIE_Y_INTEGRAL as f64;
                s[c] += v;
                s2[c] += v * v;
            }
        }
        let mean: [f64; 3] = std::array::from_fn(|c| s[c] / n as f64);
        let rv = std::array::from_fn(|c| (s2[c] / n as f64 - mean[c] * mean[c]) / mean[c].powi(2));
        (mean, rv)
    }

    #[test]
    fn white_is_white_with_low_colour_noise() {
        let n = 200_000;
        let (mean, rv) = white_stats(n);
        // The module doc's figures (0.055 / 0.024 / 0.027 by simulation): each channel must
        // stay below 0.07, the blue one far below the sech² density's 0.33.
        for (c, &v) in rv.iter().enumerate() {
            assert!(v < 0.07, "channel {c}: relative variance {v}");
        }
        // Unbiased: the mean is rgb (1, 1, 1) (D65 is sRGB's white) within 4 standard errors,
        // √(relative variance / n) ≤ 6e-4 here.
        for (c, &m) in mean.iter().enumerate() {
            let se = (rv[c] / n as f64).sqrt();
            assert!(
                (m - 1.0).abs() < 4.0 * se,
                "channel {c}: mean {m} (se {se})"
            );
        }
    }

    #[test]
    fn stratified_samples_give_stratified_wavelength_sets() {
        // n samples stratified in u (one per 1/n, as a low-discrepancy sampler's first n are)
        // must put the n·N wavelengths' CDF positions one in each of n·N strata; with
        // u + i/N mod 1 every one of 4 samples covered the same 4 strata of 16.
        for n in [1usize, 2, 4, 8, 16] {
            let strata = n * crate::spectrum::N;
            let mut hit = vec![0u32; strata];
            for k in 0..n {
                let u = (k as f32 + 0.37) / n as f32;
                for i in 0..crate::spectrum::N {
                    let x = hero_position(u, i);
                    assert!((0.0..1.0).contains(&x), "position {x}");
                    hit[(x * strata as f32) as usize] += 1;
                }
            }
            assert!(hit.iter().all(|&h| h == 1), "{n} samples: {hit:?}");
        }
    }
}
