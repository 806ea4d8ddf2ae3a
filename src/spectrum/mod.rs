//! Spectral quantities: four hero wavelengths per path (Wilkie et al. 2014, "Hero Wavelength
//! Spectral Sampling"), sampled with pbrt-v4's visible-importance density over 360–830 nm.

pub mod cie;
pub mod ior;
pub mod rgb2spec;
pub mod spectra;

pub use spectra::Spectrum;

use std::ops::{Add, AddAssign, Div, DivAssign, Index, IndexMut, Mul, MulAssign, Neg, Sub};

/// Number of wavelengths carried by each path.
pub const N: usize = 4;
/// Shortest wavelength rendered, nm.
pub const LAMBDA_MIN: f32 = 360.0;
/// Longest wavelength rendered, nm.
pub const LAMBDA_MAX: f32 = 830.0;

/// Values of a spectral quantity at the path's [`N`] wavelengths.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SampledSpectrum(pub [f32; N]);

impl SampledSpectrum {
    /// All components equal to `v`.
    #[inline]
    pub const fn splat(v: f32) -> Self {
        SampledSpectrum([v; N])
    }
    /// Zero.
    pub const ZERO: SampledSpectrum = SampledSpectrum([0.0; N]);
    /// One.
    pub const ONE: SampledSpectrum = SampledSpectrum([1.0; N]);

    /// Component-wise map.
    #[inline]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        SampledSpectrum(self.0.map(f))
    }
    /// Builds from a function of the component index.
    #[inline]
    pub fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
        SampledSpectrum(std::array::from_fn(f))
    }
    /// Largest component.
    #[inline]
    pub fn max_value(&self) -> f32 {
        self.0.iter().copied().fold(f32::NEG_INFINITY, f32::max)
    }
    /// Smallest component.
    #[inline]
    pub fn min_value(&self) -> f32 {
        self.0.iter().copied().fold(f32::INFINITY, f32::min)
    }
    /// Mean of the components.
    #[inline]
    pub fn average(&self) -> f32 {
        self.0.iter().sum::<f32>() / N as f32
    }
    /// Whether every component is zero.
    #[inline]
    pub fn is_black(&self) -> bool {
        self.0.iter().all(|&v| v == 0.0)
    }
    /// Whether every component is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|v| v.is_finite())
    }
    /// Component-wise exp.
    #[inline]
    pub fn exp(self) -> Self {
        self.map(f32::exp)
    }
    /// Component-wise sqrt (negative → 0).
    #[inline]
    pub fn sqrt(self) -> Self {
        self.map(|v| v.max(0.0).sqrt())
    }
    /// Component-wise clamp to [lo, hi].
    #[inline]
    pub fn clamp(self, lo: f32, hi: f32) -> Self {
        self.map(|v| v.clamp(lo, hi))
    }
}

macro_rules! binop {
    ($tr:ident, $f:ident, $atr:ident, $af:ident, $op:tt) => {
        impl $tr for SampledSpectrum {
            type Output = SampledSpectrum;
            #[inline]
            fn $f(self, r: SampledSpectrum) -> SampledSpectrum {
                SampledSpectrum(std::array::from_fn(|i| self.0[i] $op r.0[i]))
            }
        }
        impl $tr<f32> for SampledSpectrum {
            type Output = SampledSpectrum;
            #[inline]
            fn $f(self, r: f32) -> SampledSpectrum {
                SampledSpectrum(std::array::from_fn(|i| self.0[i] $op r))
            }
        }
        impl $atr for SampledSpectrum {
            #[inline]
            fn $af(&mut self, r: SampledSpectrum) {
                for i in 0..N {
                    self.0[i] = self.0[i] $op r.0[i];
                }
            }
        }
        impl $atr<f32> for SampledSpectrum {
            #[inline]
            fn $af(&mut self, r: f32) {
                for i in 0..N {
                    self.0[i] = self.0[i] $op r;
                }
            }
        }
    };
}
binop!(Add, add, AddAssign, add_assign, +);
binop!(Mul, mul, MulAssign, mul_assign, *);
binop!(Div, div, DivAssign, div_assign, /);

impl Sub for SampledSpectrum {
    type Output = SampledSpectrum;
    #[inline]
    fn sub(self, r: SampledSpectrum) -> SampledSpectrum {
        SampledSpectrum(std::array::from_fn(|i| self.0[i] - r.0[i]))
    }
}
impl Sub<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    #[inline]
    fn sub(self, r: SampledSpectrum) -> SampledSpectrum {
        SampledSpectrum(std::array::from_fn(|i| self - r.0[i]))
    }
}
impl Mul<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    #[inline]
    fn mul(self, r: SampledSpectrum) -> SampledSpectrum {
        r * self
    }
}
impl Neg for SampledSpectrum {
    type Output = SampledSpectrum;
    #[inline]
    fn neg(self) -> SampledSpectrum {
        self.map(|v| -v)
    }
}
impl Index<usize> for SampledSpectrum {
    type Output = f32;
    #[inline]
    fn index(&self, i: usize) -> &f32 {
        &self.0[i]
    }
}
impl IndexMut<usize> for SampledSpectrum {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut f32 {
        &mut self.0[i]
    }
}

/// The wavelengths (nm) a path carries and their sampling densities (1/nm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    pub lambda: [f32; N],
    pub pdf: [f32; N],
}

impl SampledWavelengths {
    /// Hero-wavelength sampling by visible importance: the hero is drawn from `u`, the others
    /// from `u + i/N` (mod 1), all through the same inverse CDF so each has the same density.
    pub fn sample_visible(u: f32) -> SampledWavelengths {
        let mut lambda = [0.0; N];
        let mut pdf = [0.0; N];
        for i in 0..N {
            let mut up = u + i as f32 / N as f32;
            if up >= 1.0 {
                up -= 1.0;
            }
            (lambda[i], pdf[i]) = sample_visible_wavelength_pdf(up);
        }
        SampledWavelengths { lambda, pdf }
    }

    /// Evenly spaced wavelengths with uniform density, starting at `u` within the first bin.
    pub fn sample_uniform(u: f32) -> SampledWavelengths {
        let delta = (LAMBDA_MAX - LAMBDA_MIN) / N as f32;
        let lambda = std::array::from_fn(|i| LAMBDA_MIN + (u + i as f32) * delta);
        SampledWavelengths {
            lambda,
            pdf: [1.0 / (LAMBDA_MAX - LAMBDA_MIN); N],
        }
    }

    /// Given wavelengths with unit density (for evaluating at chosen wavelengths, e.g. in tools).
    pub fn fixed(lambda: [f32; N]) -> SampledWavelengths {
        SampledWavelengths {
            lambda,
            pdf: [1.0; N],
        }
    }

    /// The hero wavelength.
    #[inline]
    pub fn hero(&self) -> f32 {
        self.lambda[0]
    }
}

// pbrt-v4's visible-wavelength density: p(λ) ∝ sech²(0.0072 (λ − 538)) on 360–830 nm.
const VIS_A: f32 = 0.0072;
const VIS_C: f32 = 538.0;

/// Density of [`sample_visible_wavelength`] (1/nm), 0 outside 360–830 nm.
pub fn visible_wavelength_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let norm = (VIS_A * (LAMBDA_MAX - VIS_C)).tanh() - (VIS_A * (LAMBDA_MIN - VIS_C)).tanh();
    VIS_A / norm / (VIS_A * (lambda - VIS_C)).cosh().powi(2)
}

/// Inverse CDF of the visible-wavelength density.
pub fn sample_visible_wavelength(u: f32) -> f32 {
    sample_visible_wavelength_pdf(u).0
}

/// Inverse CDF of the visible-wavelength density, with the density at the sample.
///
/// With t = tanh(a (λ − c)) uniform between its values at the ends, λ = c + atanh(t)/a and the
/// density is a (1 − t²)/(t1 − t0): no hyperbolic function needs evaluating besides atanh.
#[inline]
pub fn sample_visible_wavelength_pdf(u: f32) -> (f32, f32) {
    let (l, pdf) = sample_visible_wavelength_lanes(u);
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&l) {
        let l = l.clamp(LAMBDA_MIN, LAMBDA_MAX);
        return (l, visible_wavelength_pdf(l));
    }
    (l, pdf)
}

// tanh(0.0072 (360 − 538)) and tanh(0.0072 (830 − 538)), precomputed in f64.
const T0: f32 = -0.856_910_6;
const T1: f32 = 0.970_591_35;

/// [`sample_visible_wavelength_pdf`] on lanes, without the clamp of the rare results that
/// rounding puts outside 360–830 nm (the caller checks them).
#[inline(always)]
pub fn sample_visible_wavelength_lanes<F: crate::simd::Float>(u: F) -> (F, F) {
    let one = F::splat(1.0);
    let t = F::splat(T0) + u * F::splat(T1 - T0);
    let l = F::splat(VIS_C)
        + F::splat(0.5) * crate::simd::fastmath::ln((one + t) / (one - t)) / F::splat(VIS_A);
    (l, F::splat(VIS_A) * (one - t * t) / F::splat(T1 - T0))
}

#[cfg(test)]
mod tests {
    use super::*;
    const ONE_BELOW: f32 = crate::math::ONE_MINUS_EPSILON;

    #[test]
    fn fast_sampling_matches_the_density() {
        // The endpoints map to 360 and 830 nm (checks the precomputed tanh constants), and the
        // density from t equals the sech² formula.
        assert!((sample_visible_wavelength_pdf(0.0).0 - LAMBDA_MIN).abs() < 0.05);
        assert!((sample_visible_wavelength_pdf(ONE_BELOW).0 - LAMBDA_MAX).abs() < 0.05);
        for &u in &[0.01f32, 0.3, 0.7, 0.99] {
            let (l, p) = sample_visible_wavelength_pdf(u);
            assert!(
                (p - visible_wavelength_pdf(l)).abs() < 1e-4 * p,
                "{u}: {p} vs {}",
                visible_wavelength_pdf(l)
            );
        }
    }

    #[test]
    fn visible_pdf_integrates_to_one_and_inverts() {
        let n = 47_000;
        let h = (LAMBDA_MAX - LAMBDA_MIN) / n as f32;
        let s: f32 = (0..n)
            .map(|i| visible_wavelength_pdf(LAMBDA_MIN + (i as f32 + 0.5) * h) * h)
            .sum();
        assert!((s - 1.0).abs() < 1e-3, "{s}");
        // CDF(sample(u)) = u, checked by integrating the pdf up to the sample.
        for &u in &[0.1f32, 0.5, 0.9] {
            let l = sample_visible_wavelength(u);
            let m = 20_000;
            let hh = (l - LAMBDA_MIN) / m as f32;
            let c: f32 = (0..m)
                .map(|i| visible_wavelength_pdf(LAMBDA_MIN + (i as f32 + 0.5) * hh) * hh)
                .sum();
            assert!((c - u).abs() < 1e-3, "u {u} cdf {c}");
        }
    }
}
