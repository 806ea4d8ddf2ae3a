//! The random walk against the closed form (research/layered.md §3.1), furnace, reciprocity,
//! χ² of its directions against the exact pdf, and a rough, scattering stack (energy,
//! reciprocity, weighted-histogram consistency of `sample_f` with `f`).

use super::tests::{base, closed, coat, splat, RAD};
use super::*;
use crate::bsdf::microfacet::{MicrofacetDistribution, MicrofacetType};
use crate::bsdf::testing::{self, direction, Chi2Config, Estimate};
use crate::math::Pcg32;

fn walk(tau: f32, rho: f32) -> Bxdf {
    let l = LayeredBxdf::new(
        vec![coat(1.5), base(rho)],
        &[Medium::absorbing(splat(tau))],
        DEFAULT_MAX_DEPTH,
        false,
        CoatModel::Walk,
        0,
    )
    .unwrap();
    assert!(matches!(l.model, LayeredModel::Walk(_)));
    Bxdf::Layered(l)
}

/// GGX α = 0.3 coat over a scattering medium over a Lambertian base.
fn rough_scattering() -> Bxdf {
    let top = Bxdf::rough_dielectric(
        MicrofacetDistribution::new(MicrofacetType::Ggx, 0.3, 0.3),
        1.5,
        splat(1.0),
        splat(1.0),
    );
    let m = Medium {
        sigma_t: SampledSpectrum([0.5, 1.0, 1.5, 2.0]),
        albedo: splat(0.8),
        g: 0.3,
    };
    let l = LayeredBxdf::new(
        vec![top, base(0.7)],
        &[m],
        DEFAULT_MAX_DEPTH,
        true,
        CoatModel::Walk,
        0,
    )
    .unwrap();
    Bxdf::Layered(l)
}

/// `f` of a stochastic BSDF with a fresh seed from `rng` (its value at a pair is a
/// deterministic function of its seed).
fn f_fresh(b: &Bxdf, wo: Vec3, wi: Vec3, rng: &mut Pcg32) -> SampledSpectrum {
    let mut b = b.clone();
    b.reseed((rng.next_u32() as u64) << 32 | rng.next_u32() as u64);
    b.f(wo, wi, RAD)
}

/// Mean and standard error of channel 0 of `n` calls.
fn mean_of(n: usize, mut f: impl FnMut() -> f32) -> Estimate {
    Estimate::of(n, || f() as f64)
}

fn close(e: &Estimate, want: f64, what: &str) {
    assert!(
        (e.mean - want).abs() <= 4.0 * e.std_err + 1e-6 * want.abs(),
        "{what}: {e:?} vs {want}"
    );
}

#[test]
fn walk_matches_closed_form() {
    let mut rng = Pcg32::new(9, 9);
    for (it, tau) in [0.0f32, 0.7, 1.4].into_iter().enumerate() {
        let (w, c) = (walk(tau, 0.5), closed(tau, 0.5));
        for theta in [0.0f32, 45.0, 85.0] {
            let wo = direction(theta, 0.0);
            let a = testing::albedo(&w, wo, RAD, 20_000, 100 + it as u64, true);
            close(
                &a[0],
                c.albedo(wo.z)[0] as f64,
                &format!("albedo τ {tau} θ {theta}"),
            );
        }
        for (ti, to) in [
            (0.0, 0.0),
            (45.0, 45.0),
            (30.0, 60.0),
            (60.0, 30.0),
            (0.0, 80.0),
        ] {
            let (wo, wi) = (direction(ti, 0.0), direction(to, 2.5));
            let want = c.f(wo, wi)[0] as f64;
            let e = mean_of(4_000, || f_fresh(&w, wo, wi, &mut rng)[0]);
            close(&e, want, &format!("f({ti},{to}) τ {tau}"));
            // The estimator must be sharp enough for the comparison to mean something.
            assert!(e.std_err < 0.05 * want, "f({ti},{to}) τ {tau}: {e:?}");
        }
    }
}

#[test]
fn walk_white_furnace() {
    let w = walk(0.0, 1.0);
    for (i, theta) in [0.0f32, 85.0].into_iter().enumerate() {
        let wo = direction(theta, 0.0);
        let a = testing::albedo(&w, wo, RAD, 20_000, 200 + i as u64, true);
        close(&a[0], 1.0, &format!("sampled albedo θ {theta}"));
        // The non-delta part by integrating f: 1 − F(μ).
        let h = testing::hemispherical_integral(&w, wo, RAD, 40_000, 300 + i as u64);
        let f = crate::bsdf::fresnel::fresnel_dielectric(wo.z, 1.5) as f64;
        close(&h[0], 1.0 - f, &format!("∫f cos θ {theta}"));
    }
}

#[test]
fn walk_directions_follow_the_exact_pdf() {
    // White base, no absorption: weights are all 1, roulette never fires, so the walk's
    // directions must have exactly the closed form's density (research/layered.md §3.3).
    let w = walk(0.0, 1.0);
    let c = Bxdf::Layered(LayeredBxdf {
        model: LayeredModel::Closed(closed(0.0, 1.0)),
        seed: 0,
    });
    for (i, theta) in [20.0f32, 70.0].into_iter().enumerate() {
        let cfg = Chi2Config {
            seed: 50 + i as u64,
            test_count: 2,
            ..Chi2Config::default()
        };
        testing::chi2_test_against(&w, &c, direction(theta, 0.4), RAD, &cfg).unwrap();
    }
}

fn reciprocity(b: &Bxdf, pairs: &[(f32, f32)], n: usize, seed: u64) {
    let mut rng = Pcg32::new(seed, 1);
    for &(ta, tb) in pairs {
        let (a, bb) = (direction(ta, 0.3), direction(tb, 2.0));
        let x = mean_of(n, || f_fresh(b, a, bb, &mut rng)[0]);
        let y = mean_of(n, || f_fresh(b, bb, a, &mut rng)[0]);
        assert!(
            x.agrees_with(&y, 4.0),
            "f({ta},{tb}) {x:?} vs f({tb},{ta}) {y:?}"
        );
        assert!(x.mean > 0.0 && x.std_err < 0.1 * x.mean, "{x:?}");
    }
}

#[test]
fn walk_reciprocity_smooth_and_rough() {
    reciprocity(&walk(0.7, 0.5), &[(10.0, 70.0), (40.0, 80.0)], 4_000, 1);
    reciprocity(
        &rough_scattering(),
        &[(10.0, 70.0), (40.0, 80.0), (20.0, 30.0)],
        6_000,
        2,
    );
}

#[test]
fn rough_scattering_stack_energy_and_consistency() {
    let b = rough_scattering();
    assert!(matches!(&b, Bxdf::Layered(l) if matches!(l.model, LayeredModel::Walk(_))));
    let mut rng = Pcg32::new(5, 5);
    for (i, theta) in [0.0f32, 60.0].into_iter().enumerate() {
        let wo = direction(theta, 0.0);
        let a = testing::albedo(&b, wo, RAD, 20_000, 400 + i as u64, true);
        assert!(a[0].at_most(1.0, 4.0) && a[0].mean > 0.1, "{a:?}");
        // Weighted histogram over cos θ: Σ sample weights per bin vs ∫_bin f cos (uniform).
        const BINS: usize = 5;
        let n = 20_000;
        let mut hist = [[0.0f64; 2]; BINS];
        for _ in 0..n {
            let (uc, u) = (rng.next_f32(), rng.next_vec2());
            let bs = b.sample_f(wo, uc, u, RAD);
            if let Some(bs) = bs.filter(|s| s.wi.z > 0.0) {
                let v = (bs.f[0] * bs.wi.z / bs.pdf) as f64;
                let k = ((bs.wi.z * BINS as f32) as usize).min(BINS - 1);
                hist[k][0] += v;
                hist[k][1] += v * v;
            }
        }
        for (k, h) in hist.iter().enumerate() {
            let m = h[0] / n as f64;
            let sampled = Estimate {
                mean: m,
                std_err: ((h[1] / n as f64 - m * m) / (n as f64 - 1.0)).sqrt(),
            };
            // Uniform in cos θ ∈ bin and φ: density 1/(2π Δ).
            let (lo, width) = (k as f32 / BINS as f32, 1.0 / BINS as f32);
            let eval = mean_of(8_000, || {
                let c = lo + width * rng.next_f32();
                let phi = 2.0 * crate::math::PI * rng.next_f32();
                let s = (1.0 - c * c).max(0.0).sqrt();
                let wi = Vec3::new(s * phi.cos(), s * phi.sin(), c);
                f_fresh(&b, wo, wi, &mut rng)[0] * c * 2.0 * crate::math::PI * width
            });
            assert!(
                sampled.agrees_with(&eval, 4.0),
                "θ {theta} bin {k}: sampled {sampled:?} vs f {eval:?}"
            );
        }
    }
}
