use super::*;
use crate::math::Pcg32;
use std::collections::HashMap;

/// The default pattern with `scale_u` × `scale_v` cells per unit of UV and the given
/// irregularity.
fn grid(scale_u: f32, scale_v: f32, irregularity: f32) -> Scales {
    Scales {
        scale_u,
        scale_v,
        irregularity,
        ..Scales::default()
    }
}

fn irregular() -> Scales {
    Scales {
        seed: 11,
        ..grid(23.3, 17.7, 1.0)
    }
}

#[test]
fn cell_ids_are_stable_inside_a_cell_and_depend_on_the_seed() {
    let s = irregular();
    let mut rng = Pcg32::new(3, 5);
    let step = 1e-3; // in cells
    let mut checked = 0;
    let mut changed_with_seed = 0;
    let other = Scales {
        seed: 12,
        ..s.clone()
    };
    for _ in 0..4000 {
        let uv = rng.next_vec2();
        let a = s.sample(uv);
        assert!((0.0..1.0).contains(&a.id));
        if a.edge_distance < 3.0 * step {
            continue;
        }
        checked += 1;
        let d = Vec2::new(
            (rng.next_f32() - 0.5) * 2.0 * step / s.scale_u,
            (rng.next_f32() - 0.5) * 2.0 * step / s.scale_v,
        );
        let b = s.sample(uv + d);
        assert_eq!(a.cell, b.cell, "cell changed inside a cell at {uv:?}");
        assert_eq!(a.id, b.id);
        assert_eq!(a.id, s.sample(uv).id, "same seed, same id");
        if other.sample(uv).id != a.id {
            changed_with_seed += 1;
        }
    }
    assert!(checked > 3000);
    assert!(changed_with_seed > checked * 9 / 10);
}

#[test]
fn cell_count_per_area_matches_the_scales() {
    for s in [
        irregular(),
        Scales {
            irregularity: 0.0,
            ..irregular()
        },
    ] {
        // Find every cell whose centre lies in the UV square [0, 2)² by looking the pattern up on
        // a grid a fifth of a cell apart.
        let mut centres: HashMap<(i32, i32), Vec2> = HashMap::new();
        let n = (2.0 * s.scale_u.max(s.scale_v) * 5.0) as usize + 10;
        for a in 0..n {
            for b in 0..n {
                let uv = Vec2::new(
                    -0.1 + 2.2 * a as f32 / n as f32,
                    -0.1 + 2.2 * b as f32 / n as f32,
                );
                let x = s.sample(uv);
                centres.insert(x.cell, x.center);
            }
        }
        let inside = centres
            .values()
            .filter(|c| {
                let uv = Vec2::new(c.x / s.scale_u, c.y / s.scale_v);
                (0.0..2.0).contains(&uv.x) && (0.0..2.0).contains(&uv.y)
            })
            .count() as f32;
        let expected = 4.0 * s.scale_u * s.scale_v;
        let rel = (inside - expected).abs() / expected;
        assert!(
            rel < 0.03,
            "irregularity {}: {inside} cells, expected {expected}",
            s.irregularity
        );
    }
}

/// Largest slope of the height in cell space: shoulder 1.5/gap (smoothstep), dome 2/R, tile
/// overlap/(2R), each times the other factors' maximum of 1.
fn lipschitz(s: &Scales) -> f32 {
    1.5 / s.gap + 2.0 * s.dome / CELL_RADIUS + s.overlap / (2.0 * CELL_RADIUS)
}

fn max_jump_ratio(s: &Scales, seed: u64) -> f32 {
    let mut rng = Pcg32::new(seed, 1);
    let step = 1e-3;
    let mut worst: f32 = 0.0;
    for _ in 0..20000 {
        let uv = rng.next_vec2();
        let dir = rng.next_f32() * std::f32::consts::TAU;
        let d = Vec2::new(dir.cos() * step / s.scale_u, dir.sin() * step / s.scale_v);
        let jump = (s.height(uv + d, 0.0) - s.height(uv, 0.0)).abs();
        worst = worst.max(jump / (step * lipschitz(s)));
    }
    worst
}

#[test]
fn height_is_continuous_with_a_gap_and_steps_without() {
    let s = irregular();
    let r = max_jump_ratio(&s, 7);
    // Rounding in f32 cell coordinates (~30 cells, ulp 2e-6) adds at most a few percent.
    assert!(r < 1.05, "height jumps {r} times the Lipschitz bound");
    let flat = Scales {
        gap: 0.0,
        ..irregular()
    };
    // With gap = 0 the edges are steps: some pair straddling an edge must jump.
    let mut rng = Pcg32::new(9, 2);
    let mut steps = 0;
    for _ in 0..20000 {
        let uv = rng.next_vec2();
        let d = Vec2::new(2e-3 / flat.scale_u, 0.0);
        if (flat.height(uv + d, 0.0) - flat.height(uv, 0.0)).abs() > 0.1 {
            steps += 1;
        }
    }
    assert!(steps > 0, "gap = 0 must leave steps at the edges");
    // Heights stay in [0, 1].
    let mut rng = Pcg32::new(1, 1);
    for _ in 0..2000 {
        let h = s.height(rng.next_vec2(), 0.0);
        assert!((0.0..=1.0).contains(&h), "{h}");
    }
}

#[test]
fn regular_scales_are_congruent_hexagons() {
    let s = grid(10.0, 8.0, 0.0);
    let mut rng = Pcg32::new(4, 4);
    let offsets: Vec<Vec2> = (0..200)
        .map(|_| (rng.next_vec2() - Vec2::splat(0.5)) * 0.9)
        .collect();
    let profile = |c: Vec2| -> Vec<(f32, f32)> {
        offsets
            .iter()
            .map(|o| {
                let p = c + *o;
                let x = s.sample(Vec2::new(p.x / s.scale_u, p.y / s.scale_v));
                (x.edge_distance, x.height)
            })
            .collect()
    };
    // Cells in an even and an odd row (centres at integer and half-integer x).
    let reference = profile(Vec2::new(3.0, 2.0));
    for c in [
        Vec2::new(5.0, 4.0),
        Vec2::new(2.5, 3.0),
        Vec2::new(7.5, 5.0),
    ] {
        for (a, b) in reference.iter().zip(profile(c)) {
            assert!((a.0 - b.0).abs() < 1e-4 && (a.1 - b.1).abs() < 1e-4);
        }
    }
    // The hexagon: vertical edges at x = ±½ (inradius ½), slanted edges at the bisectors of
    // (±½, ±1), √1.25/2 from the centre; six vertices where they meet.
    // (gap = 0: no corner rounding, so the distances are the exact ones.)
    let sharp = Scales {
        gap: 0.0,
        ..s.clone()
    };
    let at = |p: Vec2| sharp.sample(Vec2::new(p.x / s.scale_u, p.y / s.scale_v));
    assert!((at(Vec2::new(3.0, 2.0)).edge_distance - 0.5).abs() < 1e-4);
    let slant = 1.25f32.sqrt() / 2.0;
    let dir = Vec2::new(0.5, 1.0).normalize();
    let d = at(Vec2::new(3.0, 2.0) + dir * (slant - 0.1)).edge_distance;
    assert!((d - 0.1).abs() < 1e-4, "{d}");
}

#[test]
fn integer_scales_wrap_without_a_seam() {
    let s = grid(16.0, 12.0, 0.8);
    let mut rng = Pcg32::new(8, 8);
    for _ in 0..500 {
        let uv = rng.next_vec2();
        let a = s.sample(uv);
        let b = s.sample(uv + Vec2::new(1.0, 0.0));
        let c = s.sample(uv + Vec2::new(0.0, 1.0));
        assert!((a.height - b.height).abs() < 1e-4 && a.id == b.id);
        assert!((a.height - c.height).abs() < 1e-4 && a.id == c.id);
    }
}

#[test]
fn footprint_fades_the_relief() {
    let s = irregular();
    let mut rng = Pcg32::new(2, 2);
    for _ in 0..200 {
        let uv = rng.next_vec2();
        assert_eq!(s.height(uv, 2.0), FADE_LEVEL);
        assert!(s.gradient(uv, 2.0).length() < 1e-3);
        assert!(s.sample_filtered(uv, 2.0).groove == 0.0);
    }
}

#[test]
fn tilts_stay_in_their_cone_and_vary_per_cell() {
    let s = Scales {
        tilt: 10f32.to_radians(),
        ..irregular()
    };
    let mut rng = Pcg32::new(5, 5);
    let mut angles = Vec::new();
    for _ in 0..300 {
        let (a, phi) = s.tilt_at(rng.next_vec2());
        assert!((0.0..=s.tilt).contains(&a) && (0.0..std::f32::consts::TAU).contains(&phi));
        angles.push(a);
    }
    let mean = angles.iter().sum::<f32>() / angles.len() as f32;
    // Uniform over the cone's disc: mean angle 2/3 of the largest.
    assert!(
        (mean / s.tilt - 2.0 / 3.0).abs() < 0.06,
        "{}",
        mean / s.tilt
    );
}

#[test]
fn rows_layout_makes_one_plate_across_u_with_grooves_at_both_edges() {
    let s = Scales {
        layout: Layout::Rows,
        gap: 0.08,
        ..grid(1.0, 15.0, 0.3)
    };
    let mut rng = Pcg32::new(8, 8);
    for _ in 0..2000 {
        let v = 3.0 * rng.next_f32();
        let a = s.sample(Vec2::new(0.3, v));
        let b = s.sample(Vec2::new(0.7, v));
        // One plate spans the width: same cell, same id, wherever across u.
        assert_eq!(a.id, b.id, "at v {v}");
        // Its side edges are the band's edges, u = 0 and u = 1.
        let e = s.sample(Vec2::new(0.002, v)).edge_distance;
        assert!(e < 0.003, "edge distance {e} at the band's edge");
    }
    // Rows are laid end to end along v: about scale_v plates per unit v.
    let mut ids = std::collections::HashSet::new();
    for i in 0..3000 {
        // The centre, unlike the lattice index, is not wrapped by the period of scale_v.
        ids.insert(
            s.sample(Vec2::new(0.5, i as f32 / 1000.0))
                .center
                .y
                .to_bits(),
        );
    }
    assert!((ids.len() as i32 - 45).abs() <= 1, "{}", ids.len());
}

#[test]
fn head_layout_gives_every_shield_its_cell_and_closes_the_map_edges() {
    let s = Scales {
        layout: Layout::Head,
        scale_u: 1.0,
        scale_v: 1.0,
        gap: 0.06,
        ..Scales::default()
    };
    let seeds = crate::texture::head_shields::seeds();
    let n = crate::texture::head_shields::shields();
    let mut ids = std::collections::HashSet::new();
    for (i, q) in seeds.iter().enumerate().take(n) {
        let a = s.sample(*q);
        assert_eq!(
            a.cell,
            (i as i32, 0),
            "the seed of shield {i} lies in its own cell"
        );
        assert!(a.groove < 0.5, "shield {i}'s centre is in a groove");
        ids.insert(a.id.to_bits());
    }
    assert_eq!(ids.len(), n, "shields share ids");
    // Along the lower lip (u = 0) and the back of the head (v = 1) runs a groove: the map's
    // edges are shield edges.
    let mut rng = Pcg32::new(4, 4);
    for _ in 0..200 {
        let t = 0.05 + 0.9 * rng.next_f32();
        for uv in [Vec2::new(0.0, t), Vec2::new(1.0, t)] {
            let e = s.sample(uv).edge_distance;
            assert!(e < 0.05, "edge distance {e} at {uv}");
        }
    }
    // The pattern is mirror-symmetric about the crown's midline.
    for _ in 0..500 {
        let uv = rng.next_vec2();
        let a = s.sample(uv).edge_distance;
        let b = s.sample(Vec2::new(1.0 - uv.x, uv.y)).edge_distance;
        assert!((a - b).abs() < 1e-4, "{a} vs {b} at {uv}");
    }
}

#[test]
fn the_closed_form_gradient_matches_central_differences() {
    // Central differences 1e-4 of a cell wide: their error is O(h²) where the relief is smooth
    // and O(h·Δf'') ≤ 1e-4 × 6/gap² ≈ 0.1 at the few places its second derivative jumps
    // (groove shoulders, the dome's rim); f32 cell coordinates of ~10 resolve the step to
    // ~0.5 %. The steps are measured as represented in f32. Where
    // the second-nearest edge changes from one neighbour to another near a corner, the
    // smooth minimum keeps the height continuous but its slope has a small kink, which a
    // difference straddling it does not see: a few points in a thousand may differ more.
    for s in [
        irregular(),
        Scales {
            overlap: 0.6,
            overlap_dir: Vec2::new(0.6, 0.8),
            gap: 0.1,
            ..irregular()
        },
        Scales {
            layout: Layout::Rows,
            scale_u: 1.0,
            ..irregular()
        },
        Scales {
            layout: Layout::Head,
            scale_u: 1.3,
            scale_v: 1.0,
            ..Scales::default()
        },
    ] {
        let mut rng = Pcg32::new(21, 4);
        let k = Vec2::new(s.scale_u, s.scale_v) * if s.layout == Layout::Head { 8.0 } else { 1.0 };
        let mut worst = 0.0f32;
        let mut off = 0;
        for _ in 0..3000 {
            // Near the origin, where f32 resolves the small steps.
            let uv = rng.next_vec2() * if s.layout == Layout::Head { 1.0 } else { 0.15 };
            for width in [0.0, 0.8] {
                let g = s.gradient(uv, width);
                let (hu, hv) = (1e-4 / k.x, 1e-4 / k.y);
                let (up, um) = (uv + Vec2::new(hu, 0.0), uv - Vec2::new(hu, 0.0));
                let (vp, vm) = (uv + Vec2::new(0.0, hv), uv - Vec2::new(0.0, hv));
                let fd = Vec2::new(
                    (s.height(up, width) - s.height(um, width)) / (up.x - um.x),
                    (s.height(vp, width) - s.height(vm, width)) / (vp.y - vm.y),
                );
                // Compare in cell units (the slope per cell), where the relief's slopes are O(10).
                let err = ((g - fd) / k).length();
                worst = worst.max(err);
                let slope = (g / k).length();
                if err > 0.03 + 0.02 * slope {
                    off += 1;
                }
                assert!(
                    err < 0.15 + 0.1 * slope,
                    "{:?} at {uv}: {g} vs {fd}",
                    s.layout
                );
            }
        }
        assert!(worst > 0.0);
        assert!(off <= 60, "{:?}: {off} of 6000 differ", s.layout);
    }
}

#[test]
fn the_narrow_search_finds_the_nearest_centre_up_to_its_irregularity_bound() {
    // With irregularity ≤ 0.35 the search looks one row and column either side; check against
    // a brute-force search three either side, for both lattices.
    for layout in [Layout::Hex, Layout::Rows] {
        let s = Scales {
            irregularity: 0.35,
            layout,
            ..irregular()
        };
        let lat = s.lattice();
        let mut rng = Pcg32::new(77, 1);
        for _ in 0..20000 {
            let uv = rng.next_vec2();
            let p = s.to_cell_space(uv);
            let (j0, i0) = (p.y.round() as i32, p.x.floor() as i32);
            let mut best = (f32::INFINITY, (0, 0));
            for j in j0 - 3..=j0 + 3 {
                let row = s.row_hash(j, lat);
                for i in i0 - 3..=i0 + 3 {
                    let (c, _, cell) = s.center(i, j, row, lat);
                    let d = (p - c).length_squared();
                    if d < best.0 {
                        best = (d, cell);
                    }
                }
            }
            assert_eq!(s.sample(uv).cell, best.1, "{layout:?} at {uv}");
        }
    }
}

#[test]
fn the_nearest_lookup_agrees_with_the_full_sample() {
    for s in [
        irregular(),
        Scales {
            layout: Layout::Head,
            scale_u: 1.3,
            ..Scales::default()
        },
    ] {
        let mut rng = Pcg32::new(5, 9);
        for _ in 0..5000 {
            let uv = rng.next_vec2();
            let full = s.sample(uv);
            assert_eq!(s.nearest(uv).0, full.cell);
            assert_eq!(s.id_at(uv), full.id);
        }
    }
}

#[test]
fn the_search_in_lanes_gives_the_scalar_bits_on_every_instruction_set() {
    // Hex at the narrow and the wide reach, rows, integer scales that wrap (points around
    // the seam and outside [0, 1)) and fractional ones; the lanes must reproduce the scalar
    // loop's winner and its floats exactly, on the baseline lanes (one wide) and on AVX2.
    let configs = [
        grid(15.0, 15.0, 0.2),
        grid(600.0, 600.0, 1.0),
        irregular(),
        grid(7.0, 9.0, 0.35),
        grid(5.0, 6.0, 0.36),
        Scales {
            layout: Layout::Rows,
            seed: 8,
            ..grid(1.0, 15.0, 0.15)
        },
        Scales {
            layout: Layout::Rows,
            ..grid(3.0, 4.0, 0.9)
        },
    ];
    let bits = |f: &relief::Found| {
        (
            f.c0.x.to_bits(),
            f.c0.y.to_bits(),
            f.h0,
            f.cell,
            f.e.map(f32::to_bits),
            f.n.map(|n| (n.x.to_bits(), n.y.to_bits())),
        )
    };
    let mut rng = Pcg32::new(17, 1);
    let mut compared = 0;
    for s in &configs {
        for k in 0..4000 {
            // A quarter of the points near the seam u, v ≈ 0 ≡ 1, some outside [0, 1).
            let uv = if k % 4 == 0 {
                Vec2::new(rng.next_f32() * 0.1 - 0.05, rng.next_f32() * 0.1 - 0.05)
            } else {
                Vec2::new(rng.next_f32() * 1.2 - 0.1, rng.next_f32() * 1.2 - 0.1)
            };
            let p = s.to_cell_space(uv);
            for edges in [true, false] {
                let want = bits(&s.search_scalar(p, edges));
                for isa in crate::accel::Isa::ALL.into_iter().filter(|i| i.supported()) {
                    assert_eq!(
                        bits(&s.search_on(isa, p, edges)),
                        want,
                        "{:?} at uv {uv:?} on {}",
                        s.layout,
                        isa.name()
                    );
                    compared += 1;
                }
            }
        }
    }
    assert!(compared >= 2 * 7 * 4000);
}

#[test]
fn the_remembered_search_answers_only_the_same_question() {
    // Patterns that differ in one input each, asked at the same points in an interleaved
    // order, with and without edges: every answer must be the one a fresh search gives.
    let base = grid(15.0, 15.0, 0.2);
    let patterns = [
        base.clone(),
        Scales {
            seed: 1,
            ..base.clone()
        },
        Scales {
            irregularity: 0.6,
            ..base.clone()
        },
        Scales {
            scale_u: 16.0,
            ..base.clone()
        },
        Scales {
            scale_v: 14.0,
            ..base.clone()
        },
        Scales {
            layout: Layout::Rows,
            ..base.clone()
        },
        Scales {
            layout: Layout::Head,
            ..base.clone()
        },
        Scales {
            gap: 0.2,
            dome: 0.9,
            ..base.clone()
        },
    ];
    let bits = |f: relief::Found| format!("{:?}", (f.c0, f.h0, f.cell, f.e.map(f32::to_bits), f.n));
    let mut rng = Pcg32::new(2, 3);
    for _ in 0..300 {
        let p = Vec2::new(rng.next_f32() * 15.0, rng.next_f32() * 15.0);
        for round in 0..3 {
            for (k, s) in patterns.iter().enumerate() {
                let edges = (k + round) % 2 == 0;
                let want = bits(s.search_on(crate::accel::Isa::Baseline, p, edges));
                assert_eq!(bits(s.search(p, edges)), want, "pattern {k}, edges {edges}");
                assert_eq!(
                    bits(s.search(p, !edges)),
                    bits(s.search_on(crate::accel::Isa::Baseline, p, !edges))
                );
            }
        }
    }
}
