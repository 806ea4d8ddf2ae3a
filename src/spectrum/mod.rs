//! Spectral quantities: four hero wavelengths per path (Wilkie et al. 2014, "Hero Wavelength
//! Spectral Sampling"), sampled over 360–830 nm by the density of the linear-sRGB
//! colour-matching functions ([`response`]).

pub mod cie;
pub mod ior;
pub mod response;
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
    /// The normalised D65 illuminant at each wavelength ([`cie::d65`]), computed once per
    /// path: every RGB emitter (`Spectrum::RgbIlluminant`) multiplies by it at each evaluation,
    /// and looking it up there cost ~3 % of a render of the thin-film benchmark sphere. Keep it
    /// in step with `lambda` ([`SampledWavelengths::new`]).
    pub d65: [f32; N],
}

impl SampledWavelengths {
    /// Wavelengths `lambda` with densities `pdf`, and their D65 values.
    #[inline]
    pub fn new(lambda: [f32; N], pdf: [f32; N]) -> SampledWavelengths {
        let d = cie::d65;
        SampledWavelengths {
            lambda,
            pdf,
            d65: [d(lambda[0]), d(lambda[1]), d(lambda[2]), d(lambda[3])],
        }
    }

    /// Hero-wavelength sampling by the sRGB response ([`response`]): the i-th wavelength from
    /// (u + i)/N (`response::hero_position`), all through the same inverse CDF so each has
    /// the same density.
    pub fn sample_visible(u: f32) -> SampledWavelengths {
        let (lambda, pdf) = response::sample_hero(u);
        SampledWavelengths::new(lambda, pdf)
    }

    /// [`SampledWavelengths::sample_visible`] on lanes (the same operations, so the same
    /// bits): (wavelengths, densities).
    #[inline(always)]
    pub fn sample_visible_lanes<F: crate::simd::Float>(u: F) -> ([F; N], [F; N]) {
        let mut lambda = [u; N];
        let mut pdf = [u; N];
        for i in 0..N {
            // response::hero_position in lanes: the same operations, so the same bits.
            let up = (u + F::splat(i as f32)) * F::splat(1.0 / N as f32);
            (lambda[i], pdf[i]) = response::sample_lanes(up);
        }
        (lambda, pdf)
    }

    /// Evenly spaced wavelengths with uniform density, starting at `u` within the first bin.
    pub fn sample_uniform(u: f32) -> SampledWavelengths {
        let delta = (LAMBDA_MAX - LAMBDA_MIN) / N as f32;
        let lambda = std::array::from_fn(|i| LAMBDA_MIN + (u + i as f32) * delta);
        SampledWavelengths::new(lambda, [1.0 / (LAMBDA_MAX - LAMBDA_MIN); N])
    }

    /// Given wavelengths with unit density (for evaluating at chosen wavelengths, e.g. in tools).
    pub fn fixed(lambda: [f32; N]) -> SampledWavelengths {
        SampledWavelengths::new(lambda, [1.0; N])
    }

    /// The first wavelength. From [`SampledWavelengths::sample_visible`] it always lies in the
    /// first 1/N of the response's CDF (only the set as a whole has the response's density), so
    /// an event that keeps a single wavelength (dispersion) must pick one of the N uniformly at
    /// random rather than keep this one.
    #[inline]
    pub fn hero(&self) -> f32 {
        self.lambda[0]
    }
}
