//! Tests of the film stack: the single-film code at N = 1, conservation, reciprocity, the Bragg
//! mirror's closed forms, limits, and the fast evaluator against the exact path.

use super::filmstack::{FilmStack, Layer, StackItem};
use super::ior::Ior;
use super::thinfilm::{film_rt, FilmRt};
use num_complex::Complex64 as C;

struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 = crate::math::rng::mix64(self.0);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn layer(n: f64, k: f64, d: f64) -> StackItem {
    StackItem::Layer(Layer::new(Ior::complex(n, k).unwrap(), d))
}

/// A random stack of `n` layers: indices 1–2.6, thicknesses 0–400 nm, absorbing with
/// probability `p_abs` (k up to 0.3).
fn random_stack(rng: &mut Rng, n: usize, p_abs: f64, ext: f64, base: Ior) -> FilmStack {
    let items = (0..n)
        .map(|_| {
            let k = if rng.f() < p_abs { 0.3 * rng.f() } else { 0.0 };
            layer(1.0 + 1.6 * rng.f(), k, 400.0 * rng.f())
        })
        .collect();
    FilmStack::new(Ior::Real(ext), items, base).unwrap()
}

fn close(a: &FilmRt, b: &FilmRt, tol: f64) -> bool {
    a.max_diff(b) <= tol
}

#[test]
fn one_layer_is_the_single_film_code_and_the_matrix_agrees_with_it() {
    let mut rng = Rng(11);
    let mut worst: f64 = 0.0;
    for i in 0..4000 {
        let ext = 1.0 + 0.6 * rng.f();
        let film = Ior::complex(
            1.0 + 1.6 * rng.f(),
            if i % 3 == 0 { 0.4 * rng.f() } else { 0.0 },
        )
        .unwrap();
        let d = [0.0, 5.0, 2000.0][i % 3] * rng.f() + if i % 7 == 0 { 0.0 } else { 1.0 };
        let from_inside = i % 4 == 1;
        // Dielectric bases (light may come from them) and metals.
        let base = if i % 4 == 3 {
            Ior::complex(0.1 + 2.0 * rng.f(), 4.0 * rng.f()).unwrap()
        } else {
            Ior::Real(1.0 + 1.6 * rng.f())
        };
        let st = FilmStack::film(Ior::Real(ext), film.clone(), d, base.clone()).unwrap();
        let cos = if i % 50 == 0 { 0.0 } else { rng.f() };
        let l = 360.0 + 470.0 * rng.f();
        let (n0, n2) = if from_inside {
            (base.at(l).re, C::new(ext, 0.0))
        } else {
            (ext, base.at(l))
        };
        let airy = film_rt(cos, n0, film.at(l), d, n2, l);
        assert_eq!(
            st.rt(cos, l, from_inside),
            airy,
            "N = 1 must route to the Airy code"
        );
        let m = st.rt_matrix(cos, l, from_inside);
        worst = worst.max(m.max_diff(&airy));
    }
    assert!(worst < 1e-12, "matrix vs Airy: {worst:e}");
}

#[test]
fn zero_layers_and_zero_thickness_are_the_bare_interface() {
    let bare = |n0: f64, n1: f64| ((n0 - n1) / (n0 + n1)).powi(2);
    let none = FilmStack::new(Ior::Real(1.0), vec![], Ior::Real(1.5)).unwrap();
    assert!((none.rt(1.0, 500.0, false).r() - bare(1.0, 1.5)).abs() < 1e-15);
    // Five layers of zero thickness are no layers, at any angle and from either side.
    let items = (0..5)
        .map(|i| layer(1.2 + 0.3 * i as f64, 0.1 * (i % 2) as f64, 0.0))
        .collect();
    let st = FilmStack::new(Ior::Real(1.0), items, Ior::Real(1.5)).unwrap();
    for cos in [1.0, 0.7, 0.2, 1e-6] {
        for inside in [false, true] {
            let a = st.rt(cos, 480.0, inside);
            let b = none.rt(cos, 480.0, inside);
            assert!(close(&a, &b, 1e-12), "{cos} {inside}: {a:?} {b:?}");
        }
    }
    // …and thin layers approach it: R − R_bare is O(d).
    let thin = |d: f64| {
        let items = vec![layer(2.0, 0.0, d), layer(1.3, 0.0, d)];
        FilmStack::new(Ior::Real(1.0), items, Ior::Real(1.5))
            .unwrap()
            .rt(1.0, 500.0, false)
            .r()
    };
    let e1 = (thin(1e-3) - bare(1.0, 1.5)).abs();
    let e2 = (thin(1e-4) - bare(1.0, 1.5)).abs();
    assert!(e1 < 1e-4 && e2 < 0.2 * e1, "{e1:e} {e2:e}");
}

#[test]
fn energy_is_conserved_and_absorbing_stacks_absorb() {
    let mut rng = Rng(5);
    for i in 0..3000 {
        let n = 2 + i % 9;
        let lossy = i % 2 == 1;
        let (n0, nb) = (1.0 + 0.5 * rng.f(), Ior::Real(1.0 + 1.6 * rng.f()));
        let st = random_stack(&mut rng, n, if lossy { 0.5 } else { 0.0 }, n0, nb);
        let (cos, l, inside) = (rng.f(), 360.0 + 470.0 * rng.f(), i % 3 == 0);
        let rt = st.rt(cos, l, inside);
        for (r, t, a) in [(rt.r_s, rt.t_s, rt.a_s()), (rt.r_p, rt.t_p, rt.a_p())] {
            assert!(
                (0.0..=1.0).contains(&r) && (0.0..=1.0).contains(&t),
                "{rt:?}"
            );
            assert!((r + t + a - 1.0).abs() < 1e-15);
            if lossy {
                assert!(a > -1e-12, "absorbed {a}: {rt:?}");
            } else {
                assert!(a.abs() < 1e-11, "lossless stack absorbs {a}: {rt:?}");
            }
        }
    }
}

/// cos θ in the base for light at `cos0` in the outside medium (Snell), if it propagates.
fn cos_in_base(n0: f64, nb: f64, cos0: f64) -> Option<f64> {
    let s = n0 * (1.0 - cos0 * cos0).sqrt() / nb;
    (s < 1.0).then(|| (1.0 - s * s).sqrt())
}

#[test]
fn reciprocity_between_the_two_sides() {
    let mut rng = Rng(9);
    let mut checked = 0;
    for i in 0..2000 {
        let lossy = i % 2 == 1;
        let (n0, nb) = (1.0 + 0.5 * rng.f(), 1.0 + 1.6 * rng.f());
        let st = random_stack(
            &mut rng,
            1 + i % 8,
            if lossy { 0.6 } else { 0.0 },
            n0,
            Ior::Real(nb),
        );
        let (cos0, l) = (0.02 + 0.98 * rng.f(), 360.0 + 470.0 * rng.f());
        let Some(cosb) = cos_in_base(n0, nb, cos0) else {
            continue;
        };
        let out = st.rt(cos0, l, false);
        let inn = st.rt(cosb, l, true);
        // T is the same both ways for any stack; R only without absorption.
        assert!(
            (out.t_s - inn.t_s).abs() < 1e-11 && (out.t_p - inn.t_p).abs() < 1e-11,
            "{out:?} {inn:?}"
        );
        if !lossy {
            assert!(close(&out, &inn, 1e-11), "{out:?} {inn:?}");
        } else if out.a() > 1e-3 {
            // An absorbing stack that is not symmetric reflects differently from the two sides.
            checked += ((out.r() - inn.r()).abs() > 1e-6) as usize;
        }
    }
    assert!(
        checked > 100,
        "absorbing stacks should differ from the two sides ({checked})"
    );
}

/// (H L)^N on a substrate: nH = 2.3, nL = 1.38, quarter-wave at 550 nm.
fn bragg(pairs: u32, ext: f64, sub: f64) -> FilmStack {
    let (nh, nl, l0) = (2.3, 1.38, 550.0);
    let period = vec![
        Layer::new(Ior::Real(nh), l0 / (4.0 * nh)),
        Layer::new(Ior::Real(nl), l0 / (4.0 * nl)),
    ];
    let items = vec![StackItem::Periodic {
        period,
        count: pairs,
    }];
    FilmStack::new(Ior::Real(ext), items, Ior::Real(sub)).unwrap()
}

#[test]
fn bragg_mirror_peak_reflectance_is_the_closed_form() {
    // At the design wavelength each quarter-wave layer's matrix is [[0, −i/n], [−i n, 0]]; a pair
    // H L gives diag(−nL/nH, −nH/nL), N pairs diag((−nL/nH)^N, (−nH/nL)^N), so the stack's input
    // admittance is Y = n_s (nH/nL)^{2N} and R = ((n0 − Y)/(n0 + Y))².
    for (pairs, n0, ns) in [
        (1, 1.0, 1.52),
        (5, 1.0, 1.52),
        (10, 1.33, 1.0),
        (20, 1.0, 3.5),
    ] {
        let y = ns * (2.3f64 / 1.38).powi(2 * pairs as i32);
        let want = ((n0 - y) / (n0 + y)).powi(2);
        let st = bragg(pairs, n0, ns);
        let got = st.rt(1.0, 550.0, false);
        assert!(
            (got.r_s - want).abs() < 1e-12 && (got.r_p - want).abs() < 1e-12,
            "{pairs}: {got:?} vs {want}"
        );
        let fast = st
            .prepare([550.0, 550.0, 600.0, 500.0], 1.0)
            .rt(1.0, false)
            .lane(0);
        assert!((fast.r() - want).abs() < 1e-12, "fast {pairs}: {fast:?}");
    }
}

#[test]
fn bragg_mirror_stop_band_has_the_closed_form_width() {
    // Phase thickness δ = (π/2) g of both layers at relative wavenumber g = λ0/λ. A period's half
    // trace is cos²δ − ½(ρ + 1/ρ) sin²δ (ρ = nH/nL); |half trace| > 1 is the stop band, whose
    // edges are at cos δ = ±(nH − nL)/(nH + nL), i.e. Δg = (4/π) asin((nH − nL)/(nH + nL)). Inside,
    // 1 − R falls as e^{−2Nκ} with cosh κ = |half trace|; outside R stays away from 1.
    let (nh, nl) = (2.3f64, 1.38f64);
    let rho = nh / nl;
    let half_width = (2.0 / std::f64::consts::PI) * ((nh - nl) / (nh + nl)).asin();
    let half_trace = |g: f64| {
        let d = std::f64::consts::FRAC_PI_2 * g;
        d.cos().powi(2) - 0.5 * (rho + 1.0 / rho) * d.sin().powi(2)
    };
    for side in [-1.0, 1.0] {
        let inside = 1.0 + side * 0.9 * half_width;
        let outside = 1.0 + side * 1.1 * half_width;
        let kappa = half_trace(inside).abs().acosh();
        let one_minus_r =
            |pairs: u32, g: f64| 1.0 - bragg(pairs, 1.0, 1.52).rt(1.0, 550.0 / g, false).r();
        let (a, b) = (one_minus_r(20, inside), one_minus_r(30, inside));
        let decay = (a / b).ln() / 20.0; // per pair, from N = 20 to 30: ≈ 2κ/2
        assert!(
            (decay - kappa).abs() < 1e-3 * kappa,
            "side {side}: {decay} vs κ {kappa}"
        );
        let worst = (1..=60)
            .map(|n| one_minus_r(n, outside))
            .fold(1.0f64, f64::min);
        assert!(
            worst > 0.05,
            "outside the stop band R reached {}",
            1.0 - worst
        );
        assert!(half_trace(outside).abs() < 1.0 && half_trace(inside).abs() > 1.0);
    }
}

#[test]
fn no_nan_at_the_limits() {
    let mut rng = Rng(3);
    let sixty_four = random_stack(&mut rng, 64, 0.2, 1.0, Ior::Real(1.5));
    assert_eq!(sixty_four.n_layers(), 64);
    let huge = FilmStack::new(
        Ior::Real(1.0),
        vec![layer(1.5, 0.0, 1e12), layer(1.2, 0.01, 1e9)],
        Ior::Real(1.33),
    )
    .unwrap();
    // Frustrated TIR through a thick low-index gap, from glass: the evanescent layer must not
    // overflow; nothing tunnels through 1 mm.
    let gap = FilmStack::new(
        Ior::Real(1.5),
        vec![
            layer(1.7, 0.0, 100.0),
            layer(1.0, 0.0, 1e6),
            layer(1.7, 0.0, 50.0),
        ],
        Ior::Real(1.5),
    )
    .unwrap();
    let metal = FilmStack::new(
        Ior::Real(1.0),
        vec![layer(1.5, 0.0, 100.0), layer(0.05, 4.0, 1e5)],
        Ior::Real(1.5),
    )
    .unwrap();
    let bragg_deep = bragg(4096 / 2, 1.0, 1.5);
    for st in [&sixty_four, &huge, &gap, &metal, &bragg_deep] {
        for cos in [0.0, 1e-300, 1e-9, 0.3, 0.9, 1.0, f64::NAN, -0.5, 2.0] {
            for inside in [false, true] {
                let rt = st.rt(cos, 555.0, inside);
                let fast = st
                    .prepare([555.0, 400.0, 700.0, 830.0], 1.0)
                    .rt(cos, inside)
                    .lane(0);
                for v in [
                    rt.r_s, rt.r_p, rt.t_s, rt.t_p, fast.r_s, fast.r_p, fast.t_s, fast.t_p,
                ] {
                    assert!(
                        v.is_finite() && (0.0..=1.0).contains(&v),
                        "{st} {cos} {inside}: {rt:?} {fast:?}"
                    );
                }
            }
        }
    }
    let c60 = 0.5; // 1.5 sin 60° = 1.30 > 1: evanescent in the gap
    let g = gap.rt(c60, 555.0, false);
    assert!(g.t() == 0.0 && (g.r() - 1.0).abs() < 1e-12, "{g:?}");
    assert!(bragg_deep.rt(1.0, 550.0, false).r() > 1.0 - 1e-15);
    // Exactly grazing: everything reflects.
    assert_eq!(sixty_four.rt(0.0, 500.0, false).r(), 1.0);
}

#[test]
fn fast_evaluator_equals_the_exact_path() {
    let mut rng = Rng(21);
    let mut worst: f64 = 0.0;
    let mut real_lanes = 0;
    for i in 0..3000 {
        let n = i % 10;
        let base = match i % 5 {
            0 => Ior::complex(0.05 + 2.0 * rng.f(), 5.0 * rng.f()).unwrap(),
            _ => Ior::Real(1.0 + 1.6 * rng.f()),
        };
        let inside = i % 5 != 0 && i % 2 == 0;
        let n0 = 1.0 + 0.5 * rng.f();
        let mut st = random_stack(&mut rng, n, if i % 3 == 0 { 0.4 } else { 0.0 }, n0, base);
        if i % 4 == 0 && n >= 2 {
            // Make the middle a periodic group.
            let mut items = st.items().to_vec();
            let period: Vec<Layer> = items
                .drain(..2)
                .flat_map(|it| it.period().to_vec())
                .collect();
            items.insert(
                0,
                StackItem::Periodic {
                    period,
                    count: 1 + (rng.f() * 12.0) as u32,
                },
            );
            st = FilmStack::new(st.ext().clone(), items, st.base().clone()).unwrap();
        }
        let scale = if i % 6 == 0 {
            2.0 * rng.f() as f32
        } else {
            1.0
        };
        let lambda: [f32; 4] = std::array::from_fn(|_| 360.0 + 470.0 * rng.f() as f32);
        let ev = st.prepare(lambda, scale);
        let scaled = st.scaled(scale as f64);
        let cos = rng.f();
        let fast = ev.rt(cos, inside);
        for (w, &l) in lambda.iter().enumerate() {
            let exact = scaled.rt(cos, l as f64, inside);
            let got = fast.lane(w);
            worst = worst.max(got.max_diff(&exact));
        }
        real_lanes += (st.layers().all(|l| l.ior.is_lossless())) as usize;
        // The f32 interface is the f64 result rounded.
        let r = ev.reflectance(cos as f32, inside);
        let want = ev.rt(cos as f32 as f64, inside).r();
        assert_eq!(r, want.map(|v| v as f32));
    }
    assert!(worst < 1e-12, "fast vs exact: {worst:e}");
    assert!(real_lanes > 1000, "{real_lanes}");
}
