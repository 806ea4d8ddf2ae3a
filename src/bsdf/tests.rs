//! Cross-cutting statistical tests of the BSDFs: χ² fit of sampling against `pdf`, furnace and
//! energy bounds, eval/sample consistency, reciprocity, delta-lobe weights.
//!
//! Tolerances: 4 standard errors estimated from the samples, or for deterministic identities
//! the f32 rounding of the formulas involved (stated where used).

use super::fresnel::{fresnel_conductor, fresnel_dielectric, ConductorFresnel};
use super::microfacet::{MicrofacetDistribution, MicrofacetType};
use super::testing::{
    albedo, chi2_test, direction, hemispherical_integral, reciprocity_error, Chi2Config,
};
use super::*;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::TexCoord;

use TransportMode::{Importance, Radiance};

const ETA: f32 = 1.5;
const ANGLES: [f32; 3] = [10.0, 45.0, 80.0];
const ANGLES_BELOW: [f32; 2] = [-20.0, -60.0];
const ALPHAS: [(f32, f32); 4] = [(0.05, 0.05), (0.2, 0.2), (0.6, 0.6), (0.1, 0.4)];
const KINDS: [MicrofacetType; 2] = [MicrofacetType::Ggx, MicrofacetType::Beckmann];
const PLASTIC_ALPHAS: [f32; 3] = [0.05, 0.2, 0.6];

/// Number of χ² tests below, for the Šidák correction (checked by `chi2_test_count`).
const CHI2_TESTS: usize = ANGLES.len() // diffuse
    + ANGLES.len() // plastic
    + 2 * ALPHAS.len() * ANGLES.len() // rough conductor
    + 2 * ALPHAS.len() * (ANGLES.len() + ANGLES_BELOW.len()) // rough dielectric
    + 2 * PLASTIC_ALPHAS.len() * ANGLES.len(); // rough plastic

const CHI2_SAMPLES: usize = 60_000;

fn s(v: f32) -> SampledSpectrum {
    SampledSpectrum::splat(v)
}

fn cfg(seed: u64) -> Chi2Config {
    Chi2Config {
        cos_bins: 20,
        phi_bins: 40,
        samples: CHI2_SAMPLES,
        seed,
        test_count: CHI2_TESTS,
        significance: 0.01,
    }
}

fn chi2(b: &Bxdf, theta: f32, mode: TransportMode, seed: u64) {
    let wo = direction(theta, 0.4);
    if let Err(e) = chi2_test(b, wo, mode, &cfg(seed)) {
        panic!("{b:?} θo = {theta}°: {e}");
    }
}

fn rough_conductor(kind: MicrofacetType, a: (f32, f32)) -> Bxdf {
    Bxdf::rough_conductor(
        MicrofacetDistribution::new(kind, a.0, a.1),
        ConductorFresnel::Complex {
            eta: s(0.2),
            k: s(3.0),
        },
        s(1.0),
    )
}

fn rough_dielectric(kind: MicrofacetType, a: (f32, f32)) -> Bxdf {
    Bxdf::rough_dielectric(
        MicrofacetDistribution::new(kind, a.0, a.1),
        ETA,
        s(1.0),
        s(1.0),
    )
}

fn plastic(rho: f32, nonlinear: bool) -> Bxdf {
    let fdr = fresnel::fresnel_diffuse_reflectance(1.0 / ETA);
    Bxdf::Plastic(plastic::PlasticBxdf::new(
        None,
        ETA,
        s(rho),
        s(1.0),
        fdr,
        nonlinear,
    ))
}

fn rough_plastic(kind: MicrofacetType, a: f32, rho: f32) -> Bxdf {
    let fdr = fresnel::fresnel_diffuse_reflectance(1.0 / ETA);
    Bxdf::Plastic(plastic::PlasticBxdf::new(
        Some(MicrofacetDistribution::new(kind, a, a)),
        ETA,
        s(rho),
        s(1.0),
        fdr,
        false,
    ))
}

#[test]
fn chi2_test_count() {
    assert_eq!(CHI2_TESTS, 3 + 3 + 24 + 40 + 18);
}

#[test]
fn chi2_diffuse_and_plastic() {
    let d = Bxdf::Diffuse(diffuse::DiffuseBxdf::new(s(0.7)));
    for (i, &t) in ANGLES.iter().enumerate() {
        chi2(&d, t, Radiance, 100 + i as u64);
        // The χ² includes the delta lobe's share as its own category; check it on its own too:
        // the fraction of delta samples is binomial with mean 1 − ∫pdf (4σ).
        let o = chi2_test(
            &plastic(0.5, false),
            direction(t, 0.4),
            Radiance,
            &cfg(200 + i as u64),
        )
        .unwrap_or_else(|e| panic!("plastic θo = {t}°: {e}"));
        let q = 1.0 - o.pdf_integral;
        let sigma = (q * (1.0 - q) / CHI2_SAMPLES as f64).sqrt();
        assert!(
            o.failed_fraction == 0.0 && (o.delta_fraction - q).abs() <= 4.0 * sigma,
            "{o:?}"
        );
    }
}

/// χ² of `make(kind, α)` at each of `ANGLES`, for both distributions and each roughness,
/// with seeds counting up from `seed` + 1.
fn chi2_each_kind<A: Copy>(alphas: &[A], mut seed: u64, make: impl Fn(MicrofacetType, A) -> Bxdf) {
    for kind in KINDS {
        for &a in alphas {
            for t in ANGLES {
                seed += 1;
                chi2(&make(kind, a), t, Radiance, seed);
            }
        }
    }
}

#[test]
fn chi2_rough_conductor() {
    chi2_each_kind(&ALPHAS, 300, rough_conductor);
}

fn chi2_rough_dielectric(kind: MicrofacetType, seed0: u64) {
    let mut seed = seed0;
    for a in ALPHAS {
        for t in ANGLES.iter().chain(ANGLES_BELOW.iter()) {
            seed += 1;
            chi2(&rough_dielectric(kind, a), *t, Radiance, seed);
        }
    }
}

#[test]
fn chi2_rough_dielectric_ggx() {
    chi2_rough_dielectric(MicrofacetType::Ggx, 400);
}

#[test]
fn chi2_rough_dielectric_beckmann() {
    chi2_rough_dielectric(MicrofacetType::Beckmann, 500);
}

#[test]
fn chi2_rough_plastic() {
    chi2_each_kind(&PLASTIC_ALPHAS, 600, |kind, a| rough_plastic(kind, a, 0.5));
}

#[test]
fn smooth_dielectric_weights_sum_to_one() {
    let b = Bxdf::dielectric(ETA, s(1.0), s(1.0));
    for theta in [0.0f32, 30.0, 60.0, 85.0, -10.0, -40.0, -45.0, -80.0] {
        let wo = direction(theta, 1.1);
        let r = fresnel_dielectric(wo.z, ETA);
        let u = crate::math::Vec2::ZERO;
        // Just below and above the threshold uc = F: reflection, then transmission.
        let bs_r = b.sample_f(wo, (r - 1e-4).max(0.0), u, Radiance).unwrap();
        assert!(bs_r.flags == BxdfFlags::SPECULAR_REFLECTION);
        assert!((bs_r.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-6);
        let w_r = bs_r.f[0] * bs_r.wi.z.abs() / bs_r.pdf;
        assert!((w_r - 1.0).abs() < 1e-6, "reflection weight {w_r}");
        if r >= 1.0 {
            // Total internal reflection: every sample reflects.
            assert!(theta < 0.0 && (wo.z.abs() < (1.0 - 1.0 / (ETA * ETA)).sqrt()));
            let bs = b.sample_f(wo, 0.999, u, Radiance).unwrap();
            assert!(bs.flags == BxdfFlags::SPECULAR_REFLECTION);
            continue;
        }
        for mode in [Radiance, Importance] {
            let bs_t = b.sample_f(wo, (r + 1e-4).min(0.9999), u, mode).unwrap();
            assert!(bs_t.flags == BxdfFlags::SPECULAR_TRANSMISSION);
            let etap = if wo.z > 0.0 { ETA } else { 1.0 / ETA };
            // Snell: sin θt = sin θo / η'.
            let so = (1.0 - wo.z * wo.z).sqrt();
            let st = (1.0 - bs_t.wi.z * bs_t.wi.z).sqrt();
            assert!((st * etap - so).abs() < 1e-5 && bs_t.wi.z * wo.z < 0.0);
            let w_t = bs_t.f[0] * bs_t.wi.z.abs() / bs_t.pdf;
            let expect = if mode == Radiance {
                1.0 / (etap * etap)
            } else {
                1.0
            };
            assert!((w_t - expect).abs() < 1e-5, "transmission weight {w_t}");
        }
        // Importance-mode furnace: all weights are 1, so R + T = 1 exactly.
        let a = albedo(&b, wo, Importance, 2000, 5, true);
        assert!((a[0].mean - 1.0).abs() < 1e-5 && a[0].std_err < 1e-6);
        // The fraction of reflections is F (binomial, 4σ).
        let n = 20_000;
        let mut rr = crate::math::Pcg32::new(9, 2);
        let k = (0..n)
            .filter(|_| {
                let bs = b.sample_f(wo, rr.next_f32(), u, Radiance).unwrap();
                bs.flags == BxdfFlags::SPECULAR_REFLECTION
            })
            .count() as f64;
        let sigma = (r as f64 * (1.0 - r as f64) / n as f64).sqrt();
        assert!((k / n as f64 - r as f64).abs() <= 4.0 * sigma + 1.0 / n as f64);
    }
}

#[test]
fn thin_dielectric_conserves_energy() {
    let b = fresnel::ThinSheetFresnel { eta: ETA };
    let bx = Bxdf::ThinDielectric(smooth::Smooth::new(b, s(1.0), s(1.0)));
    for theta in [0.0f32, 45.0, 80.0, -30.0] {
        let wo = direction(theta, 0.3);
        let r = fresnel_dielectric(wo.z.abs(), ETA);
        // R + T²R/(1 − R²) = 2R/(1 + R).
        assert!((b.sheet_reflectance(wo.z) - 2.0 * r / (1.0 + r)).abs() < 1e-6);
        let a = albedo(&bx, wo, Radiance, 5000, 3, true);
        assert!((a[0].mean - 1.0).abs() < 1e-5 && a[0].std_err < 1e-6);
        let bs = bx
            .sample_f(wo, 0.9999, crate::math::Vec2::ZERO, Radiance)
            .unwrap();
        assert!(
            (bs.wi + wo).length() < 1e-6,
            "transmission goes straight through"
        );
    }
}

#[test]
fn smooth_conductor_weight_is_fresnel() {
    let (eta, k) = (s(0.4), s(2.4));
    for theta in [0.0f32, 50.0, 85.0] {
        let wo = direction(theta, 2.0);
        for (fr, expect) in [
            (ConductorFresnel::Mirror, 1.0),
            (
                ConductorFresnel::Complex { eta, k },
                fresnel_conductor(wo.z, eta, k)[0],
            ),
        ] {
            let b = Bxdf::conductor(fr, s(1.0));
            let bs = b
                .sample_f(wo, 0.5, crate::math::Vec2::ZERO, Radiance)
                .unwrap();
            let w = bs.f[0] * bs.wi.z / bs.pdf;
            assert!((w - expect).abs() < 1e-6);
        }
        let below = direction(-theta - 1.0, 2.0);
        let b = Bxdf::conductor(ConductorFresnel::Mirror, s(1.0));
        assert!(b
            .sample_f(below, 0.5, crate::math::Vec2::ZERO, Radiance)
            .is_none());
    }
}

#[test]
fn white_diffuse_albedo_is_one() {
    let b = Bxdf::Diffuse(diffuse::DiffuseBxdf::new(s(1.0)));
    for theta in ANGLES {
        let a = albedo(&b, direction(theta, 0.0), Radiance, 10_000, 1, true);
        // Every weight is ρ·cos/π / (cos/π) = 1 up to f32 rounding.
        assert!((a[0].mean - 1.0).abs() < 1e-5, "{:?}", a[0]);
    }
}

#[test]
fn white_plastic_albedo_is_one() {
    // ρ = 1: specular F plus the internal-reflection series sum to exactly 1; 4σ.
    for nonlinear in [false, true] {
        for theta in [0.0f32, 30.0, 60.0, 85.0] {
            let a = albedo(
                &plastic(1.0, nonlinear),
                direction(theta, 0.0),
                Radiance,
                100_000,
                7,
                true,
            );
            assert!(
                (a[0].mean - 1.0).abs() <= 4.0 * a[0].std_err,
                "θ {theta}: {:?}",
                a[0]
            );
        }
    }
}

#[test]
fn energy_is_bounded() {
    let n = 40_000;
    let mut seed = 10;
    let mut check = |b: &Bxdf, wo: Vec3, mode: TransportMode| {
        seed += 1;
        let a = albedo(b, wo, mode, n, seed, true);
        assert!(a[0].at_most(1.0, 4.0), "{b:?} wo {wo:?}: {:?}", a[0]);
        a[0].mean
    };
    for kind in KINDS {
        for a in ALPHAS {
            let mirror = Bxdf::rough_conductor(
                MicrofacetDistribution::new(kind, a.0, a.1),
                ConductorFresnel::Mirror,
                s(1.0),
            );
            for t in ANGLES {
                check(&mirror, direction(t, 0.2), Radiance);
            }
            for t in ANGLES.iter().chain(ANGLES_BELOW.iter()) {
                check(&rough_dielectric(kind, a), direction(*t, 0.2), Importance);
            }
        }
        for a in PLASTIC_ALPHAS {
            for t in ANGLES {
                check(&rough_plastic(kind, a, 0.8), direction(t, 0.2), Radiance);
            }
        }
    }
    for t in ANGLES {
        check(&plastic(0.8, true), direction(t, 0.0), Radiance);
    }
}

#[test]
fn eval_and_sampling_agree() {
    // E[f·cos/pdf] under sampling = ∫ f cos by uniform sampling; both estimates carry their
    // standard error, compared at 4σ.
    let mut cases: Vec<(Bxdf, f32, TransportMode)> = vec![
        (
            Bxdf::Diffuse(diffuse::DiffuseBxdf::new(s(0.6))),
            40.0,
            Radiance,
        ),
        (plastic(0.6, false), 40.0, Radiance),
    ];
    for kind in KINDS {
        for a in [(0.2, 0.2), (0.6, 0.6), (0.1, 0.4)] {
            cases.push((rough_conductor(kind, a), 30.0, Radiance));
            cases.push((rough_dielectric(kind, a), 30.0, Radiance));
            cases.push((rough_dielectric(kind, a), -50.0, Radiance));
            cases.push((rough_dielectric(kind, a), -20.0, Importance));
        }
        cases.push((rough_plastic(kind, 0.3, 0.6), 60.0, Radiance));
    }
    for (i, (b, t, mode)) in cases.iter().enumerate() {
        let wo = direction(*t, 0.5);
        let a = albedo(b, wo, *mode, 50_000, 20 + i as u64, false);
        let h = hemispherical_integral(b, wo, *mode, 200_000, 40 + i as u64);
        assert!(
            a[0].agrees_with(&h[0], 4.0),
            "{b:?} θ {t}: {:?} vs {:?}",
            a[0],
            h[0]
        );
    }
}

#[test]
fn reciprocity() {
    // f(a, b) in radiance mode equals f(b, a) in importance mode; the formulas are symmetric up
    // to f32 rounding of the half vector and products (relative 1e-3 allows for steep D).
    let mut bxdfs = vec![plastic(0.5, false)];
    for kind in KINDS {
        bxdfs.push(rough_conductor(kind, (0.3, 0.15)));
        bxdfs.push(rough_dielectric(kind, (0.3, 0.15)));
        bxdfs.push(rough_plastic(kind, 0.3, 0.5));
    }
    let mut rng = crate::math::Pcg32::new(77, 0);
    for b in &bxdfs {
        let mut nonzero = 0;
        for _ in 0..2000 {
            let a = crate::math::warp::square_to_uniform_sphere(rng.next_vec2());
            let c = crate::math::warp::square_to_uniform_sphere(rng.next_vec2());
            let e = reciprocity_error(b, a, c);
            assert!(e < 1e-3, "{b:?}: {a:?} {c:?} rel. error {e}");
            if !b.f(a, c, Radiance).is_black() {
                nonzero += 1;
            }
        }
        assert!(nonzero > 100, "the test must see non-zero values");
    }
}

/// Builds the material of one `<bsdf>` through the plugin registry.
fn load(xml: &str) -> Material {
    let scene = format!("<scene version=\"3.0.0\">{xml}</scene>");
    let (root, _) =
        crate::scene::mitsuba::load_str(&scene, std::path::Path::new("t.xml"), &[]).unwrap();
    let node = root
        .children_with_tag(crate::plugin::Tag::Bsdf)
        .next()
        .unwrap();
    crate::plugin::registry::bsdf(node, &mut Vec::new()).unwrap()
}

#[test]
fn materials_evaluate_with_their_parameters() {
    let tc = TexCoord::default();
    let wl = SampledWavelengths::fixed([450.0, 500.0, 550.0, 600.0]);
    let m = load(
        r#"<bsdf type="twosided"><bsdf type="diffuse"><float name="reflectance" value="0.2"/></bsdf>
           <bsdf type="diffuse"><float name="reflectance" value="0.9"/></bsdf></bsdf>"#,
    );
    match m.eval(&tc, &wl, false, 0) {
        (Bxdf::Diffuse(d), true) => assert_eq!(d.r[0], 0.9),
        other => panic!("{other:?}"),
    }
    match m.eval(&tc, &wl, true, 0) {
        (Bxdf::Diffuse(d), true) => assert_eq!(d.r[0], 0.2),
        other => panic!("{other:?}"),
    }
    let g = load(
        r#"<bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1.25"/></bsdf>"#,
    );
    assert!(g.has_delta_only() && g.has_transmission());
    match g.eval(&tc, &wl, true, 0).0 {
        Bxdf::Dielectric(d) => assert!((d.fresnel.eta - 1.2).abs() < 1e-6),
        other => panic!("{other:?}"),
    }
    // The conductor's exterior index under its 3.x name (`ext_ior`) and its 0.6 one.
    for name in ["ext_ior", "ext_eta"] {
        let rc = load(&format!(
            r#"<bsdf type="roughconductor"><string name="distribution" value="ggx"/>
               <float name="alpha_u" value="0.3"/><float name="alpha_v" value="0.1"/>
               <spectrum name="eta" value="0.4"/><spectrum name="k" value="2.4"/>
               <float name="{name}" value="2"/></bsdf>"#
        ));
        match rc.eval(&tc, &wl, true, 0).0 {
            Bxdf::RoughConductor(c) => {
                assert_eq!((c.distrib.alpha_x, c.distrib.alpha_y), (0.3, 0.1));
                match c.fresnel {
                    ConductorFresnel::Complex { eta, k } => {
                        assert!(eta[0] == 0.2 && k[0] == 1.2, "{name}")
                    }
                    _ => panic!(),
                }
            }
            other => panic!("{other:?}"),
        }
    }
    let p = load(r#"<bsdf type="plastic"><float name="int_ior" value="1.5"/></bsdf>"#);
    match p {
        Material::Plastic(p) => assert!(p.fdr_int > 0.55 && p.fdr_int < 0.65),
        _ => unreachable!(),
    }
    assert!(matches!(
        Material::Null.eval(&tc, &wl, true, 0).0,
        Bxdf::Black
    ));
}
