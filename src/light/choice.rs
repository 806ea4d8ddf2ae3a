//! The light that next-event estimation samples at a vertex: a defensive mixture of an even
//! choice and a choice by power (Hesterberg 1995, below), with the smooth environments left to
//! the BSDF's own samples where a vertex asks for that (see [`crate::integrator::path`]).

use super::distribution::Distribution1D;
use crate::simd::{Float, Int, Mask};

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
    use crate::light::distribution::tests::check_frequencies;
    use crate::math::Pcg32;

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
