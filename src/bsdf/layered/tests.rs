//! Closed form against research/layered.md §3 (values computed there by independent
//! quadrature and a 2M-path Monte Carlo), its sampler by χ², and the `absorption` BSDF.

use super::closed_form::{CoatOptics, CoatedDiffuse};
use super::*;
use crate::bsdf::absorption::AbsorptionBxdf;
use crate::bsdf::diffuse::DiffuseBxdf;
use crate::bsdf::testing::{self, direction, Chi2Config};

pub(super) const RAD: TransportMode = TransportMode::Radiance;

pub(super) fn splat(v: f32) -> SampledSpectrum {
    SampledSpectrum::splat(v)
}
pub(super) fn coat(eta: f32) -> Bxdf {
    Bxdf::dielectric(eta, splat(1.0), splat(1.0))
}
pub(super) fn base(rho: f32) -> Bxdf {
    Bxdf::Diffuse(DiffuseBxdf::new(splat(rho)))
}
pub(super) fn closed(tau: f32, rho: f32) -> CoatedDiffuse {
    CoatedDiffuse::new(CoatOptics::Dielectric { eta: 1.5 }, splat(rho), splat(tau))
}
pub(super) fn film(tau: f32, rho: f32, lambda: [f32; 4]) -> CoatedDiffuse {
    let coat = CoatOptics::Film {
        eta: 1.5,
        film_ior: [1.8; 4],
        thickness_nm: 300.0,
        lambda,
    };
    CoatedDiffuse::new(coat, splat(rho), splat(tau))
}

#[test]
fn integrals_match_research_values() {
    let c = closed(1.4, 0.5);
    assert!((c.escape[0] - 0.082744).abs() < 2e-6, "E {}", c.escape[0]);
    assert!((c.ret[0] - 0.005453).abs() < 2e-6, "R_r {}", c.ret[0]);
    // τ = 0: E = 1 − F̄_int.
    let c0 = closed(0.0, 0.5);
    assert!(
        (c0.escape[0] - 0.403654).abs() < 2e-6,
        "1 − F̄int {}",
        c0.escape[0]
    );
}

#[test]
fn albedo_matches_research_table() {
    let table = [
        (0.0, [0.316071, 0.084505, 0.049821]),
        (30.0, [0.317156, 0.084110, 0.050530]),
        (45.0, [0.323366, 0.090331, 0.058295]),
        (60.0, [0.351113, 0.125265, 0.095989]),
        (75.0, [0.467861, 0.280991, 0.258032]),
        (85.0, [0.724148, 0.626972, 0.615269]),
    ];
    for (theta, r) in table {
        for (tau, want) in [0.0, 0.7, 1.4].into_iter().zip(r) {
            let got = closed(tau, 0.5).albedo((theta as f32).to_radians().cos())[0];
            assert!(
                (got - want).abs() < 3e-5,
                "θ {theta} τ {tau}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn point_values_and_pdf_match_research_table() {
    let f = |c: &CoatedDiffuse, ti: f32, to: f32| c.f(direction(ti, 0.0), direction(to, 2.0))[0];
    let (c0, c14) = (closed(0.0, 0.5), closed(1.4, 0.5));
    for (ti, to, want0, want14) in [
        (0.0, 0.0, 0.092886, 0.003975),
        (45.0, 45.0, 0.090915, 0.002674),
        (30.0, 60.0, 0.087987, 0.002525),
        (60.0, 30.0, 0.087987, 0.002525),
        (0.0, 80.0, 0.059243, 0.001607),
    ] {
        let (a, b) = (f(&c0, ti, to), f(&c14, ti, to));
        assert!((a - want0).abs() < 1e-5, "f({ti},{to}) τ 0: {a} vs {want0}");
        assert!(
            (b - want14).abs() < 1e-6,
            "f({ti},{to}) τ 1.4: {b} vs {want14}"
        );
    }
    for (ti, to, want) in [
        (0.0, 0.0, 0.322999),
        (45.0, 45.0, 0.223548),
        (30.0, 60.0, 0.152982),
    ] {
        // The table's density picks the delta lobe with F̄(μo); the sampler picks it with
        // F̄/R̄ (its share of the albedo), which scales the diffuse density by (1 − F̄/R̄)/(1 − F̄).
        let mu = direction(ti, 0.0).z;
        let fr = crate::bsdf::fresnel::fresnel_dielectric(mu, 1.5);
        let want = want * (1.0 - fr / c0.albedo(mu)[0]) / (1.0 - fr);
        let p = c0.pdf(direction(ti, 0.0), direction(to, 1.0));
        assert!((p - want).abs() < 2e-5, "pdf({ti},{to}) {p} vs {want}");
    }
}

#[test]
fn white_furnace_closed_form_plain_and_film() {
    for theta in [0.0f32, 30.0, 60.0, 80.0, 89.0] {
        let mu = theta.to_radians().cos();
        let r = closed(0.0, 1.0).albedo(mu)[0];
        assert!((r - 1.0).abs() < 1e-5, "plain θ {theta}: {r}");
        let rf = film(0.0, 1.0, [400.0, 450.0, 550.0, 650.0]).albedo(mu);
        for v in rf.0 {
            assert!((v - 1.0).abs() < 1e-4, "film θ {theta}: {rf:?}");
        }
        // Absorption or a grey base can only lose energy.
        let lossy = film(1.4, 0.5, [400.0, 450.0, 550.0, 650.0]).albedo(mu);
        assert!(lossy.max_value() < 1.0);
    }
}

#[test]
fn film_top_matches_research_table() {
    let lambda = [450.0, 550.0, 650.0, 550.0];
    let r0 = film(0.0, 0.5, lambda);
    let r14 = film(1.4, 0.5, lambda);
    let fr = r0.coat.outside(1.0);
    for (i, (rf, a, b)) in [
        (0.126521, 0.369764, 0.135037),
        (0.041364, 0.309354, 0.050829),
        (0.114102, 0.351013, 0.122312),
    ]
    .into_iter()
    .enumerate()
    {
        assert!((fr[i] - rf).abs() < 2e-5, "R_film {} vs {rf}", fr[i]);
        assert!(
            (r0.albedo(1.0)[i] - a).abs() < 5e-5,
            "{} vs {a}",
            r0.albedo(1.0)[i]
        );
        assert!(
            (r14.albedo(1.0)[i] - b).abs() < 5e-5,
            "{} vs {b}",
            r14.albedo(1.0)[i]
        );
    }
    // A film of zero thickness is the bare coat.
    let bare = CoatedDiffuse::new(
        CoatOptics::Film {
            eta: 1.5,
            film_ior: [1.8; 4],
            thickness_nm: 0.0,
            lambda,
        },
        splat(0.5),
        splat(0.0),
    );
    assert!((bare.albedo(1.0)[1] - 0.316071).abs() < 3e-5);
}

fn closed_bxdf(c: CoatedDiffuse) -> Bxdf {
    Bxdf::Layered(LayeredBxdf {
        model: LayeredModel::Closed(c),
        seed: 0,
    })
}

#[test]
fn closed_form_sampling_chi2_and_albedo() {
    let cases = [
        (closed_bxdf(closed(0.0, 0.5)), 0.0f32),
        (closed_bxdf(closed(1.4, 0.5)), 45.0),
        (closed_bxdf(closed(0.7, 0.5)), 80.0),
        (
            closed_bxdf(film(1.4, 0.5, [450.0, 500.0, 600.0, 700.0])),
            30.0,
        ),
        (
            closed_bxdf(film(0.0, 0.5, [450.0, 500.0, 600.0, 700.0])),
            75.0,
        ),
    ];
    let n = cases.len();
    for (i, (b, theta)) in cases.iter().enumerate() {
        let wo = direction(*theta, 0.3);
        let cfg = Chi2Config {
            seed: 10 + i as u64,
            test_count: n,
            samples: 100_000,
            ..Chi2Config::default()
        };
        let out = testing::chi2_test(b, wo, RAD, &cfg).unwrap_or_else(|e| panic!("case {i}: {e}"));
        assert!(out.delta_fraction > 0.0);
        // Mean sample weight (delta lobe included) = closed-form albedo.
        let est = testing::albedo(b, wo, RAD, 40_000, 77 + i as u64, true);
        let Bxdf::Layered(l) = b else { unreachable!() };
        let LayeredModel::Closed(c) = &l.model else {
            unreachable!()
        };
        let want = c.albedo(wo.z);
        for (j, e) in est.iter().enumerate() {
            let se = e.std_err.max(1e-7);
            assert!(
                (e.mean - want[j] as f64).abs() <= 4.0 * se,
                "case {i} channel {j}: {e:?} vs {}",
                want[j]
            );
        }
    }
}

#[test]
fn absorption_is_the_index_matched_closed_form() {
    let a = AbsorptionBxdf::new(splat(0.6), splat(0.7), 2.0);
    let c = CoatedDiffuse::new(CoatOptics::Dielectric { eta: 1.0 }, splat(0.6), splat(1.4));
    for (ti, to) in [(0.0, 0.0), (30.0, 70.0), (80.0, 10.0)] {
        let (wo, wi) = (direction(ti, 0.0), direction(to, 1.0));
        let (x, y) = (a.f(wo, wi)[0], c.f(wo, wi)[0]);
        assert!((x - y).abs() <= 1e-5 * x.max(1e-6), "{ti},{to}: {x} vs {y}");
    }
    // Thesis parameters: σa = 0.7, d = 2 at normal incidence both ways: ρ/π e^{−2.8}.
    let v = a.f(direction(0.0, 0.0), direction(0.0, 0.0))[0];
    assert!((v - 0.6 / std::f32::consts::PI * (-2.8f32).exp()).abs() < 1e-7);
}

#[test]
fn absorption_chi2_and_energy() {
    let b = Bxdf::Absorption(AbsorptionBxdf::new(splat(0.8), splat(0.3), 1.0));
    for (i, theta) in [10.0f32, 70.0].into_iter().enumerate() {
        let wo = direction(theta, 0.0);
        let cfg = Chi2Config {
            seed: 40 + i as u64,
            test_count: 2,
            ..Chi2Config::default()
        };
        testing::chi2_test(&b, wo, RAD, &cfg).unwrap();
        let e = testing::albedo(&b, wo, RAD, 20_000, 5, true);
        let u = testing::hemispherical_integral(&b, wo, RAD, 200_000, 6);
        assert!(
            e[0].at_most(0.8, 4.0) && e[0].agrees_with(&u[0], 4.0),
            "{e:?} {u:?}"
        );
    }
}

#[test]
fn film_table_interpolation_matches_direct_quadrature() {
    // Off-grid wavelengths and thickness: the per-thread 1 nm table must agree with the
    // quadrature evaluated at the exact values (module header: < 1e-3 relative for fringe
    // periods ≥ 70 nm; a 900 nm keratin-like film has periods ≥ 85 nm over 400–700 nm).
    let lambda = [431.37, 517.82, 603.05, 688.61];
    let coat = CoatOptics::Film {
        eta: 1.5,
        film_ior: [1.56; 4],
        thickness_nm: 901.43,
        lambda,
    };
    let c = CoatedDiffuse::new(coat, splat(0.5), splat(1.4));
    for (i, &l) in lambda.iter().enumerate() {
        let (e, r, _) = super::integrals::film_integrals_1(1.5, 1.56, 901.43, l as f64, 1.4);
        let (got_e, got_r) = (c.escape[i] as f64, c.ret[i] as f64);
        assert!((got_e - e).abs() <= 1e-3 * e, "E at {l}: {got_e} vs {e}");
        assert!(
            (got_r - r).abs() <= 1e-3 * r.max(1e-3),
            "R_r at {l}: {got_r} vs {r}"
        );
    }
}

#[test]
fn film_coat_memo_answers_each_coat_angle_and_side() {
    // The film coat keeps its last two answers per thread. Interleave coats that differ in one
    // value each and both sides (dropping η, the thickness or the side from the memo's key
    // fails this): every answer must be the direct Airy sum
    // of its own coat (film_rt per wavelength, to the few ulp of the 4-lane cosine).
    use crate::optics::thinfilm::film_rt;
    use num_complex::Complex64;
    // η, the third film index, the thickness and the fourth wavelength.
    let coat = |eta: f32, ior: f32, d: f32, l: f32| CoatOptics::Film {
        eta,
        film_ior: [1.56, 1.56, ior, 1.56],
        thickness_nm: d,
        lambda: [431.0, 517.0, 603.0, l],
    };
    let base = coat(1.5, 1.56, 500.0, 688.0);
    // The base coat between variants that differ from it in one value each.
    let coats = [
        base,
        coat(1.33, 1.56, 500.0, 688.0),
        base,
        coat(1.5, 1.8, 500.0, 688.0),
        base,
        coat(1.5, 1.56, 300.0, 688.0),
        base,
        coat(1.5, 1.56, 500.0, 700.0),
        base,
    ];
    let direct = |c: &CoatOptics, mu: f32, inside: bool| -> [f64; 4] {
        let CoatOptics::Film {
            eta,
            film_ior,
            thickness_nm,
            lambda,
        } = *c
        else {
            unreachable!()
        };
        let (n0, n2) = if inside {
            (eta as f64, 1.0)
        } else {
            (1.0, eta as f64)
        };
        std::array::from_fn(|i| {
            let re = |x: f64| Complex64::new(x, 0.0);
            film_rt(
                mu as f64,
                n0,
                re(film_ior[i] as f64),
                thickness_nm as f64,
                re(n2),
                lambda[i] as f64,
            )
            .r()
        })
    };
    // Each coat after its neighbour at the same angle (so a key missing a field answers with
    // the neighbour's value), the angle changing between passes over the coats, from outside
    // and inside in turn, each asked twice (the second time a remembered answer).
    for round in 0..2 {
        for mu in [0.8f32, 0.31] {
            for (k, c) in coats.iter().enumerate() {
                for ask in 0..4 {
                    let inside = ask % 2 == 1;
                    let got = if inside { c.inside(mu) } else { c.outside(mu) };
                    let want = direct(c, mu, inside);
                    for i in 0..4 {
                        assert!(
                            (got[i] as f64 - want[i]).abs() <= 1e-6,
                            "round {round}, ask {ask}, coat {k}, μ {mu}, inside {inside}, \
                             lane {i}: {} vs {}",
                            got[i],
                            want[i]
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn film_integrals_direct_matches_a_fine_sum() {
    // The 4-lane quadrature (its rule sized by the film's fringes) against an independent
    // fine sum: the midpoint rule with 4000 points on each side of the critical cosine, in the
    // same substitution μ = μc + (1 − μc)s² (the midpoint rule's error there, ~h²/24 of the
    // second derivative, is below 1e-6 for these fringes). Films from none to 2 µm, indices
    // from 1.3 to 2.4, dispersive (the index differs per lane) and absorbing slabs. The bound
    // is the 24-point rule's own error on the worst case (6.7e-5: a 2 µm film of 1.3 in a coat
    // less dense than the outside, η = 0.8), which smaller rules must not exceed.
    use super::integrals::{critical_cosines, film_integrals_direct};
    use crate::optics::thinfilm::film_rt;
    use num_complex::Complex64;
    let fine = |mu_c: f64, f: &dyn Fn(f64) -> f64| -> f64 {
        let m = 4000;
        let mut sum = 0.0;
        for j in 0..m {
            let x = (j as f64 + 0.5) / m as f64;
            if mu_c > 0.0 {
                sum += f(mu_c * x) * mu_c / m as f64;
            }
            sum += f(mu_c + (1.0 - mu_c) * x * x) * 2.0 * (1.0 - mu_c) * x / m as f64;
        }
        sum
    };
    let lambda = [383.0f32, 471.5, 566.25, 702.0];
    let mut worst = 0.0f64;
    for eta in [1.33f32, 1.5, 0.8] {
        for n in [1.3f32, 1.56, 2.4] {
            for d in [0.0f32, 60.0, 330.0, 900.0, 2000.0] {
                for tau in [0.0f32, 0.7] {
                    // Dispersion: the index falls towards the red, as keratin's does.
                    let film_ior = lambda.map(|l| n + 4000.0 / (l * l) - 0.01);
                    let taus = SampledSpectrum(lambda.map(|l| tau * 500.0 / l));
                    let coat = CoatOptics::Film {
                        eta,
                        film_ior,
                        thickness_nm: d,
                        lambda,
                    };
                    let (e, r, k) = film_integrals_direct(coat, taus);
                    let (mu_c_in, mu_c_out) = critical_cosines(eta as f64);
                    let r_film = |mu: f64, n0: f64, n2: f64, i: usize| {
                        let nf = Complex64::new(film_ior[i] as f64, 0.0);
                        let n2 = Complex64::new(n2, 0.0);
                        film_rt(mu, n0, nf, d as f64, n2, lambda[i] as f64).r()
                    };
                    let mut k_ref = 0.0;
                    for i in 0..4 {
                        let t = taus[i] as f64;
                        let fi = |mu: f64| r_film(mu, eta as f64, 1.0, i).clamp(0.0, 1.0);
                        let e_ref =
                            fine(mu_c_in, &|mu| 2.0 * mu * (-t / mu).exp() * (1.0 - fi(mu)));
                        let r_ref = fine(mu_c_in, &|mu| 2.0 * mu * (-2.0 * t / mu).exp() * fi(mu));
                        k_ref += fine(mu_c_out, &|mu| {
                            2.0 * mu * (1.0 - r_film(mu, 1.0, eta as f64, i))
                        }) / 4.0;
                        let err = (e[i] as f64 - e_ref).abs().max((r[i] as f64 - r_ref).abs());
                        worst = worst.max(err);
                        assert!(
                            err < 1e-4,
                            "η {eta}, n {n}, d {d}, τ {tau}, λ {}: E {} vs {e_ref}, R {} vs {r_ref}",
                            lambda[i],
                            e[i],
                            r[i]
                        );
                    }
                    assert!(
                        (k as f64 - k_ref).abs() < 1e-4,
                        "η {eta}, n {n}, d {d}: K {k} vs {k_ref}"
                    );
                }
            }
        }
    }
    eprintln!("worst E / R_r error {worst:.2e}");
}

#[test]
fn coated_diffuse_integrates_a_dispersive_film_over_a_coloured_slab() {
    // Keratin-like dispersion and an RGB-like optical depth: the table's rows (one per index
    // and τ) do not serve such a coat, so it takes the 4-lane quadrature; per lane, the
    // integrals must be the 48-point quadrature's at that lane's index and τ.
    let lambda = [412.0f32, 498.5, 577.0, 655.25];
    let film_ior = lambda.map(|l| 1.532 + 5890.0 / (l * l));
    let tau = [2.0f32, 1.6, 1.3, 1.1];
    let coat = CoatOptics::Film {
        eta: 1.45,
        film_ior,
        thickness_nm: 337.5,
        lambda,
    };
    let c = CoatedDiffuse::new(coat, splat(0.5), SampledSpectrum(tau));
    for i in 0..4 {
        let (e, r, _) = super::integrals::film_integrals_1(
            1.45,
            film_ior[i] as f64,
            337.5,
            lambda[i] as f64,
            tau[i] as f64,
        );
        assert!(
            (c.escape[i] as f64 - e).abs() < 1e-4,
            "E at {}: {} vs {e}",
            lambda[i],
            c.escape[i]
        );
        assert!(
            (c.ret[i] as f64 - r).abs() < 1e-4,
            "R_r at {}: {} vs {r}",
            lambda[i],
            c.ret[i]
        );
    }
}
