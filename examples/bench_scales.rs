//! Micro-benchmark of the `scales` texture's full evaluation (what the bump map and the groove
//! colour call at every hit): the flagship's soil crumbs (Voronoi, irregularity 1) and dorsal
//! scales (irregularity 0.2) at a fixed set of pseudo-random UV points. Prints nanoseconds per
//! call and a checksum of the results (to compare two builds that must agree).
//!
//! cargo run --release --example bench_scales

use ophis::math::Vec2;
use ophis::texture::scales::Scales;
use std::time::Instant;

fn main() {
    let crumbs = Scales {
        scale_u: 600.0,
        scale_v: 600.0,
        irregularity: 1.0,
        gap: 0.28,
        dome: 0.9,
        overlap: 0.0,
        seed: 3,
        ..Scales::default()
    };
    let dorsal = Scales {
        scale_u: 15.0,
        scale_v: 15.0,
        irregularity: 0.2,
        gap: 0.05,
        dome: 0.35,
        overlap: 0.5,
        seed: 7,
        ..Scales::default()
    };
    let mut state = 0x1234_5678_u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        (state >> 8) as f32 / 16_777_216.0
    };
    let points: Vec<Vec2> = (0..200_000).map(|_| Vec2::new(next(), next())).collect();
    for (name, s) in [("crumbs", &crumbs), ("dorsal", &dorsal)] {
        let mut best = f64::INFINITY;
        let mut sum = 0.0f64;
        for _ in 0..5 {
            let t = Instant::now();
            sum = 0.0;
            for &uv in &points {
                let x = s.sample(uv);
                sum += (x.height + x.edge_distance) as f64;
            }
            best = best.min(t.elapsed().as_secs_f64());
        }
        println!(
            "{name}: {:.1} ns per evaluation (best of 5), checksum {sum:.6}",
            best * 1e9 / points.len() as f64
        );
    }
}
