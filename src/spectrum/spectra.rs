//! Spectral distributions as they appear in scenes: constants, tabulated curves, blackbodies and
//! RGB colours uplifted to smooth spectra (Jakob & Hanika 2019, "A Low-Dimensional Function Space
//! for Efficient Spectral Upsampling").

use super::rgb2spec::{rgb_to_sigmoid, SigmoidPolynomial};
use super::{cie, SampledSpectrum, SampledWavelengths};
use crate::simd::{Float, Int};
use std::sync::Arc;

/// A piecewise-linear function of wavelength (nm), constant beyond its ends.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseLinear {
    pub lambda: Vec<f32>,
    pub values: Vec<f32>,
    /// Where the search for the segment of a wavelength starts: per bin of `bin` nm from
    /// `lambda[0]`, the last knot at or below the bin's start.
    start: Vec<u32>,
    bin: f32,
    /// Knots a search may have to step over from a start (see `eval_lanes`).
    steps: u32,
}

/// Most bins of a curve's start table.
const START_BINS: usize = 4096;

impl PiecewiseLinear {
    /// A curve from (λ, value) pairs; `None` unless λ is strictly increasing, finite and the two
    /// lists have the same non-zero length.
    pub fn new(lambda: Vec<f32>, values: Vec<f32>) -> Option<PiecewiseLinear> {
        if lambda.is_empty() || lambda.len() != values.len() {
            return None;
        }
        if lambda.windows(2).any(|w| !(w[1] > w[0]))
            || lambda.iter().chain(&values).any(|v| !v.is_finite())
        {
            return None;
        }
        // About sixteen bins per knot (at most START_BINS), so that a search starting two bins
        // early steps over at most one knot on an evenly tabulated curve: each step is a
        // gather in the wavefront's lanes, and a table of 16 entries per knot costs little.
        let range = lambda[lambda.len() - 1] - lambda[0];
        let bin = range / (16 * lambda.len()).min(START_BINS) as f32;
        let bins = ((range / bin) as usize + 1).min(START_BINS + 1);
        let start: Vec<u32> = (0..bins)
            .map(|j| {
                let x = lambda[0] + j as f32 * bin;
                (lambda.partition_point(|&k| k <= x) - 1) as u32
            })
            .collect();
        // A lane starts two bins early (the rounding of its bin index and of a bin's start may
        // each be off by one), so it steps over at most the knots of four bins.
        // Past the table's last bin, the knots up to the end may remain.
        let at = |k: usize| start.get(k).copied().unwrap_or(lambda.len() as u32 - 1);
        let steps = (0..bins).map(|j| at(j + 4) - at(j)).max().unwrap_or(0) + 1;
        Some(PiecewiseLinear {
            lambda,
            values,
            start,
            bin,
            steps,
        })
    }

    /// Value at `l` nm.
    pub fn eval(&self, l: f32) -> f32 {
        self.eval_lanes(l)
    }

    /// [`PiecewiseLinear::eval`] on lanes: the segment of each lane's wavelength is the last
    /// knot at or below it, found from a start table (two bins early) in a fixed number of
    /// steps — the knot a binary search would find — then the same interpolation.
    #[inline(always)]
    pub fn eval_lanes<F: Float>(&self, l: F) -> F {
        let n = self.lambda.len();
        let first = F::splat(self.lambda[0]);
        let last = F::splat(self.lambda[n - 1]);
        if n == 1 {
            return F::splat(self.values[0]);
        }
        let max_bin = F::I::splat(self.start.len() as i32 - 1);
        let bin = ((l - first) / F::splat(self.bin)).to_int() - F::I::splat(2);
        // Lanes outside the range (and NaN) read bin 0; their value is replaced below.
        let inside = l.gt(first) & l.lt(last);
        let bin = F::I::select(inside, bin, F::I::splat(0));
        let bin = F::I::select(bin.lt(F::I::splat(0)), F::I::splat(0), bin);
        let bin = F::I::select(bin.gt(max_bin), max_bin, bin);
        // The last segment starts at n − 2.
        let cap = F::I::splat(n as i32 - 2);
        let i = F::I::gather(&self.start, bin);
        let mut i = F::I::select(i.gt(cap), cap, i);
        for _ in 0..self.steps {
            let probe = i + F::I::splat(1);
            let step = !probe.gt(cap) & F::gather(&self.lambda, probe).le(l);
            i = F::I::select(step, probe, i);
        }
        let (l0, l1) = (
            F::gather(&self.lambda, i),
            F::gather(&self.lambda, i + F::I::splat(1)),
        );
        let (v0, v1) = (
            F::gather(&self.values, i),
            F::gather(&self.values, i + F::I::splat(1)),
        );
        let t = (l - l0) / (l1 - l0);
        let v = v0 + t * (v1 - v0);
        let v = F::select(l.ge(last), F::splat(self.values[n - 1]), v);
        F::select(l.le(first), F::splat(self.values[0]), v)
    }
}

/// A spectral distribution.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f32),
    /// A tabulated curve.
    PiecewiseLinear(Arc<PiecewiseLinear>),
    /// Planck's law at `temperature` kelvin in W·m⁻²·sr⁻¹·nm⁻¹, times `scale`.
    Blackbody { temperature: f32, scale: f32 },
    /// A reflectance-like RGB colour (components in [0, 1]) uplifted to a smooth spectrum.
    RgbAlbedo(SigmoidPolynomial),
    /// An RGB colour with components beyond 1: `scale` × a smooth spectrum of the colour / `scale`.
    RgbUnbounded { scale: f32, poly: SigmoidPolynomial },
    /// An RGB emission: the uplifted colour times the D65 illuminant normalised to unit luminance,
    /// so that `rgb(1, 1, 1)` renders as white (1, 1, 1) as in Mitsuba's spectral variants.
    RgbIlluminant { scale: f32, poly: SigmoidPolynomial },
}

impl Spectrum {
    /// A reflectance from linear sRGB; components are clamped to [0, 1].
    pub fn rgb_albedo(rgb: [f32; 3]) -> Spectrum {
        let c = rgb.map(|v| {
            if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                0.0
            }
        });
        if c[0] == c[1] && c[1] == c[2] {
            return Spectrum::Constant(c[0]);
        }
        Spectrum::RgbAlbedo(rgb_to_sigmoid(c))
    }

    /// An unbounded non-negative quantity (e.g. an index or extinction) from linear sRGB.
    pub fn rgb_unbounded(rgb: [f32; 3]) -> Spectrum {
        let c = rgb.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
        if c[0] == c[1] && c[1] == c[2] {
            return Spectrum::Constant(c[0]);
        }
        let (scale, poly) = Self::scaled(c);
        Spectrum::RgbUnbounded { scale, poly }
    }

    /// An emitted radiance from linear sRGB (multiplied by normalised D65).
    pub fn rgb_illuminant(rgb: [f32; 3]) -> Spectrum {
        let c = rgb.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
        let (scale, poly) = Self::scaled(c);
        Spectrum::RgbIlluminant { scale, poly }
    }

    fn scaled(c: [f32; 3]) -> (f32, SigmoidPolynomial) {
        let m = c[0].max(c[1]).max(c[2]);
        if m <= 0.0 {
            return (0.0, rgb_to_sigmoid([0.0; 3]));
        }
        let scale = 2.0 * m;
        (scale, rgb_to_sigmoid(c.map(|v| v / scale)))
    }

    /// Value at one wavelength (nm).
    pub fn eval(&self, l: f32) -> f32 {
        match self {
            Spectrum::Constant(v) => *v,
            Spectrum::PiecewiseLinear(p) => p.eval(l),
            Spectrum::Blackbody { temperature, scale } => scale * blackbody(l, *temperature),
            Spectrum::RgbAlbedo(p) => p.eval(l),
            Spectrum::RgbUnbounded { scale, poly } => scale * poly.eval(l),
            Spectrum::RgbIlluminant { scale, poly } => scale * poly.eval(l) * cie::d65(l),
        }
    }

    /// Values at the path's wavelengths.
    #[inline]
    pub fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        // One match for the four wavelengths, so the uplift's arithmetic runs in SIMD lanes.
        let l = wl.lambda;
        match self {
            Spectrum::Constant(v) => SampledSpectrum::splat(*v),
            Spectrum::RgbAlbedo(p) => SampledSpectrum(p.eval4(l)),
            Spectrum::RgbUnbounded { scale, poly } => SampledSpectrum(poly.eval4(l)) * *scale,
            Spectrum::RgbIlluminant { scale, poly } => {
                // D65 as the wavelengths carry it (computed once per path; `l.map(cie::d65)`
                // here, not inlined, was 2 % of a render of the thin-film benchmark sphere).
                let (p, d) = (poly.eval4(l), wl.d65);
                SampledSpectrum([
                    scale * p[0] * d[0],
                    scale * p[1] * d[1],
                    scale * p[2] * d[2],
                    scale * p[3] * d[3],
                ])
            }
            _ => SampledSpectrum::from_fn(|i| self.eval(l[i])),
        }
    }

    /// Largest value over 360–830 nm (sampled at 1 nm), used for light power estimates.
    pub fn max_value(&self) -> f32 {
        match self {
            Spectrum::Constant(v) => *v,
            _ => (360..=830).map(|l| self.eval(l as f32)).fold(0.0, f32::max),
        }
    }
}

/// Planck's law: spectral radiance of a blackbody at `t` kelvin, in W·m⁻²·sr⁻¹·nm⁻¹.
pub fn blackbody(lambda_nm: f32, t: f32) -> f32 {
    if !(t > 0.0) {
        return 0.0;
    }
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    let l = lambda_nm as f64 * 1e-9;
    let le = (2.0 * H * C * C) / (l.powi(5) * ((H * C / (l * KB * t as f64)).exp() - 1.0));
    (le * 1e-9) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piecewise_linear_interpolates_and_clamps() {
        let p = PiecewiseLinear::new(vec![400.0, 500.0, 600.0], vec![1.0, 3.0, 2.0]).unwrap();
        assert_eq!(p.eval(300.0), 1.0);
        assert_eq!(p.eval(450.0), 2.0);
        assert_eq!(p.eval(550.0), 2.5);
        assert_eq!(p.eval(700.0), 2.0);
        assert!(PiecewiseLinear::new(vec![500.0, 400.0], vec![1.0, 1.0]).is_none());
    }

    #[test]
    fn the_start_table_finds_the_segment_a_binary_search_finds() {
        // The interpolation as written before the start table (a binary search), against the
        // table's: curves with dense, sparse and uneven knots over narrow and wide ranges, at
        // random wavelengths, at the knots themselves and one ulp either side of them.
        fn reference(p: &PiecewiseLinear, l: f32) -> f32 {
            let n = p.lambda.len();
            if l <= p.lambda[0] {
                return p.values[0];
            }
            if l >= p.lambda[n - 1] {
                return p.values[n - 1];
            }
            let i = p.lambda.partition_point(|&x| x <= l) - 1;
            let t = (l - p.lambda[i]) / (p.lambda[i + 1] - p.lambda[i]);
            p.values[i] + t * (p.values[i + 1] - p.values[i])
        }
        let mut rng = crate::math::Pcg32::new(12, 3);
        for case in 0..300 {
            let n = 2 + (rng.next_u32() % 200) as usize;
            let spacing = [0.01f32, 0.3, 1.0, 7.0, 500.0][case % 5];
            let mut lambda = vec![200.0 + 100.0 * rng.next_f32()];
            for _ in 1..n {
                let last = *lambda.last().unwrap();
                let next = last + spacing * (0.05 + 2.0 * rng.next_f32());
                if next > last {
                    lambda.push(next);
                }
            }
            let values: Vec<f32> = lambda.iter().map(|_| rng.next_f32() * 3.0).collect();
            let p = PiecewiseLinear::new(lambda.clone(), values).unwrap();
            let (lo, hi) = (lambda[0] - 10.0, lambda[lambda.len() - 1] + 10.0);
            let mut probes: Vec<f32> = (0..500).map(|_| lo + (hi - lo) * rng.next_f32()).collect();
            for &k in &lambda {
                probes.extend([
                    k,
                    f32::from_bits(k.to_bits() - 1),
                    f32::from_bits(k.to_bits() + 1),
                ]);
            }
            for l in probes {
                assert_eq!(
                    p.eval(l).to_bits(),
                    reference(&p, l).to_bits(),
                    "case {case} at {l}"
                );
            }
        }
    }

    #[test]
    fn blackbody_peak_follows_wien() {
        // Wien's displacement law: λ_max = 2.897771955e6 nm·K / T.
        let t = 5000.0;
        let peak = (300..1200)
            .map(|l| l as f32)
            .max_by(|a, b| blackbody(*a, t).total_cmp(&blackbody(*b, t)))
            .unwrap();
        assert!((peak - 2.897_772e6 / t).abs() <= 1.0, "{peak}");
    }
}
