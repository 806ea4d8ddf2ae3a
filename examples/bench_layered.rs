//! Micro-benchmark (not a test): nanoseconds per BSDF construction, `f` and `sample_f` for the
//! snake-skin stack (n = 1.5 coat or a 300 nm film of n = 1.56 on it, absorbing layer of optical
//! depth 1.4, grey base 0.5), closed form against the position-free random walk, and the
//! standard deviation of one `f` sample (what a render's per-pixel noise scales with).
//!
//! `cargo run --release --example bench_layered`

use ophis::bsdf::layered::closed_form::{CoatOptics, CoatedDiffuse};
use ophis::bsdf::layered::{CoatModel, LayeredBxdf, LayeredModel, Medium, DEFAULT_MAX_DEPTH};
use ophis::bsdf::{diffuse::DiffuseBxdf, Bxdf, TransportMode};
use ophis::math::{Pcg32, Vec3};
use ophis::spectrum::SampledSpectrum;
use std::hint::black_box;
use std::time::Instant;

fn time_ns(n: usize, mut f: impl FnMut(usize)) -> f64 {
    let t = Instant::now();
    for i in 0..n {
        f(i);
    }
    t.elapsed().as_nanos() as f64 / n as f64
}

fn dir(theta_deg: f32, phi: f32) -> Vec3 {
    let (s, c) = theta_deg.to_radians().sin_cos();
    Vec3::new(s * phi.cos(), s * phi.sin(), c)
}

fn main() {
    let s = SampledSpectrum::splat;
    let mode = TransportMode::Radiance;
    let coat = || Bxdf::dielectric(1.5, s(1.0), s(1.0));
    let base = || Bxdf::Diffuse(DiffuseBxdf::new(s(0.5)));
    let media = [Medium::absorbing(s(1.4))];
    let build = |closed: bool| {
        Bxdf::Layered(
            LayeredBxdf::new(
                [coat(), base()],
                &media,
                DEFAULT_MAX_DEPTH,
                closed,
                CoatModel::Walk,
                1,
            )
            .unwrap(),
        )
    };
    let film = CoatOptics::Film {
        eta: 1.5,
        film_ior: [1.56; 4],
        thickness_nm: 300.0,
        lambda: [450.0, 520.0, 590.0, 660.0],
    };
    let n = 200_000;
    let mut rng = Pcg32::new(1, 1);
    let dirs: Vec<(Vec3, Vec3)> = (0..1024)
        .map(|_| {
            let a = 85.0 * rng.next_f32();
            let b = 85.0 * rng.next_f32();
            (dir(a, 0.0), dir(b, std::f32::consts::TAU * rng.next_f32()))
        })
        .collect();
    println!("snake stack: coat 1.5 / absorbing τ = 1.4 / base 0.5 (release build)");
    let t = time_ns(20_000, |_| {
        black_box(build(true));
    });
    println!("construct closed form (dielectric coat): {t:8.0} ns");
    let t = time_ns(2_000, |i| {
        // New wavelengths every time, as in a render (no memo hits).
        let l = 400.0 + 0.1 * i as f32;
        let f = CoatOptics::Film {
            eta: 1.5,
            film_ior: [1.56; 4],
            thickness_nm: 300.0,
            lambda: [l, l + 70.0, l + 140.0, l + 210.0],
        };
        black_box(CoatedDiffuse::new(f, s(0.5), s(1.4)));
    });
    println!("construct closed form (film coat, new λ): {t:7.0} ns");
    let t = time_ns(20_000, |_| {
        black_box(build(false));
    });
    println!("construct random walk:                   {t:8.0} ns");
    let film_b = Bxdf::Layered(LayeredBxdf {
        model: LayeredModel::Closed(CoatedDiffuse::new(film, s(0.5), s(1.4))),
        seed: 1,
    });
    for (name, b) in [
        ("closed form, dielectric", build(true)),
        ("closed form, film      ", film_b),
        ("random walk, dielectric", build(false)),
    ] {
        let tf = time_ns(n, |i| {
            let (wo, wi) = dirs[i & 1023];
            black_box(b.f(wo, wi, mode));
        });
        let ts = time_ns(n, |i| {
            let (wo, _) = dirs[i & 1023];
            black_box(b.sample_f(wo, rng.next_f32(), rng.next_vec2(), mode));
        });
        // Relative standard deviation of one f sample at (30°, 60°).
        let (wo, wi) = (dir(30.0, 0.0), dir(60.0, 3.0));
        let (mut m, mut m2) = (0.0f64, 0.0f64);
        let k = 100_000;
        let mut b = b.clone();
        for i in 0..k {
            // A stochastic f is a deterministic function of its seed: a new seed per sample.
            b.reseed(i as u64);
            let v = b.f(wo, wi, mode)[0] as f64;
            m += v;
            m2 += v * v;
        }
        let mean = m / k as f64;
        let sd = (m2 / k as f64 - mean * mean).max(0.0).sqrt();
        println!(
            "{name}: f {tf:7.0} ns, sample_f {ts:7.0} ns, f(30°,60°) = {mean:.6}, σ/mean of one f = {:.3}",
            sd / mean
        );
    }
}
