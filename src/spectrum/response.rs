//! The density the hero wavelengths are drawn from: proportional to |r̄| + |ḡ| + |b̄|, the
//! absolute linear-sRGB colour-matching functions (the CIE 1931 x̄, ȳ, z̄ through the
//! XYZ → sRGB matrix), tabulated piecewise constant on 1 nm bins over 360–830 nm.
//!
//! Why this density: a pixel's colour is ∫ L(λ) (r̄, ḡ, b̄)(λ) dλ estimated from the path's
//! wavelengths, so the noise of each channel depends on how well the density follows that
//! channel's curve. pbrt-v4's visible density (sech², centred on 538 nm; ophis's until
//! 2026-12) follows ȳ and leaves the blue channel, whose z̄ peaks at 445 nm, undersampled:
//! for a D65-white sky seen directly through four hero wavelengths the per-sample relative
//! variance is 0.017 / 0.0009 / 0.33 in R / G / B (measured in ophis and by simulation);
//! with this density it is 0.055 / 0.024 / 0.027, a third of the sum. Among the densities
//! tried in that simulation (x̄ + ȳ + z̄, D65-weighted versions, √(r̄² + ḡ² + b̄²),
//! max(|r̄|, |ḡ|, |b̄|)) this one gave the lowest total, with one and with several samples per
//! pixel. The idea of sampling by the colour-matching functions rather than by luminance is
//! Radziszewski, Boryczko & Alda 2009, "An improved technique for full spectral rendering"
//! (JWSCG 17).
//!
//! Every rendered channel stays unbiased: the density is positive over all of 360–830 nm
//! (|r̄| + |ḡ| + |b̄| ≥ ‖XYZ_TO_SRGB⁻¹‖⁻¹ (x̄ + ȳ + z̄) > 0 on the table), so x̄/p, ȳ/p,
//! z̄/p stay bounded.
//!
//! Sampling: the density's inverse CDF, tabulated at [`CELLS`] equally likely cells (the
//! wavelengths λ_j where the CDF of the 1 nm histogram reaches j / CELLS, in f64), is
//! interpolated linearly in u. That makes the sampled density piecewise constant per cell,
//! 1 / (CELLS (λ_{j+1} − λ_j)), which is the density returned (so every estimate stays exactly
//! unbiased) and follows the 1 nm histogram to within a cell's width; sampling is one table
//! read, with no search, cheap enough to draw four wavelengths for every path.

use super::cie::{srgb_bar_node, NODES};
use super::{LAMBDA_MAX, LAMBDA_MIN};
use std::sync::OnceLock;

/// Bins of the histogram: one per nm.
const BINS: usize = NODES - 1;
/// Equally likely cells of the sampling table.
const CELLS: usize = 4096;

struct Table {
    /// λ_j (nm) at the cell edges: lambda[0] = 360, lambda[CELLS] = 830.
    lambda: [f32; CELLS + 1],
    /// Width λ_{j+1} − λ_j of each cell (nm), as f32 arithmetic gives it.
    width: [f32; CELLS],
    /// Density in each cell: 1 / (CELLS · width).
    pdf: [f32; CELLS],
}

fn table() -> &'static Table {
    static T: OnceLock<Box<Table>> = OnceLock::new();
    T.get_or_init(|| {
        let w = |k: usize| srgb_bar_node(k).iter().map(|v| v.abs() as f64).sum::<f64>();
        // Bin weight: the trapezoid of the curve over the bin.
        let weights: Vec<f64> = (0..BINS).map(|k| 0.5 * (w(k) + w(k + 1))).collect();
        let total: f64 = weights.iter().sum();
        let mut cdf = vec![0.0f64; BINS + 1];
        for k in 0..BINS {
            cdf[k + 1] = cdf[k] + weights[k] / total;
        }
        let mut t = Box::new(Table {
            lambda: [0.0; CELLS + 1],
            width: [0.0; CELLS],
            pdf: [0.0; CELLS],
        });
        let mut k = 0;
        for j in 0..=CELLS {
            let u = j as f64 / CELLS as f64;
            while k + 1 < BINS && cdf[k + 1] <= u {
                k += 1;
            }
            let f = ((u - cdf[k]) / (cdf[k + 1] - cdf[k])).clamp(0.0, 1.0);
            t.lambda[j] = (LAMBDA_MIN as f64 + k as f64 + f) as f32;
        }
        t.lambda[0] = LAMBDA_MIN;
        t.lambda[CELLS] = LAMBDA_MAX;
        for j in 0..CELLS {
            t.width[j] = t.lambda[j + 1] - t.lambda[j];
            t.pdf[j] = 1.0 / (CELLS as f32 * t.width[j]);
        }
        t
    })
}

/// A wavelength (nm) for `u` in [0, 1) and its density (1/nm).
#[inline]
pub fn sample_response_wavelength(u: f32) -> (f32, f32) {
    sample_in(table(), u)
}

/// The hero wavelengths for `u`: the i-th from `u + i/N` (mod 1), with their densities (the
/// table fetched once for all of them).
#[inline]
pub(crate) fn sample_hero(u: f32) -> ([f32; super::N], [f32; super::N]) {
    let t = table();
    let mut lambda = [0.0; super::N];
    let mut pdf = [0.0; super::N];
    for i in 0..super::N {
        let up = u + i as f32 / super::N as f32;
        let up = if up >= 1.0 { up - 1.0 } else { up };
        (lambda[i], pdf[i]) = sample_in(t, up);
    }
    (lambda, pdf)
}

#[inline(always)]
fn sample_in(t: &Table, u: f32) -> (f32, f32) {
    let x = u.clamp(0.0, 1.0) * CELLS as f32;
    let j = (x as usize).min(CELLS - 1);
    let f = x - j as f32;
    ((t.lambda[j] + f * t.width[j]).min(LAMBDA_MAX), t.pdf[j])
}

/// [`sample_response_wavelength`] on lanes, the same operations in the same order (so the
/// same bits): `u` in [0, 1).
#[inline(always)]
pub(crate) fn sample_lanes<F: crate::simd::Float>(u: F) -> (F, F) {
    use crate::simd::Int;
    let t = table();
    let x = u.clamp(0.0, 1.0) * F::splat(CELLS as f32);
    let last = F::I::splat(CELLS as i32 - 1);
    let j = x.to_int();
    let j = F::I::select(j.gt(last), last, j);
    let f = x - F::from_int(j);
    let l = F::gather(&t.lambda, j) + f * F::gather(&t.width, j);
    (l.min(F::splat(LAMBDA_MAX)), F::gather(&t.pdf, j))
}

/// The density (1/nm) of [`sample_response_wavelength`] at `lambda`; 0 outside 360–830 nm.
pub fn response_wavelength_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let t = table();
    let j = t.lambda.partition_point(|&l| l <= lambda).clamp(1, CELLS) - 1;
    t.pdf[j]
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
        assert!(t.pdf.iter().all(|&p| p > 0.0 && p.is_finite()));
        let sum: f64 = (0..CELLS).map(|j| (t.pdf[j] * t.width[j]) as f64).sum();
        assert!((sum - 1.0).abs() < 1e-5, "{sum}");
        // CDF(sample(u)) = u: the sample's cell and position within it; the density found
        // at the sample is the one returned.
        for i in 0..=1000 {
            let u = (i as f32 / 1000.0).min(crate::math::ONE_MINUS_EPSILON);
            let (l, p) = sample_response_wavelength(u);
            assert!((LAMBDA_MIN..=LAMBDA_MAX).contains(&l), "u {u}: {l}");
            let j = t.lambda.partition_point(|&x| x <= l).clamp(1, CELLS) - 1;
            let c = j as f32 / CELLS as f32 + (l - t.lambda[j]) * t.pdf[j];
            assert!((c - u).abs() < 2e-5, "u {u}: λ {l}, cdf {c}");
            assert_eq!(p, response_wavelength_pdf(l), "u {u}: λ {l}");
        }
        // The cells follow the 1 nm histogram of |r̄| + |ḡ| + |b̄|: at 450, 550 and 600 nm
        // the density is the curve's over its integral to within 2 %.
        let curve = |l: usize| -> f64 {
            let k = l - LAMBDA_MIN as usize;
            srgb_bar_node(k).iter().map(|v| v.abs() as f64).sum()
        };
        let total: f64 = (0..BINS)
            .map(|k| 0.5 * (curve(360 + k) + curve(361 + k)))
            .sum();
        for l in [450usize, 550, 600] {
            let want = curve(l) / total;
            let got = response_wavelength_pdf(l as f32 + 0.5) as f64;
            assert!((got - want).abs() < 0.02 * want, "{l} nm: {got} vs {want}");
        }
    }

    /// Per-sample relative variance of the linear-sRGB channels of a D65-white emitter seen
    /// through four hero wavelengths, with independent u (`n` samples).
    fn white_relative_variance(n: usize) -> [f64; 3] {
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
        std::array::from_fn(|c| {
            let m = s[c] / n as f64;
            (s2[c] / n as f64 - m * m) / (m * m)
        })
    }

    #[test]
    fn white_is_white_with_low_colour_noise() {
        // Unbiased: the mean is rgb (1, 1, 1) (D65 is sRGB's white); the standard error of
        // each mean is √(relative variance / n) ≤ 0.0011 here.
        let n = 200_000;
        let rv = white_relative_variance(n);
        // The module doc's figures (0.055 / 0.024 / 0.027, a total of 0.106): each channel
        // must stay below 0.07, and the blue one far below the sech² density's 0.33.
        for (c, &v) in rv.iter().enumerate() {
            assert!(v < 0.07, "channel {c}: relative variance {v}");
        }
        let mut rng = Pcg32::new(6, 6);
        let mut mean = [0.0f64; 3];
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
                mean[c] += rgb[c] as f64 / crate::spectrum::cie::CIE_Y_INTEGRAL as f64 / n as f64;
            }
        }
        for (c, &m) in mean.iter().enumerate() {
            let se = (rv[c] / n as f64).sqrt();
            assert!(
                (m - 1.0).abs() < 4.0 * se + 2e-4,
                "channel {c}: mean {m} (se {se})"
            );
        }
    }
}
