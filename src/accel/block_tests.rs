use super::*;
use crate::math::{warp, Pcg32};
use crate::shape::mesh::intersect_watertight_sheared;
use crate::shape::Sphere;

fn rand_in(rng: &mut Pcg32, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * (hi - lo) + Vec3::splat(lo)
}

/// Four triangles of one of several kinds: a random soup, a fan around a shared vertex (shared
/// edges), slivers, or large triangles far from the origin.
fn four(rng: &mut Pcg32, kind: u32) -> [[Vec3; 3]; 4] {
    let mut t = [[Vec3::ZERO; 3]; 4];
    match kind {
        0 => {
            for tri in &mut t {
                let c = rand_in(rng, -2.0, 2.0);
                *tri = [0, 1, 2].map(|_| c + rand_in(rng, -1.0, 1.0));
            }
        }
        1 => {
            let c = rand_in(rng, -1.0, 1.0);
            let ring: Vec<Vec3> = (0..5).map(|_| c + rand_in(rng, -1.0, 1.0)).collect();
            for (i, tri) in t.iter_mut().enumerate() {
                *tri = [c, ring[i], ring[i + 1]];
            }
        }
        2 => {
            for tri in &mut t {
                let a = rand_in(rng, -1.0, 1.0);
                let d = rand_in(rng, -1.0, 1.0);
                *tri = [
                    a,
                    a + d,
                    a + d * (0.5 + 1e-4 * rng.next_f32()) + Vec3::splat(1e-6),
                ];
            }
        }
        _ => {
            let off = Vec3::new(3.0e4, -2.0e4, 1.0e4);
            for tri in &mut t {
                *tri = [0, 1, 2].map(|_| off + rand_in(rng, -500.0, 500.0));
            }
        }
    }
    t
}

/// A ray towards a random point, a vertex or an edge point of the triangles, sometimes along an
/// axis, sometimes with a finite extent.
fn ray_at(rng: &mut Pcg32, tris: &[[Vec3; 3]; 4]) -> Ray {
    let tri = tris[(rng.next_u32() % 4) as usize];
    let target = match rng.next_u32() % 4 {
        0 => tri[(rng.next_u32() % 3) as usize],
        1 => {
            let s = rng.next_f32();
            tri[0] + (tri[1] - tri[0]) * s
        }
        _ => {
            let b = warp::square_to_uniform_triangle(rng.next_vec2());
            b.x * tri[0] + b.y * tri[1] + (1.0 - b.x - b.y) * tri[2]
        }
    };
    let scale = (tri[1] - tri[0]).length().max(1.0);
    let mut d = warp::square_to_uniform_sphere(rng.next_vec2());
    if rng.next_u32().is_multiple_of(8) {
        d = Vec3::ZERO;
        d[(rng.next_u32() % 3) as usize] = if rng.next_f32() < 0.5 { -1.0 } else { 1.0 };
    }
    let mut ray = Ray::new(target - d * (3.0 * scale * rng.next_f32()), d);
    if rng.next_u32().is_multiple_of(3) {
        ray.t_max = 4.0 * scale * rng.next_f32();
    }
    ray
}

/// What a sequential scalar loop over the slots decides.
fn scalar(
    slots: &[(u32, [Vec3; 3]); 4],
    ray: &Ray,
    sr: &ShearedRay,
    shapes: &[Shape],
) -> (Option<(usize, f32, Vec2)>, bool) {
    // Every slot hit within the ray's range is a candidate; the first in (t, id) order wins.
    let mut best: Option<(usize, f32, Vec2)> = None;
    let mut any = false;
    for (lane, (id, c)) in slots.iter().enumerate() {
        let hit = if *id == EMPTY {
            None
        } else if id & ANALYTIC != 0 {
            shapes[(id & !ANALYTIC) as usize].intersect_prim(0, ray)
        } else {
            intersect_watertight_sheared(c[0], c[1], c[2], ray, sr)
        };
        any |= hit.is_some();
        if let Some((t, uv)) = hit {
            let first = match best {
                None => true,
                Some((l, bt, _)) => t < bt || (t == bt && *id < slots[l].0),
            };
            if first {
                best = Some((lane, t, uv));
            }
        }
    }
    (best, any)
}

fn bits(h: Option<(usize, f32, Vec2)>) -> Option<(usize, u32, u32, u32)> {
    h.map(|(l, t, uv)| (l, t.to_bits(), uv.x.to_bits(), uv.y.to_bits()))
}

#[test]
fn block_test_is_bit_identical_to_the_scalar_watertight_test() {
    let mut rng = Pcg32::new(31, 7);
    let shapes = [Shape::Sphere(Sphere::simple(
        Vec3::new(0.3, 0.2, -0.1),
        0.7,
    ))];
    let (mut hits, mut edge_lanes, mut analytic_hits) = (0, 0, 0);
    for case in 0..40_000 {
        let tris = four(&mut rng, case % 4);
        let mut slots = [0, 1, 2, 3].map(|i| (100 + i as u32, tris[i]));
        // Some blocks carry padding and an analytic lane, as leaves do.
        if case % 5 == 0 {
            slots[3].0 = EMPTY;
        }
        if case % 7 == 0 {
            slots[1].0 = ANALYTIC;
        }
        let block = Block::new(slots);
        let ray = ray_at(&mut rng, &tris);
        let Some(sr) = ShearedRay::new(ray.d) else {
            continue;
        };
        let lanes = RayLanes::new(&ray, &sr);
        let (want, want_any) = scalar(&slots, &ray, &sr, &shapes);
        let mut best = Best::new(ray.t_max);
        let got = block
            .closest(&lanes, &ray, &mut best, &shapes)
            .map(|(l, uv)| (l, best.t, uv));
        assert_eq!(bits(got), bits(want), "case {case}: {ray:?}");
        assert_eq!(block.any(&lanes, &ray, &shapes), want_any, "case {case}");
        if let Some((l, _, _)) = got {
            assert_eq!(best.id, slots[l].0);
            hits += 1;
            analytic_hits += (slots[l].0 == ANALYTIC) as usize;
        }
        // Count triangle lanes that take the f64 edge path, so the test is known to reach it.
        let sh = |p: Vec3| {
            let p = p - ray.o;
            (p[sr.kx] - sr.sx * p[sr.kz], p[sr.ky] - sr.sy * p[sr.kz])
        };
        for (id, c) in &slots {
            if id & ANALYTIC == 0 {
                let ((ax, ay), (bx, by), (cx, cy)) = (sh(c[0]), sh(c[1]), sh(c[2]));
                let on_edge = cx * by - cy * bx == 0.0
                    || ax * cy - ay * cx == 0.0
                    || bx * ay - by * ax == 0.0;
                edge_lanes += on_edge as usize;
            }
        }
    }
    assert!(hits > 10_000, "{hits}");
    assert!(analytic_hits > 100, "{analytic_hits}");
    assert!(edge_lanes > 50, "{edge_lanes}");
}
