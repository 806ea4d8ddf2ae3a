//! Piecewise-constant distributions for importance sampling (inversion of a tabulated CDF; the
//! 2D case samples a marginal over rows, then the chosen row's conditional — see Pharr, Jakob &
//! Humphreys, "Physically Based Rendering", 3rd ed., §13.6.7). The light choice built on them
//! is [`super::choice`].
//!
//! Known limits: the CDF is accumulated in f64 but stored in f32, so a cell whose weight is below
//! ~1e-7 of the total may never be drawn although its pdf is positive.

use crate::math::{Vec2, ONE_MINUS_EPSILON};
use crate::simd::{Float, Int};

/// A piecewise-constant density on [0, 1) with `n` equal cells.
///
/// Negative or non-finite weights count as zero; if every weight is zero the distribution is
/// uniform, so that it can always be sampled and its pdf always matches its samples.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    func: Vec<f32>,
    cdf: Vec<f32>,
    /// ∫₀¹ of the effective (possibly uniform-fallback) function.
    integral: f32,
    /// Sum of the weights as given (zero when the fallback is in use).
    total: f64,
}

impl Distribution1D {
    /// A distribution proportional to `weights` (an empty list counts as one cell).
    pub fn new(weights: &[f32]) -> Distribution1D {
        let mut func: Vec<f32> = weights
            .iter()
            .map(|&w| if w.is_finite() && w > 0.0 { w } else { 0.0 })
            .collect();
        if func.is_empty() {
            func.push(0.0);
        }
        let total: f64 = func.iter().map(|&w| w as f64).sum();
        if !(total > 0.0 && total.is_finite()) {
            func.iter_mut().for_each(|w| *w = 1.0);
        }
        let n = func.len();
        let sum: f64 = func.iter().map(|&w| w as f64).sum();
        let mut cdf = Vec::with_capacity(n + 1);
        let mut acc = 0.0f64;
        cdf.push(0.0);
        for &w in &func {
            acc += w as f64;
            cdf.push((acc / sum) as f32);
        }
        cdf[n] = 1.0;
        Distribution1D {
            func,
            cdf,
            integral: (sum / n as f64) as f32,
            total: if total.is_finite() { total } else { 0.0 },
        }
    }

    /// Number of cells.
    #[inline]
    pub fn count(&self) -> usize {
        self.func.len()
    }

    /// Sum of the weights as given (0 if they were all zero).
    pub fn total(&self) -> f64 {
        self.total
    }

    /// The cell whose CDF interval holds `u`: cdf[i] ≤ u < cdf[i+1] (so never an empty cell).
    #[inline]
    fn find(&self, u: f32) -> usize {
        self.find_lanes(u) as usize
    }

    /// [`Distribution1D::find`] on lanes (for u ≥ 0): a binary search of fixed length for the
    /// last CDF entry at or below u, capped at the last cell.
    #[inline(always)]
    fn find_lanes<F: Float>(&self, u: F) -> F::I {
        let mut lo = F::I::splat(0);
        let mut len = self.cdf.len();
        while len > 1 {
            let half = len / 2;
            let probe = lo + F::I::splat(half as i32);
            lo = F::I::select(F::gather(&self.cdf, probe).le(u), probe, lo);
            len -= half;
        }
        let last = F::I::splat(self.func.len() as i32 - 1);
        F::I::select(lo.gt(last), last, lo)
    }

    /// [`Distribution1D::sample_discrete`]'s cell and its probability, on lanes.
    #[inline(always)]
    pub(crate) fn sample_discrete_lanes<F: Float>(&self, u: F) -> (F::I, F) {
        let i = self.find_lanes(u.clamp(0.0, ONE_MINUS_EPSILON));
        let pmf = F::gather(&self.func, i) / F::splat(self.integral * self.count() as f32);
        (i, pmf)
    }

    /// Samples x ∈ [0, 1); returns (x, density at x, cell index).
    pub(crate) fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let u = u.clamp(0.0, ONE_MINUS_EPSILON);
        let i = self.find(u);
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let du = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
        let x = ((i as f32 + du) / self.count() as f32).min(ONE_MINUS_EPSILON);
        (x, self.func[i] / self.integral, i)
    }

    /// Samples a cell; returns (index, probability, `u` re-stretched to [0, 1) within the cell).
    pub(crate) fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let u = u.clamp(0.0, ONE_MINUS_EPSILON);
        let i = self.find(u);
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let remapped = if c1 > c0 {
            ((u - c0) / (c1 - c0)).min(ONE_MINUS_EPSILON)
        } else {
            0.5
        };
        (i, self.pmf(i), remapped)
    }

    /// Density of [`Self::sample_continuous`] at `x` (0 outside [0, 1]).
    pub(crate) fn pdf(&self, x: f32) -> f32 {
        if !(0.0..=1.0).contains(&x) {
            return 0.0;
        }
        let i = ((x * self.count() as f32) as usize).min(self.count() - 1);
        self.func[i] / self.integral
    }

    /// Probability of [`Self::sample_discrete`] returning cell `i`.
    pub(crate) fn pmf(&self, i: usize) -> f32 {
        match self.func.get(i) {
            Some(&f) => f / (self.integral * self.count() as f32),
            None => 0.0,
        }
    }
}

/// A piecewise-constant density on [0, 1)², from a row-major grid of weights (`nu` columns along
/// x = u, `nv` rows along y = v).
#[derive(Clone, Debug)]
pub struct Distribution2D {
    conditional: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// `weights.len()` must be `nu * nv`; missing entries count as zero.
    pub fn new(weights: &[f32], nu: usize, nv: usize) -> Distribution2D {
        let (nu, nv) = (nu.max(1), nv.max(1));
        let conditional: Vec<Distribution1D> = (0..nv)
            .map(|v| Distribution1D::new(weights.get(v * nu..(v + 1) * nu).unwrap_or(&[])))
            .collect();
        let rows: Vec<f32> = conditional.iter().map(|d| d.total() as f32).collect();
        Distribution2D {
            marginal: Distribution1D::new(&rows),
            conditional,
        }
    }

    /// Samples a point of [0, 1)²; returns (point, density, (column, row)).
    pub fn sample(&self, u: Vec2) -> (Vec2, f32, (usize, usize)) {
        let (v, pdf_v, iv) = self.marginal.sample_continuous(u.y);
        let (x, pdf_u, iu) = self.conditional[iv].sample_continuous(u.x);
        (Vec2::new(x, v), pdf_v * pdf_u, (iu, iv))
    }

    /// Density of [`Self::sample`] at `p`.
    pub(crate) fn pdf(&self, p: Vec2) -> f32 {
        if !(0.0..=1.0).contains(&p.y) {
            return 0.0;
        }
        let nv = self.marginal.count();
        let iv = ((p.y * nv as f32) as usize).min(nv - 1);
        self.marginal.pdf(p.y) * self.conditional[iv].pdf(p.x)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::math::Pcg32;

    /// Draws `n` samples and checks each cell's frequency against its pmf within 4σ of the
    /// binomial count.
    pub(crate) fn check_frequencies(counts: &[u32], pmf: impl Fn(usize) -> f32, n: u32) {
        for (i, &c) in counts.iter().enumerate() {
            let p = pmf(i) as f64;
            let mean = p * n as f64;
            let sigma = (n as f64 * p * (1.0 - p)).sqrt();
            assert!(
                (c as f64 - mean).abs() <= 4.0 * sigma + 1e-9,
                "cell {i}: {c} vs {mean} ± {sigma}"
            );
        }
    }

    #[test]
    fn discrete_frequencies_match_pmf_and_skip_zeros() {
        let w = [1.0, 0.0, 3.0, 0.5, 0.0, 2.0];
        let d = Distribution1D::new(&w);
        let total: f32 = w.iter().sum();
        for (i, &wi) in w.iter().enumerate() {
            assert!((d.pmf(i) - wi / total).abs() < 1e-6);
        }
        let mut rng = Pcg32::new(7, 0);
        let n = 200_000;
        let mut counts = [0u32; 6];
        for _ in 0..n {
            let (i, p, r) = d.sample_discrete(rng.next_f32());
            assert!(p > 0.0 && (0.0..1.0).contains(&r));
            counts[i] += 1;
        }
        assert_eq!(counts[1] + counts[4], 0);
        check_frequencies(&counts, |i| d.pmf(i), n);
    }

    #[test]
    fn continuous_mean_matches_pdf() {
        // E[g(x)/pdf(x)] = ∫₀¹ g for g(x) = x², with the sample variance giving 4σ.
        let d = Distribution1D::new(&[0.2, 5.0, 1.0, 0.0, 3.0]);
        let mut rng = Pcg32::new(11, 0);
        let n = 100_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let (x, pdf, i) = d.sample_continuous(rng.next_f32());
            assert_eq!(i, (x * 5.0) as usize);
            assert!((pdf - d.pdf(x)).abs() < 1e-6 && pdf > 0.0);
            let f = (x * x / pdf) as f64;
            s += f;
            s2 += f * f;
        }
        let mean = s / n as f64;
        let sigma = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
        // The zero cell [0.6, 0.8) is never sampled, so the estimate is of ∫ outside it.
        let want = 1.0 / 3.0 - (0.8f64.powi(3) - 0.6f64.powi(3)) / 3.0;
        assert!(
            (mean - want).abs() < 4.0 * sigma,
            "{mean} vs {want} ± {sigma}"
        );
    }

    #[test]
    fn all_zero_and_bad_weights_fall_back_to_uniform() {
        for w in [&[0.0, 0.0, 0.0][..], &[f32::NAN, -1.0, 0.0], &[]] {
            let d = Distribution1D::new(w);
            let n = d.count() as f32;
            assert!((d.pmf(0) - 1.0 / n).abs() < 1e-6);
            assert!((d.pdf(0.3) - 1.0).abs() < 1e-6);
            let (x, pdf, _) = d.sample_continuous(0.55);
            assert!((x - 0.55).abs() < 1e-6 && (pdf - 1.0).abs() < 1e-6);
        }
        let d2 = Distribution2D::new(&[0.0; 6], 3, 2);
        let (p, pdf, _) = d2.sample(Vec2::new(0.2, 0.7));
        assert!((pdf - 1.0).abs() < 1e-6 && (d2.pdf(p) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn two_d_frequencies_match_pdf() {
        let (nu, nv) = (4, 3);
        let w = [1.0, 2.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 5.0, 1.0, 1.0, 3.0];
        let d = Distribution2D::new(&w, nu, nv);
        let total: f32 = w.iter().sum();
        let mut rng = Pcg32::new(3, 3);
        let n = 200_000;
        let mut counts = vec![0u32; nu * nv];
        for _ in 0..n {
            let (p, pdf, (iu, iv)) = d.sample(rng.next_vec2());
            assert!((pdf - d.pdf(p)).abs() < 1e-5 * pdf);
            counts[iv * nu + iu] += 1;
        }
        // A cell has area 1/(nu nv), so its probability is pdf/(nu nv) = w/total.
        check_frequencies(&counts, |i| w[i] / total, n);
    }
}
