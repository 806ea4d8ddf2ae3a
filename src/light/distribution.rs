//! Piecewise-constant distributions for importance sampling (inversion of a tabulated CDF; the
//! 2D case samples a marginal over rows, then the chosen row's conditional — see Pharr, Jakob &
//! Humphreys, "Physically Based Rendering", 3rd ed., §13.6.7), and the light sampler built on
//! them (half uniform, half by power).
//!
//! Known limits: the CDF is accumulated in f64 but stored in f32, so a cell whose weight is below
//! ~1e-7 of the total may never be drawn although its pdf is positive.

use crate::math::{Vec2, ONE_MINUS_EPSILON};
use crate::simd::{Float, Int, Mask};

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

/// Chooses a light for next-event estimation: half of the probability is spread evenly over
/// the lights that emit, half in proportion to their power (a defensive mixture, Hesterberg,
/// "Weighted average importance sampling and defensive mixture distributions", Technometrics
/// 37(2), 1995).
///
/// Power alone starves small lights next to a big one (Veach's multiple-importance scene: the
/// big light took ~98 % of the samples and the highlights of the four small ones came out 4–5×
/// noisier than with Mitsuba's uniform choice); uniform alone wastes samples on dim lights.
/// With the even mixture every light gets at least half of what either pure rule would give
/// it, so the variance of its contribution is at most twice that of the better rule. Lights of
/// zero power are never chosen unless every light has zero power; then the choice is uniform.
///
/// The even half is spread over the lights that only light sampling reaches well: the smooth
/// environments (below) take their power's share alone wherever another light emits, since a
/// BSDF's own samples are their defensive technique already (multiple importance sampling
/// counts them at every vertex). Without that, a vertex that keeps the full choice (the random
/// walk of `multilayered`) gave the flagship's sky a quarter of its light samples on top of its
/// power's share, 32 % in all for 8 % of the light, and the sun's glints on the snake's back
/// had two thirds of the light samples where they now have 93 %: relVar × spp 0.103 → 0.080,
/// 1.34× (1.23–1.42×) faster to equal noise (`bench/noise.py --spp 64 --repeats 3 --cpu`,
/// 320×180, 2026-12-03); the thin-film sphere with the walked coat under its grey `constant`
/// sky and a sun is level (0.0059 → 0.0061 at 1.03× the speed, 1.01×; 96², 64 spp, 2 pairs).
///
/// A second distribution leaves out the smooth environments (`constant`, Preetham's `sky`;
/// see [`crate::integrator::path`]'s module notes): the same choice
/// conditioned on not picking one, for vertices whose BSDF samples such a light better than
/// light sampling can (see [`crate::integrator::path`]'s module notes).
#[derive(Clone, Debug)]
pub struct LightSampler {
    dist: Option<Distribution1D>,
    /// The choice without smooth environments; `None` when no other light can be chosen.
    without_env: Option<Distribution1D>,
    /// Whether light `i` is a smooth environment.
    smooth_env: Vec<bool>,
}

/// The share of the probability spread evenly over the emitting lights.
pub(crate) const UNIFORM_SHARE: f64 = 0.5;

impl LightSampler {
    /// A sampler for lights of the given powers, none of them a smooth environment.
    pub fn new(powers: &[f32]) -> LightSampler {
        LightSampler::with_smooth_envs(powers, &vec![false; powers.len()])
    }

    /// A sampler for lights of the given powers, where `smooth_env[i]` says whether light `i`
    /// is a smooth environment.
    pub fn with_smooth_envs(powers: &[f32], smooth_env: &[bool]) -> LightSampler {
        assert_eq!(powers.len(), smooth_env.len());
        let ok = |p: f32| p.is_finite() && p > 0.0;
        let total: f64 = powers.iter().filter(|&&p| ok(p)).map(|&p| p as f64).sum();
        // The lights that share the even half: the emitting ones that light sampling alone
        // reaches well, or every emitting light where there are none of those.
        let others = (0..powers.len()).any(|i| ok(powers[i]) && !smooth_env[i]);
        let sharing = |i: usize| ok(powers[i]) && (!others || !smooth_env[i]);
        let n_sharing = (0..powers.len()).filter(|&i| sharing(i)).count();
        let even = |i: usize| {
            if sharing(i) {
                UNIFORM_SHARE / n_sharing as f64
            } else {
                0.0
            }
        };
        let weights: Vec<f32> = powers
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                if ok(p) && total.is_finite() {
                    (even(i) + (1.0 - UNIFORM_SHARE) * p as f64 / total) as f32
                } else if ok(p) {
                    1.0 // powers overflowing f64 are all "huge": share evenly
                } else {
                    0.0
                }
            })
            .collect();
        let dist = (!powers.is_empty()).then(|| Distribution1D::new(&weights));
        let without_env = dist.as_ref().and_then(|d| {
            let w: Vec<f32> = (0..powers.len())
                .map(|i| if smooth_env[i] { 0.0 } else { d.pmf(i) })
                .collect();
            w.iter().any(|&x| x > 0.0).then(|| Distribution1D::new(&w))
        });
        LightSampler {
            dist,
            without_env,
            smooth_env: smooth_env.to_vec(),
        }
    }

    /// Whether some light is a smooth environment (so that leaving them out changes the
    /// choice).
    pub fn has_smooth_env(&self) -> bool {
        self.smooth_env.iter().any(|&u| u)
    }

    /// Whether some light besides the smooth environments can be chosen.
    pub fn has_other_lights(&self) -> bool {
        self.without_env.is_some()
    }

    /// Whether light `i` is a smooth environment.
    pub(crate) fn is_smooth_env(&self, i: usize) -> bool {
        self.smooth_env.get(i).copied().unwrap_or(false)
    }

    /// Picks a light, leaving out the smooth environments when `no_env`: (index,
    /// probability); `None` when there is nothing to choose.
    pub fn sample_for(&self, u: f32, no_env: bool) -> Option<(usize, f32)> {
        if !no_env {
            return self.sample(u);
        }
        let (i, p, _) = self.without_env.as_ref()?.sample_discrete(u);
        Some((i, p))
    }

    /// Probability that [`Self::sample_for`] picks light `i`.
    pub(crate) fn pmf_for(&self, i: usize, no_env: bool) -> f32 {
        if !no_env {
            return self.pmf(i);
        }
        self.without_env.as_ref().map_or(0.0, |d| d.pmf(i))
    }

    /// [`LightSampler::sample_for`] on lanes, leaving out the smooth environments in the
    /// lanes of `no_env`: (light, probability; 0 where nothing can be chosen), `None` without
    /// lights.
    #[inline(always)]
    pub(crate) fn sample_lanes_for<F: Float>(&self, u: F, no_env: F::M) -> Option<(F::I, F)> {
        let all = self.sample_lanes(u)?;
        if !no_env.any() {
            return Some(all);
        }
        let (i, p) = match &self.without_env {
            Some(d) => d.sample_discrete_lanes(u),
            None => (F::I::splat(0), F::splat(0.0)),
        };
        Some((F::I::select(no_env, i, all.0), F::select(no_env, p, all.1)))
    }

    /// Picks a light: (index, probability); `None` when there are no lights.
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        let d = self.dist.as_ref()?;
        let (i, p, _) = d.sample_discrete(u);
        Some((i, p))
    }

    /// [`LightSampler::sample`] on lanes: (light, probability), `None` without lights.
    #[inline(always)]
    pub(crate) fn sample_lanes<F: Float>(&self, u: F) -> Option<(F::I, F)> {
        Some(self.dist.as_ref()?.sample_discrete_lanes(u))
    }

    /// Probability that [`Self::sample`] picks light `i`.
    pub(crate) fn pmf(&self, i: usize) -> f32 {
        self.dist.as_ref().map_or(0.0, |d| d.pmf(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;

    /// Draws `n` samples and checks each cell's frequency against its pmf within 4σ of the
    /// binomial count.
    fn check_frequencies(counts: &[u32], pmf: impl Fn(usize) -> f32, n: u32) {
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

    #[test]
    fn light_sampler_mixes_uniform_and_power_and_skips_dark_lights() {
        // Powers 2, 0, 6: the two emitting lights get 0.5/2 + 0.5·(2/8 or 6/8).
        let s = LightSampler::new(&[2.0, 0.0, 6.0]);
        assert_eq!(s.pmf(1), 0.0);
        assert!((s.pmf(0) - 0.375).abs() < 1e-6 && (s.pmf(2) - 0.625).abs() < 1e-6);
        let mut rng = Pcg32::new(5, 0);
        let n = 100_000;
        let mut counts = [0u32; 3];
        for _ in 0..n {
            let (i, p) = s.sample(rng.next_f32()).unwrap();
            assert_eq!(p, s.pmf(i));
            counts[i] += 1;
        }
        check_frequencies(&counts, |i| s.pmf(i), n);
        assert!(LightSampler::new(&[]).sample(0.5).is_none());
        assert!((LightSampler::new(&[0.0, 0.0]).pmf(1) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn no_light_gets_less_than_half_of_either_pure_rule() {
        // Veach's scene: one big light with 98 % of the power and four small ones.
        let powers = [98.0, 0.5, 0.5, 0.5, 0.5];
        let s = LightSampler::new(&powers);
        let total: f32 = powers.iter().sum();
        for (i, &p) in powers.iter().enumerate() {
            let uniform = 1.0 / powers.len() as f32;
            let by_power = p / total;
            assert!(
                s.pmf(i) >= 0.5 * uniform.max(by_power) - 1e-6,
                "{i}: {}",
                s.pmf(i)
            );
        }
        let sum: f32 = (0..5).map(|i| s.pmf(i)).sum();
        assert!((sum - 1.0).abs() < 1e-6);
        // Overflowing powers still give a valid, even choice.
        let s = LightSampler::new(&[f32::MAX, f32::MAX, f32::MAX]);
        assert!((s.pmf(2) - 1.0 / 3.0).abs() < 1e-6);
    }

    #[test]
    fn choice_without_smooth_environments_is_the_conditional_choice() {
        // Lights 1 and 3 are smooth environments; light 4 emits nothing.
        let powers = [2.0, 30.0, 6.0, 5.0, 0.0];
        let env = [false, true, false, true, false];
        let s = LightSampler::with_smooth_envs(&powers, &env);
        assert!(s.has_smooth_env() && s.is_smooth_env(3) && !s.is_smooth_env(0));
        // The environments take their power's share alone; the even half goes to lights 0
        // and 2 (the non-environments that emit).
        let total = 43.0f32;
        for (i, want) in [
            (0, 0.25 + 0.5 * 2.0 / total),
            (1, 0.5 * 30.0 / total),
            (2, 0.25 + 0.5 * 6.0 / total),
            (3, 0.5 * 5.0 / total),
            (4, 0.0),
        ] {
            assert!(
                (s.pmf(i) - want).abs() < 1e-6,
                "{i}: {} vs {want}",
                s.pmf(i)
            );
        }
        let rest = s.pmf(0) + s.pmf(2);
        for (i, &is_env) in env.iter().enumerate() {
            let want = if is_env { 0.0 } else { s.pmf(i) / rest };
            assert!((s.pmf_for(i, true) - want).abs() < 1e-6, "{i}");
            assert_eq!(s.pmf_for(i, false), s.pmf(i));
        }
        let mut rng = Pcg32::new(3, 0);
        let n = 100_000;
        let mut counts = [0u32; 5];
        for _ in 0..n {
            let (i, p) = s.sample_for(rng.next_f32(), true).unwrap();
            assert_eq!(p, s.pmf_for(i, true));
            counts[i] += 1;
        }
        check_frequencies(&counts, |i| s.pmf_for(i, true), n);
        // The lanes give the same choices, per lane as asked.
        let us: Vec<f32> = (0..64).map(|k| (k as f32 + 0.5) / 64.0).collect();
        for (k, &u) in us.iter().enumerate() {
            let no_env = k % 2 == 0;
            let (i, p) = s
                .sample_lanes_for::<f32>(u, no_env)
                .map(|(i, p)| (i as usize, p))
                .unwrap();
            assert_eq!(Some((i, p)), s.sample_for(u, no_env), "u = {u}");
        }
        // Only environments: nothing to choose without them; none at all: no choice.
        let only = LightSampler::with_smooth_envs(&[1.0, 0.0], &[true, false]);
        assert!(only.sample_for(0.3, true).is_none());
        assert_eq!(only.pmf_for(0, true), 0.0);
        assert_eq!(
            only.sample_lanes_for::<f32>(0.3, true).map(|x| x.1),
            Some(0.0)
        );
        let plain = LightSampler::new(&[1.0, 2.0]);
        assert!(!plain.has_smooth_env());
        assert_eq!(plain.sample_for(0.7, true), plain.sample(0.7));
    }
}
