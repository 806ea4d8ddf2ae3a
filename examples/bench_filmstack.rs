//! Micro-benchmark (not a test): nanoseconds per four-wavelength reflectance evaluation of
//! interference stacks with the rendering evaluator (`FilmStack::prepare` → `StackEval::rt`),
//! against the single-film Airy code as the film BSDFs call it (`film_rt` once per hero
//! wavelength). Each figure is the median of 15 timed runs over 1024 angles, with the fastest and
//! slowest run, so the spread of a shared machine shows.
//!
//! `cargo run --release --example bench_filmstack`

use num_complex::Complex64 as C;
use ophis::optics::filmstack::FilmStack;
use ophis::optics::ior::Ior;
use ophis::optics::stackspec::parse_items;
use ophis::optics::thinfilm::film_rt;
use std::hint::black_box;
use std::time::Instant;

const LAMBDA: [f32; 4] = [452.0, 538.0, 611.0, 689.0];
const RUNS: usize = 15;

/// (median, min, max) ns per call of `f` over `cos`, `reps` sweeps per run.
fn time(cos: &[f64], reps: usize, mut f: impl FnMut(f64) -> f64) -> (f64, f64, f64) {
    let mut runs: Vec<f64> = (0..RUNS)
        .map(|_| {
            let t = Instant::now();
            let mut acc = 0.0;
            for _ in 0..reps {
                for &c in cos {
                    acc += f(black_box(c));
                }
            }
            black_box(acc);
            t.elapsed().as_nanos() as f64 / (reps * cos.len()) as f64
        })
        .collect();
    runs.sort_by(|a, b| a.partial_cmp(b).unwrap());
    (runs[RUNS / 2], runs[0], runs[RUNS - 1])
}

fn stack(ext: f64, spec: &str, base: Ior) -> FilmStack {
    FilmStack::new(Ior::Real(ext), parse_items(spec).unwrap(), base).unwrap()
}

/// `n` distinct lossless layers alternating around keratin and air-like indices.
fn distinct(n: usize) -> String {
    (0..n)
        .map(|i| {
            let (ior, d) = if i % 2 == 0 {
                (1.56 + 0.01 * i as f64, 105.0 + i as f64)
            } else {
                (1.0 + 0.02 * i as f64, 88.0 + i as f64)
            };
            format!("{ior}:{d}")
        })
        .collect::<Vec<_>>()
        .join(",")
}

fn main() {
    let mut seed = 1u64;
    let cos: Vec<f64> = (0..1024)
        .map(|_| {
            seed = ophis::math::rng::mix64(seed);
            0.05 + 0.95 * (seed >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect();
    let reps = 200;
    println!(
        "ns per evaluation of R at 4 wavelengths (median [min–max] of {RUNS} runs, release build)"
    );

    // The baseline: one 300 nm film of n = 1.56 on glass through the single-film Airy code,
    // four calls as bsdf/filmfresnel.rs makes them.
    let film = |c: f64| {
        let mut s = 0.0;
        for l in LAMBDA {
            s += film_rt(c, 1.0, C::new(1.56, 0.0), 300.0, C::new(1.5, 0.0), l as f64).r();
        }
        s
    };
    let base = time(&cos, reps, film);
    println!(
        "{:<46} {:7.1} [{:6.1}–{:6.1}]   1.00×",
        "single film, film_rt × 4", base.0, base.1, base.2
    );

    let cases: Vec<(String, FilmStack, bool)> = vec![
        (
            "stack, 1 layer".into(),
            stack(1.0, "1.56:300", Ior::Real(1.5)),
            false,
        ),
        (
            "stack, 2 layers".into(),
            stack(1.0, &distinct(2), Ior::Real(1.5)),
            false,
        ),
        (
            "stack, 7 layers".into(),
            stack(1.0, &distinct(7), Ior::Real(1.5)),
            false,
        ),
        (
            "stack, 21 layers (distinct)".into(),
            stack(1.0, &distinct(21), Ior::Real(1.5)),
            false,
        ),
        (
            "stack, 21 layers as (H,L)x10,H".into(),
            stack(1.0, "(2.3:59.8,1.38:99.6)x10,2.3:59.8", Ior::Real(1.5)),
            false,
        ),
        (
            "stack, 7 layers on gold (0.35+2.7i)".into(),
            stack(1.0, &distinct(7), Ior::complex(0.35, 2.7).unwrap()),
            false,
        ),
        (
            "stack, 7 layers, one absorbing (complex path)".into(),
            stack(
                1.0,
                &format!("{},1.7+0.03i:80", distinct(6)),
                Ior::Real(1.5),
            ),
            false,
        ),
        (
            "stack, 7 layers from a 1.56 base (TIR, complex)".into(),
            stack(1.0, &distinct(7), Ior::Real(1.56)),
            true,
        ),
    ];
    for (name, st, inside) in &cases {
        let ev = st.prepare(LAMBDA, 1.0);
        let t = time(&cos, reps, |c| ev.rt(c, *inside).r().iter().sum());
        println!(
            "{name:<46} {:7.1} [{:6.1}–{:6.1}]   {:.2}×",
            t.0,
            t.1,
            t.2,
            t.0 / base.0
        );
    }
    println!(
        "size of a prepared stack (StackEval): {} bytes",
        std::mem::size_of::<ophis::optics::stackeval::StackEval>()
    );
    for (name, st, _) in cases.iter().take(4) {
        let t = time(&cos[..64], 50, |c| st.prepare(LAMBDA, c as f32).lambda()[0]);
        println!(
            "prepare, {:<37} {:7.1} [{:6.1}–{:6.1}]",
            &name[7..],
            t.0,
            t.1,
            t.2
        );
    }
}
