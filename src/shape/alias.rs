//! Walker's alias method: O(1) sampling of a discrete distribution.
//!
//! Walker, "An Efficient Method for Generating Discrete Random Variables with General
//! Distributions", ACM TOMS 3(3), 1977; the table is built with Vose's stable O(n) construction
//! (Vose, "A Linear Algorithm for Generating Random Numbers with a Given Distribution", IEEE TSE
//! 17(9), 1991). Each of the n buckets holds a threshold and an alias: a uniform u picks bucket
//! ⌊u·n⌋, whose own item is taken when the fraction u·n − ⌊u·n⌋ falls below the threshold and
//! the alias otherwise. The fraction left over is rescaled to [0, 1) and returned, so one random
//! number both selects the item and positions the sample inside it.
//!
//! With equal weights every threshold is 1 and the mapping is exactly i = ⌊u·n⌋, fraction
//! u·n − i: the same as inverting a cumulative table, so meshes of equal triangles (rectangles,
//! cubes) sample the same points as before.

/// A table for sampling indices in proportion to their weights.
#[derive(Clone, Debug)]
pub(crate) struct AliasTable {
    /// Per bucket: the probability of keeping the bucket's own item, and its alias.
    buckets: Vec<(f32, u32)>,
}

impl AliasTable {
    /// The table for `weights` (non-negative, finite, not all zero); `None` otherwise.
    pub fn new(weights: &[f64]) -> Option<AliasTable> {
        let n = weights.len();
        let total: f64 = weights.iter().sum();
        let valid = weights.iter().all(|w| *w >= 0.0 && w.is_finite());
        if n == 0 || n > u32::MAX as usize || !valid || !(total > 0.0 && total.is_finite()) {
            return None;
        }
        // Scaled so that the mean is 1: buckets below 1 are filled up by items above 1.
        let mut p: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
        let mut buckets: Vec<(f32, u32)> = (0..n as u32).map(|i| (1.0, i)).collect();
        let (mut small, mut large): (Vec<u32>, Vec<u32>) =
            (0..n as u32).partition(|&i| p[i as usize] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            buckets[s as usize] = (p[s as usize] as f32, l);
            // The large item gives bucket s what it lacks.
            p[l as usize] = (p[l as usize] + p[s as usize]) - 1.0;
            if p[l as usize] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // What is left is 1 up to rounding: those buckets keep their own item.
        Some(AliasTable { buckets })
    }

    #[cfg(test)]
    /// Number of items.
    pub fn len(&self) -> usize {
        self.buckets.len()
    }

    /// The item for `u` in [0, 1), and the leftover fraction rescaled to [0, 1).
    #[inline]
    pub fn sample(&self, u: f32) -> (usize, f32) {
        let n = self.buckets.len();
        // f64 keeps every bit of u·n (24 + at most 32 bits).
        let x = u as f64 * n as f64;
        let i = (x as usize).min(n - 1);
        let f = x - i as f64;
        let (keep, alias) = self.buckets[i];
        let keep = keep as f64;
        let (item, r) = if keep == 1.0 {
            // A full bucket (every bucket when the weights are equal): f / 1 without the
            // division's latency, the same bits.
            (i, f)
        } else if f < keep {
            (i, f / keep)
        } else {
            (alias as usize, (f - keep) / (1.0 - keep))
        };
        (item, (r as f32).clamp(0.0, crate::math::ONE_MINUS_EPSILON))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;

    /// Upper 1 % point of χ² with k degrees of freedom (Wilson–Hilferty).
    fn chi2_critical(k: f64) -> f64 {
        let z = 2.326_347_874; // standard normal 99 % quantile
        k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3)
    }

    fn chi2(counts: &[u64], expected: &[f64]) -> f64 {
        counts
            .iter()
            .zip(expected)
            .map(|(&c, &e)| (c as f64 - e).powi(2) / e)
            .sum()
    }

    #[test]
    fn frequencies_match_the_weights() {
        let mut rng = Pcg32::new(21, 5);
        // Uneven weights over four decades, some zero (never drawn), one dominant.
        let mut w: Vec<f64> = (0..200)
            .map(|i| match i % 17 {
                0 => 0.0,
                1 => 40.0,
                _ => 10f64.powf(3.0 * rng.next_f32() as f64) * 0.01,
            })
            .collect();
        w[5] = 300.0;
        let t = AliasTable::new(&w).unwrap();
        assert_eq!(t.len(), 200);
        let total: f64 = w.iter().sum();
        let n = 2_000_000u64;
        let mut counts = vec![0u64; w.len()];
        // The leftover fraction, histogrammed in 8 bins per item.
        let mut frac = vec![0u64; 8];
        for _ in 0..n {
            let (i, r) = t.sample(rng.next_f32());
            assert!((0.0..1.0).contains(&r));
            counts[i] += 1;
            frac[(r * 8.0) as usize] += 1;
        }
        for (i, &c) in counts.iter().enumerate() {
            if w[i] == 0.0 {
                assert_eq!(c, 0, "zero-weight item {i} drawn");
            }
        }
        // χ² over the items with weight, pooling expected counts below 5 in one cell.
        let (mut obs, mut exp) = (Vec::new(), Vec::new());
        let (mut po, mut pe) = (0u64, 0.0);
        for (i, &c) in counts.iter().enumerate() {
            let e = n as f64 * w[i] / total;
            if w[i] == 0.0 {
                continue;
            }
            if e < 5.0 {
                po += c;
                pe += e;
            } else {
                obs.push(c);
                exp.push(e);
            }
        }
        if pe > 0.0 {
            obs.push(po);
            exp.push(pe);
        }
        let x = chi2(&obs, &exp);
        assert!(
            x < chi2_critical((obs.len() - 1) as f64),
            "χ² {x} over {} cells",
            obs.len()
        );
        // The leftover fraction is uniform, so it can position the sample inside the item.
        let x = chi2(&frac, &[n as f64 / 8.0; 8]);
        assert!(x < chi2_critical(7.0), "fraction χ² {x}");
    }

    #[test]
    fn a_biased_table_fails_the_same_test() {
        // The test above has teeth: a 3 % shift of one weight's probability is detected.
        let w = [1.0, 2.0, 3.0, 4.0];
        let t = AliasTable::new(&w).unwrap();
        let mut rng = Pcg32::new(4, 4);
        let n = 2_000_000u64;
        let mut counts = [0u64; 4];
        for _ in 0..n {
            counts[t.sample(rng.next_f32()).0] += 1;
        }
        let exp = w.map(|x| n as f64 * x / 10.0);
        assert!(chi2(&counts, &exp) < chi2_critical(3.0));
        let wrong = [exp[0] * 1.03, exp[1], exp[2], exp[3] - exp[0] * 0.03];
        assert!(chi2(&counts, &wrong) > chi2_critical(3.0));
    }

    #[test]
    fn equal_weights_invert_like_a_cumulative_table() {
        let t = AliasTable::new(&[2.5; 6]).unwrap();
        let mut rng = Pcg32::new(1, 2);
        for _ in 0..10_000 {
            let u = rng.next_f32();
            let x = u as f64 * 6.0;
            let (i, r) = t.sample(u);
            assert_eq!(i, x as usize);
            assert_eq!(r, (x - i as f64) as f32);
        }
        assert!(AliasTable::new(&[]).is_none());
        assert!(AliasTable::new(&[0.0, 0.0]).is_none());
        assert!(AliasTable::new(&[1.0, f64::NAN]).is_none());
        assert!(AliasTable::new(&[1.0, -1.0]).is_none());
        assert_eq!(AliasTable::new(&[0.0, 3.0]).unwrap().sample(0.1).0, 1);
    }
}
