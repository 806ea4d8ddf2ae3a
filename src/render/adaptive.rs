//! Adaptive sampling: the same number of samples, spent where the image is noisy.
//!
//! A render with the sampler's `adaptive` set first takes a *pilot* of a quarter of its
//! samples per pixel (at least [`MIN_PILOT`]) uniformly, keeping each pixel's sum of squared
//! luminance beside its sums. From the pilot each pixel's relative noise per sample is
//! estimated,
//!
//!   σ_i = √( s²(Y) / (Ȳ² + ε) ),  s² the pilot's sample variance of Y, ε = 10⁻²,
//!
//! and each pixel gets a target count N_i ∝ the root mean square of σ over the (up to 24)
//! pixels around it in a 5 × 5 window (their pooled relative variance), the pixel itself left
//! out, floored at a fifth of the image's mean, no lower than the pilot and
//! no higher than [`MAX_FACTOR`] × spp, with Σ N_i = spp × pixels (the budget the uniform
//! render would spend). For a fixed budget the mean relative variance Σ σ_i² / N_i is smallest
//! with N_i ∝ σ_i (Neyman's optimal allocation of stratified sampling, J. Neyman 1934, "On the
//! two different aspects of the representative method", JRSS 97(4)); the neighbours stand in for the pixel because a pixel whose own pilot
//! decided its count would keep more samples when they happened to be far from its mean, and
//! its estimate would be biased. Its own pilot samples are kept: nothing is thrown away.
//!
//! On the flagship nine tenths of the noise is the sun's glints along the snake's back, in a
//! few per cent of the pixels. Measured there (`bench/noise.py --spp 64 --repeats 3`, 320×180,
//! relVar × spp, median of three pairs, 2026-12-03): uniform 0.298; with a pilot of a quarter
//! and the *mean* σ of the window, 0.151 over the eight nearest neighbours and 0.140 over the
//! 5 × 5 window; with the root mean square over the 5 × 5 window (the settings here) 0.127,
//! 2.35× less than uniform; but the snake's samples, which it now favours, cost more, 11 % more
//! CPU per sample here and 27 % at 640×360 and 256 spp, so the time to equal noise falls about
//! 2× (`--cpu --config=-:adaptive=false --config=-:adaptive=true`). A pilot of an eighth gave
//! 0.135 (0.134 against 0.130 at 256 spp); with the mean σ of the 3 × 3 window, an eighth
//! 0.177 and a half 0.136 against a quarter's 0.151; counts ∝ σ^0.75
//! or σ^0.8 were worse, σ^1.3 level; the floor at 0.1 and the cap at 64 × spp changed nothing
//! (neither binds there). Counting the pixel itself in its window gave less (0.128 with the
//! mean σ), but biased.
//!
//! Determinism: the pass schedule stays a function of the sample count. After the pilot,
//! passes run on a *nominal* axis s ∈ [pilot, spp], pixel i holding
//!
//!   f_i(s) = pilot + ⌊(s − pilot)(N_i − pilot) / (spp − pilot)⌋
//!
//! samples at the end of nominal pass s, so each pixel's samples are grouped into the same
//! sums whatever the threads, the tile order, or where a render was interrupted and resumed.
//! The targets are computed once, serially, from the pilot's sums (the same bits whatever the
//! threads), and kept in the film with each pixel's nominal progress, so a checkpoint carries
//! them (`checkpoint.rs`, version 3).
//!
//! Cycles calls the same idea adaptive sampling (with a noise threshold rather than a fixed
//! budget); Mitsuba 3 has none.

use crate::film::Film;

/// Fewest pilot samples per pixel: below this the pilot's variance says little.
pub const MIN_PILOT: u32 = 4;

/// Most samples a pixel may get, as a multiple of spp.
pub const MAX_FACTOR: u32 = 16;

/// The ε of the relative variance (linear luminance units), as in `bench/noise.py`'s metric.
const EPS: f64 = 1e-2;

/// How far the window of pixels that set a pixel's count reaches: 2, a 5 × 5 window.
const RADIUS: usize = 2;

/// The floor of a pixel's share, as a fraction of the image's mean window noise.
const FLOOR: f64 = 0.2;

/// An adaptive render's state, kept in the film.
#[derive(Clone, Debug, PartialEq)]
pub struct Adaptive {
    /// The target samples per pixel on average (the render's spp).
    pub spp: u32,
    /// Pilot samples per pixel.
    pub pilot: u32,
    /// Per pixel, the sum of the squared luminance (Y) of its pilot samples.
    pub sq: Vec<f64>,
    /// Per pixel, the nominal sample index its samples reach (the end of the last pass it
    /// finished): during the pilot its sample count.
    pub done: Vec<u32>,
    /// Per pixel, its target count; empty until the pilot is complete.
    pub targets: Vec<u32>,
}

/// The pilot of an adaptive render of `spp` samples per pixel, or `None` where it would leave
/// nothing to allocate.
pub fn pilot(spp: u32) -> Option<u32> {
    let p = (spp / 4).max(MIN_PILOT);
    (p < spp).then_some(p)
}

impl Adaptive {
    /// The state of a fresh adaptive render of `pixels` pixels, or `None` (see [`pilot`]).
    pub fn new(spp: u32, pixels: usize) -> Option<Adaptive> {
        Some(Adaptive {
            spp,
            pilot: pilot(spp)?,
            sq: vec![0.0; pixels],
            done: vec![0; pixels],
            targets: Vec::new(),
        })
    }

    /// What the workers of a pass need: the counts, without the per-pixel progress.
    pub fn plan(&self) -> Plan {
        Plan {
            spp: self.spp,
            pilot: self.pilot,
            targets: self.targets.clone(),
        }
    }
}

/// An adaptive render's per-pixel counts, as the workers of one pass read them.
#[derive(Clone, Debug)]
pub struct Plan {
    spp: u32,
    pilot: u32,
    /// Empty during the pilot.
    targets: Vec<u32>,
}

impl Plan {
    /// The samples pixel `i` holds at the end of nominal pass `s` (the module notes' f_i).
    #[inline]
    pub fn samples_at(&self, i: usize, s: u32) -> u32 {
        if s <= self.pilot || self.targets.is_empty() {
            return s;
        }
        let extra = (self.targets[i] - self.pilot) as u64;
        self.pilot + ((s - self.pilot) as u64 * extra / (self.spp - self.pilot) as u64) as u32
    }
}

/// Each pixel's target count from a film holding exactly `a.pilot` samples per pixel (see
/// the module notes).
pub fn targets(film: &Film, a: &Adaptive) -> Vec<u32> {
    let (w, h) = (film.width as usize, film.height as usize);
    let n = a.pilot as f64;
    let sigma: Vec<f64> = film
        .pixels
        .iter()
        .zip(&a.sq)
        .map(|(p, &sq)| {
            let mean = p[1] / n;
            let var = ((sq - p[1] * mean) / (n - 1.0)).max(0.0);
            (var / (mean * mean + EPS)).sqrt()
        })
        .collect();
    let mut around = vec![0.0f64; w * h];
    for y in 0..h {
        for x in 0..w {
            let (mut sum, mut count) = (0.0, 0u32);
            for yy in y.saturating_sub(RADIUS)..(y + RADIUS + 1).min(h) {
                for xx in x.saturating_sub(RADIUS)..(x + RADIUS + 1).min(w) {
                    if (xx, yy) != (x, y) {
                        sum += sigma[yy * w + xx] * sigma[yy * w + xx];
                        count += 1;
                    }
                }
            }
            // A 1 × 1 image has no neighbours: its one pixel takes the whole budget anyway.
            around[y * w + x] = if count > 0 {
                (sum / count as f64).sqrt()
            } else {
                1.0
            };
        }
    }
    let mean = around.iter().sum::<f64>() / around.len() as f64;
    let floor = FLOOR * mean;
    if !(floor > 0.0) {
        // A noiseless pilot (or a black image): nothing says where to spend; stay uniform.
        return vec![a.spp; w * h];
    }
    for v in &mut around {
        *v = v.max(floor);
    }
    // Water-filling: N_i = clamp(λ·around_i, pilot, cap) with λ such that Σ N_i is the budget.
    let (lo, hi) = (a.pilot as f64, (a.spp as f64) * MAX_FACTOR as f64);
    let budget = a.spp as f64 * (w * h) as f64;
    let spent = |lambda: f64| -> f64 { around.iter().map(|v| (lambda * v).clamp(lo, hi)).sum() };
    // λ = hi / floor puts every pixel at the cap, past the budget.
    let (_, l1) = crate::math::bisect_increasing(spent, budget, (0.0, hi / floor), 100);
    around
        .iter()
        .map(|v| ((l1 * v).clamp(lo, hi) + 0.5).floor() as u32)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A film holding `pilot` samples per pixel with the given per-pixel luminance mean and
    /// sample variance.
    fn film(w: u32, h: u32, pilot: u32, stats: impl Fn(usize) -> (f64, f64)) -> (Film, Adaptive) {
        let mut f = Film::new(w, h);
        let mut a = Adaptive::new(4 * pilot, (w * h) as usize).unwrap();
        assert_eq!(a.pilot, pilot);
        let n = pilot as f64;
        for i in 0..(w * h) as usize {
            let (mean, var) = stats(i);
            f.pixels[i] = [0.0, mean * n, 0.0, n];
            a.sq[i] = var * (n - 1.0) + mean * mean * n;
        }
        (f, a)
    }

    #[test]
    fn targets_spend_the_budget_within_bounds() {
        let (f, a) = film(40, 30, 8, |i| (0.5, if i % 37 == 0 { 4.0 } else { 0.01 }));
        let t = targets(&f, &a);
        let total: u64 = t.iter().map(|&v| v as u64).sum();
        let budget = a.spp as u64 * t.len() as u64;
        // Each pixel's rounding moves the sum by at most a half.
        assert!(
            total.abs_diff(budget) <= t.len() as u64 / 2,
            "{total} vs {budget}"
        );
        assert!(t.iter().all(|&v| v >= a.pilot && v <= a.spp * MAX_FACTOR));
        // The noisy pixels' neighbours get more than the quiet image's pixels.
        assert!(t[1] > t[20 * 40 + 20], "{} {}", t[1], t[20 * 40 + 20]);
    }

    #[test]
    fn a_pixel_s_own_noise_does_not_set_its_count() {
        let quiet = |_| (0.5, 0.01);
        let (f, a) = film(9, 9, 8, quiet);
        let (g, b) = film(9, 9, 8, |i| if i == 40 { (0.5, 50.0) } else { quiet(i) });
        let (t, u) = (targets(&f, &a), targets(&g, &b));
        // The noisy centre's neighbours gain; the centre itself keeps its quiet neighbours'
        // share (less, as the budget moved to them).
        assert!(u[31] > t[31]);
        assert!(u[40] <= t[40], "{} {}", u[40], t[40]);
    }

    #[test]
    fn a_noiseless_pilot_stays_uniform() {
        let (f, a) = film(5, 4, 4, |_| (0.3, 0.0));
        assert!(targets(&f, &a).iter().all(|&v| v == a.spp));
    }

    #[test]
    fn nominal_passes_reach_each_target_monotonically() {
        let mut a = Adaptive::new(100, 3).unwrap();
        a.targets = vec![25, 100, 1600];
        let p = a.plan();
        for i in 0..3 {
            assert_eq!(p.samples_at(i, a.pilot), a.pilot);
            assert_eq!(p.samples_at(i, a.spp), a.targets[i]);
            for s in a.pilot..a.spp {
                assert!(p.samples_at(i, s) <= p.samples_at(i, s + 1));
            }
        }
        assert_eq!(pilot(4), None);
        assert_eq!(pilot(5), Some(4));
        assert_eq!(pilot(128), Some(32));
    }
}
