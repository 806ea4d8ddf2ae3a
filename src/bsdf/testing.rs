//! Statistical checks for BSDFs, shared by the unit tests here and the integration tests.
//!
//! - [`chi2_test`]: χ² goodness of fit of `sample_f`'s directions against `pdf`. Directions are
//!   binned over (cos θ, φ) on the whole sphere (equal-area cells); expected counts integrate
//!   `pdf` over each cell by adaptive 2D Simpson quadrature to an error far below the Poisson
//!   noise; cells expecting fewer than 5 samples are pooled; the mass `sample_f` puts outside
//!   the histogram (delta lobes, failed samples) is one more category, expected n·(1 − ∫pdf). The
//!   p-value comes from the regularised upper incomplete gamma function (own implementation) and
//!   is compared with a significance of 0.01 Šidák-corrected over the number of tests run.
//!   Every non-delta sample's `f` and `pdf` are also checked against `f()` and `pdf()`.
//! - [`albedo`]: mean of f·|cos|/pdf under sampling (the directional albedo, or the part of it
//!   from non-delta lobes), with its standard error; [`hemispherical_integral`]: the same
//!   non-delta albedo by uniform-sphere Monte Carlo of f·|cos|, an independent oracle.
//! - [`reciprocity_error`]: f(a, b) in radiance mode against f(b, a) in importance mode (the
//!   adjoint BSDF), which for reflection is plain reciprocity and for refraction includes η².

use super::{Bxdf, TransportMode};
use crate::math::{Pcg32, Vec3};
use crate::spectrum::N;
// The χ² harness and the other checks below serve only the unit tests; the albedo estimate
// and `direction` also serve `ophis bsdf`.
#[cfg(test)]
use {
    super::BsdfSample,
    crate::math::{warp, Vec2, PI},
    crate::spectrum::SampledSpectrum,
};

#[cfg(test)]
/// Parameters of a χ² test.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Chi2Config {
    /// Number of bins in cos θ over [−1, 1].
    pub cos_bins: usize,
    /// Number of bins in φ over [0, 2π).
    pub phi_bins: usize,
    /// Number of calls to `sample_f`.
    pub samples: usize,
    /// Seed of the random stream.
    pub seed: u64,
    /// Number of χ² tests in the suite, for the Šidák correction.
    pub test_count: usize,
    /// Family-wise significance level.
    pub significance: f64,
}

#[cfg(test)]
impl Default for Chi2Config {
    fn default() -> Self {
        Chi2Config {
            cos_bins: 20,
            phi_bins: 40,
            samples: 100_000,
            seed: 1,
            test_count: 1,
            significance: 0.01,
        }
    }
}

#[cfg(test)]
/// What a χ² test found.
#[derive(Clone, Debug)]
pub(crate) struct Chi2Outcome {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// Per-test significance after the Šidák correction.
    pub threshold: f64,
    /// Fraction of samples that came from delta lobes.
    pub delta_fraction: f64,
    /// Fraction of calls to `sample_f` that returned no sample.
    pub failed_fraction: f64,
    /// ∫ pdf over the sphere.
    pub pdf_integral: f64,
}

#[cfg(test)]
/// Runs the χ² test; `Err` explains a failure (low p-value, samples where pdf = 0, or samples
/// whose `f`/`pdf` disagree with evaluation).
pub(crate) fn chi2_test(
    bxdf: &Bxdf,
    wo: Vec3,
    mode: TransportMode,
    cfg: &Chi2Config,
) -> Result<Chi2Outcome, String> {
    chi2_test_against(bxdf, bxdf, wo, mode, cfg)
}

#[cfg(test)]
/// [`chi2_test`] of `sampler`'s directions against the density `pdf()` of another BSDF,
/// `density` (e.g. a stochastic BSDF's sampler against a closed form of the same model).
pub(crate) fn chi2_test_against(
    sampler: &Bxdf,
    density: &Bxdf,
    wo: Vec3,
    mode: TransportMode,
    cfg: &Chi2Config,
) -> Result<Chi2Outcome, String> {
    chi2_test_fns(
        |uc, u| sampler.sample_f(wo, uc, u, mode),
        |wi| sampler.pdf(wo, wi, mode),
        |wi| sampler.f(wo, wi, mode),
        |wi| density.pdf(wo, wi, mode),
        cfg,
    )
}

#[cfg(test)]
/// The χ² test on functions: `sample` draws a direction from (uc, u), `pdf` and `f` are what
/// the sampler claims to have used (checked sample by sample unless the sample's pdf is only
/// proportional), and `density` is integrated over the bins for the expected counts (e.g. a
/// sampler that takes extra parameters, as `Bxdf::sample_f_weighted`).
pub(crate) fn chi2_test_fns(
    mut sample: impl FnMut(f32, Vec2) -> Option<BsdfSample>,
    pdf: impl Fn(Vec3) -> f32,
    f: impl Fn(Vec3) -> SampledSpectrum,
    density: impl Fn(Vec3) -> f32,
    cfg: &Chi2Config,
) -> Result<Chi2Outcome, String> {
    let (nc, np) = (cfg.cos_bins, cfg.phi_bins);
    let mut obs = vec![0.0f64; nc * np];
    let mut rng = Pcg32::new(cfg.seed, 0x5eed);
    let (mut n_delta, mut n_fail) = (0usize, 0usize);
    for _ in 0..cfg.samples {
        let uc = rng.next_f32();
        let u = rng.next_vec2();
        let Some(bs) = sample(uc, u) else {
            n_fail += 1;
            continue;
        };
        if bs.is_specular() {
            n_delta += 1;
            continue;
        }
        if bs.pdf.is_nan() || bs.pdf <= 0.0 || !bs.f.is_finite() {
            return Err(format!(
                "non-delta sample {:?} with pdf {} f {:?}",
                bs.wi, bs.pdf, bs.f
            ));
        }
        if !bs.pdf_is_proportional {
            // Sampling and evaluation are the same formulas in f32; 1e-3 relative covers the
            // rounding of recomputing the half vector.
            let (p, fv) = (pdf(bs.wi), f(bs.wi));
            let close = |a: f32, b: f32| (a - b).abs() <= 1e-3 * a.abs().max(b.abs()) + 1e-12;
            if !close(p, bs.pdf) || (0..N).any(|i| !close(fv[i], bs.f[i])) {
                return Err(format!(
                    "sample_f disagrees with f/pdf at wi {:?}: pdf {} vs {}, f {:?} vs {:?}",
                    bs.wi, bs.pdf, p, bs.f, fv
                ));
            }
        }
        let w = bs.wi.normalize();
        obs[cell_of(w, nc, np)] += 1.0;
    }

    let n = cfg.samples as f64;
    let tol = 0.02 / n;
    let mut exp = vec![0.0f64; nc * np];
    for ic in 0..nc {
        for ip in 0..np {
            let c0 = -1.0 + 2.0 * ic as f64 / nc as f64;
            let c1 = -1.0 + 2.0 * (ic + 1) as f64 / nc as f64;
            let p0 = 2.0 * std::f64::consts::PI * ip as f64 / np as f64;
            let p1 = 2.0 * std::f64::consts::PI * (ip + 1) as f64 / np as f64;
            let mut g = |c: f64, p: f64| {
                let s = (1.0 - c * c).max(0.0).sqrt();
                let w = Vec3::new((s * p.cos()) as f32, (s * p.sin()) as f32, c as f32);
                density(w) as f64
            };
            exp[ic * np + ip] = n * integrate_cell(&mut g, c0, c1, p0, p1, tol);
        }
    }
    let pdf_integral = exp.iter().sum::<f64>() / n;

    // Categories: histogram cells plus "not in the histogram".
    let mut cats: Vec<(f64, f64)> = obs.iter().copied().zip(exp.iter().copied()).collect();
    let outside_obs = (n_delta + n_fail) as f64;
    cats.push((outside_obs, (n - pdf_integral * n).max(0.0)));
    for &(o, e) in &cats {
        if e < 1e-9 && o > 0.0 {
            return Err(format!("{o} samples where the expected count is {e:.2e}"));
        }
    }
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    let mut big: Vec<(f64, f64)> = Vec::new();
    for &(o, e) in &cats {
        if e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            big.push((o, e));
        }
    }
    if pool_e >= 5.0 {
        big.push((pool_o, pool_e));
    } else if let Some(smallest) = big.iter_mut().min_by(|a, b| a.1.total_cmp(&b.1)) {
        // A pool still too small for the χ² approximation joins the smallest adequate cell.
        smallest.0 += pool_o;
        smallest.1 += pool_e;
    }
    let stat: f64 = big.iter().map(|&(o, e)| (o - e) * (o - e) / e).sum();
    let used = big.len();
    let dof = used.saturating_sub(1).max(1);
    let p_value = gamma_q(0.5 * dof as f64, 0.5 * stat);
    let threshold = 1.0 - (1.0 - cfg.significance).powf(1.0 / cfg.test_count as f64);
    let out = Chi2Outcome {
        statistic: stat,
        dof,
        p_value,
        threshold,
        delta_fraction: n_delta as f64 / n,
        failed_fraction: n_fail as f64 / n,
        pdf_integral,
    };
    if p_value < threshold {
        return Err(format!(
            "χ² rejected: statistic {:.1} over {} degrees of freedom, p = {:.2e} below the \
             corrected significance {:.2e} ({out:?})",
            out.statistic, out.dof, out.p_value, out.threshold
        ));
    }
    Ok(out)
}

#[cfg(test)]
fn cell_of(w: Vec3, nc: usize, np: usize) -> usize {
    let c = w.z.clamp(-1.0, 1.0) as f64;
    let ic = (((c + 1.0) * 0.5 * nc as f64) as usize).min(nc - 1);
    let mut phi = (w.y as f64).atan2(w.x as f64);
    if phi < 0.0 {
        phi += 2.0 * std::f64::consts::PI;
    }
    let ip = ((phi / (2.0 * std::f64::consts::PI) * np as f64) as usize).min(np - 1);
    ic * np + ip
}

#[cfg(test)]
/// ∫∫ g over a rectangle: 4×4 starting pieces, each refined adaptively by Simpson's rule.
fn integrate_cell(
    g: &mut impl FnMut(f64, f64) -> f64,
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    tol: f64,
) -> f64 {
    let k = 4;
    let (hx, hy) = ((x1 - x0) / k as f64, (y1 - y0) / k as f64);
    let mut s = 0.0;
    for i in 0..k {
        for j in 0..k {
            let (a0, b0) = (x0 + i as f64 * hx, y0 + j as f64 * hy);
            let whole = simpson(g, a0, a0 + hx, b0, b0 + hy);
            s += adapt(g, a0, a0 + hx, b0, b0 + hy, whole, tol / 16.0, 10);
        }
    }
    s
}

#[cfg(test)]
fn simpson(g: &mut impl FnMut(f64, f64) -> f64, x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    let (xm, ym) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let w = [1.0, 4.0, 1.0];
    let xs = [x0, xm, x1];
    let ys = [y0, ym, y1];
    let mut s = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            s += w[i] * w[j] * g(xs[i], ys[j]);
        }
    }
    s * (x1 - x0) * (y1 - y0) / 36.0
}

#[cfg(test)]
#[allow(clippy::too_many_arguments)]
fn adapt(
    g: &mut impl FnMut(f64, f64) -> f64,
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let (xm, ym) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let q = [
        simpson(g, x0, xm, y0, ym),
        simpson(g, xm, x1, y0, ym),
        simpson(g, x0, xm, ym, y1),
        simpson(g, xm, x1, ym, y1),
    ];
    let sum: f64 = q.iter().sum();
    if depth == 0 || (sum - whole).abs() <= 15.0 * tol {
        return sum + (sum - whole) / 15.0;
    }
    let t = tol / 2.0;
    adapt(g, x0, xm, y0, ym, q[0], t, depth - 1)
        + adapt(g, xm, x1, y0, ym, q[1], t, depth - 1)
        + adapt(g, x0, xm, ym, y1, q[2], t, depth - 1)
        + adapt(g, xm, x1, ym, y1, q[3], t, depth - 1)
}

#[cfg(test)]
/// ln Γ(x) for x > 0 (Lanczos approximation, g = 7, nine terms; relative error ~1e-15).
pub(crate) fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection formula.
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    let t = x + 7.5;
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

#[cfg(test)]
/// Regularised upper incomplete gamma Q(a, x) = Γ(a, x)/Γ(a): the series of P for x < a + 1,
/// a Lentz continued fraction for Q otherwise.
pub(crate) fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_pre = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        (1.0 - sum * log_pre.exp()).max(0.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (log_pre.exp() * h).clamp(0.0, 1.0)
    }
}

/// A Monte Carlo mean with its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub mean: f64,
    pub std_err: f64,
}

impl Estimate {
    fn from_sums(s: f64, s2: f64, n: usize) -> Estimate {
        let n = n as f64;
        let mean = s / n;
        let var = (s2 / n - mean * mean).max(0.0);
        Estimate {
            mean,
            std_err: (var / (n - 1.0).max(1.0)).sqrt(),
        }
    }
    #[cfg(test)]
    /// The mean of `n` draws of `x` and its standard error.
    pub(crate) fn of(n: usize, mut x: impl FnMut() -> f64) -> Estimate {
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let v = x();
            s += v;
            s2 += v * v;
        }
        Estimate::from_sums(s, s2, n)
    }
    #[cfg(test)]
    /// Whether two independent estimates agree within `k` combined standard errors.
    pub(crate) fn agrees_with(&self, o: &Estimate, k: f64) -> bool {
        (self.mean - o.mean).abs() <= k * (self.std_err.powi(2) + o.std_err.powi(2)).sqrt()
    }
    #[cfg(test)]
    /// Whether the estimate is compatible with a true value ≤ `bound` at `k` standard errors.
    pub(crate) fn at_most(&self, bound: f64, k: f64) -> bool {
        self.mean <= bound + k * self.std_err
    }
}

/// Mean and standard error per channel of `n` draws of `sample`, each drawing from `rng`.
fn per_channel(
    n: usize,
    mut rng: Pcg32,
    mut sample: impl FnMut(&mut Pcg32) -> [f64; N],
) -> [Estimate; N] {
    let mut s = [0.0f64; N];
    let mut s2 = [0.0f64; N];
    for _ in 0..n {
        let v = sample(&mut rng);
        for i in 0..N {
            s[i] += v[i];
            s2[i] += v[i] * v[i];
        }
    }
    std::array::from_fn(|i| Estimate::from_sums(s[i], s2[i], n))
}

/// Directional albedo E[f·|cos θi|/pdf] under `sample_f` (failed samples count 0). With
/// `include_delta = false` only non-delta samples contribute, which estimates the same
/// quantity as [`hemispherical_integral`].
pub fn albedo(
    bxdf: &Bxdf,
    wo: Vec3,
    mode: TransportMode,
    n: usize,
    seed: u64,
    include_delta: bool,
) -> [Estimate; N] {
    per_channel(n, Pcg32::new(seed, 0xa1b), |rng| {
        let (uc, u) = (rng.next_f32(), rng.next_vec2());
        match bxdf.sample_f(wo, uc, u, mode) {
            Some(bs) if bs.pdf > 0.0 && (include_delta || !bs.is_specular()) => {
                let w = bs.wi.z.abs() / bs.pdf;
                bs.f.0.map(|v| (v * w) as f64)
            }
            _ => [0.0; N],
        }
    })
}

#[cfg(test)]
/// Asserts reciprocity (see [`reciprocity_error`], below 2·10⁻³) between `n` pairs of uniform
/// random directions from the stream `seed`, of which at least `min_checked` must carry
/// f ≥ 10⁻³ (below that, values are dominated by the f32 rounding of the angles).
pub(crate) fn assert_reciprocal(b: &Bxdf, n: usize, seed: u64, min_checked: usize) {
    let mut rng = Pcg32::new(seed, seed);
    let mut checked = 0;
    for _ in 0..n {
        let a = warp::square_to_uniform_sphere(rng.next_vec2());
        let c = warp::square_to_uniform_sphere(rng.next_vec2());
        if b.f(a, c, TransportMode::Radiance).max_value() < 1e-3 {
            continue;
        }
        checked += 1;
        let e = reciprocity_error(b, a, c);
        assert!(e < 2e-3, "{a:?} {c:?}: {e}");
    }
    assert!(checked > min_checked, "{checked}");
}

#[cfg(test)]
/// Asserts that a lossless BxDF returns all the energy it receives: in importance mode (no 1/η²
/// factor) its albedo, reflection and transmission together, is 1 within 4σ at each incident
/// polar angle `thetas` (degrees, negative from below) and azimuth `phi`, over `n` samples.
pub(crate) fn assert_keeps_all_energy(b: &Bxdf, thetas: &[f32], phi: f32, n: usize, what: &str) {
    for &theta in thetas {
        let a = albedo(
            b,
            direction(theta, phi),
            TransportMode::Importance,
            n,
            3,
            true,
        );
        for e in &a {
            assert!(
                (e.mean - 1.0).abs() <= 4.0 * e.std_err + 1e-5,
                "{what} θ {theta}: {a:?}"
            );
        }
    }
}

#[cfg(test)]
/// ∫ f(wo, wi) |cos θi| dwi over the sphere by uniform sampling (non-delta lobes only).
pub(crate) fn hemispherical_integral(
    bxdf: &Bxdf,
    wo: Vec3,
    mode: TransportMode,
    n: usize,
    seed: u64,
) -> [Estimate; N] {
    per_channel(n, Pcg32::new(seed, 0x4e1), |rng| {
        let wi = warp::square_to_uniform_sphere(rng.next_vec2());
        let f = bxdf.f(wo, wi, mode);
        f.0.map(|v| (v * wi.z.abs() * 4.0 * PI) as f64)
    })
}

#[cfg(test)]
/// Largest relative difference over the channels between f(a, b) in radiance mode and
/// f(b, a) in importance mode (0 when both are below 1e-20, where f32 intermediates run into
/// subnormals and carry no relative precision, and the value is irrelevant to any render).
pub(crate) fn reciprocity_error(bxdf: &Bxdf, a: Vec3, b: Vec3) -> f32 {
    let f1 = bxdf.f(a, b, TransportMode::Radiance);
    let f2 = bxdf.f(b, a, TransportMode::Importance);
    (0..N)
        .map(|i| {
            let m = f1[i].abs().max(f2[i].abs());
            if m < 1e-20 {
                0.0
            } else {
                (f1[i] - f2[i]).abs() / m
            }
        })
        .fold(0.0, f32::max)
}

/// A direction at polar angle `theta_deg` (negative: below the surface) and azimuth `phi`.
pub fn direction(theta_deg: f32, phi: f32) -> Vec3 {
    let t = theta_deg.to_radians();
    let (s, c) = t.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(s.abs() * cp, s.abs() * sp, c.abs() * theta_deg.signum())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_q_known_values() {
        // χ² with 2 dof: Q(1, x/2) = e^{−x/2}.
        for x in [0.5f64, 2.0, 10.0, 40.0] {
            assert!((gamma_q(1.0, x / 2.0) - (-x / 2.0).exp()).abs() < 1e-12);
        }
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-12);
        // Q(a, a) → 1/2 for large a; the χ² median is ≈ dof (1 − 2/(9 dof))³.
        let dof = 800.0f64;
        let med = dof * (1.0 - 2.0 / (9.0 * dof)).powi(3);
        assert!((gamma_q(dof / 2.0, med / 2.0) - 0.5).abs() < 1e-3);
    }
}
