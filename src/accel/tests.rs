use super::build::MEDIAN_DEPTH;
use super::*;
use crate::math::{warp, Pcg32, Transform, Vec3};
use crate::shape::{Disk, Sphere, TriangleMesh};

fn rand_in(rng: &mut Pcg32, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * (hi - lo) + Vec3::splat(lo)
}

/// Random triangles of assorted sizes in [−10, 10]³, as one mesh.
fn soup(rng: &mut Pcg32, n: usize, offset: Vec3) -> TriangleMesh {
    let mut p = Vec::with_capacity(3 * n);
    for i in 0..n {
        let c = rand_in(rng, -10.0, 10.0);
        let size = if i % 10 == 0 { 4.0 } else { 0.7 };
        for _ in 0..3 {
            p.push(c + rand_in(rng, -size, size));
        }
    }
    let idx = (0..n as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let t = Transform::translate(offset);
    TriangleMesh::new(p, None, None, idx, &t, false, false).unwrap()
}

pub(super) fn scene(seed: u64) -> Vec<Shape> {
    let mut rng = Pcg32::new(seed, 0);
    let mut shapes = vec![
        Shape::Mesh(soup(&mut rng, 1500, Vec3::ZERO)),
        Shape::Mesh(soup(&mut rng, 300, Vec3::new(3.0, 0.0, 0.0))),
    ];
    for _ in 0..20 {
        let c = rand_in(&mut rng, -10.0, 10.0);
        shapes.push(Shape::Sphere(Sphere::simple(c, 0.2 + 2.0 * rng.next_f32())));
    }
    let t = Transform::translate(Vec3::new(1.0, 2.0, 0.5))
        .compose(&Transform::rotate(Vec3::new(1.0, 1.0, 0.0), 50.0).unwrap())
        .compose(&Transform::scale(Vec3::splat(3.0)).unwrap());
    shapes.push(Shape::Disk(Disk::new(&t, false)));
    shapes.push(Shape::Mesh(TriangleMesh::cube(&t, false).unwrap()));
    shapes
}

#[test]
fn bvh_agrees_with_brute_force() {
    let shapes = scene(1);
    let bvh = Bvh::build(&shapes);
    let total: usize = shapes.iter().map(Shape::prim_count).sum();
    assert_eq!(bvh.prim_count(), total);
    assert!(bvh.depth() < MEDIAN_DEPTH, "depth {}", bvh.depth());
    assert!(bvh.node_count() < 2 * total, "{}", bvh.node_count());
    let mut rng = Pcg32::new(2, 0);
    let (mut hits, mut blocked) = (0, 0);
    for i in 0..20_000 {
        let o = rand_in(&mut rng, -15.0, 15.0);
        let d = warp::square_to_uniform_sphere(rng.next_vec2());
        let mut ray = Ray::new(o, d);
        if i % 3 == 0 {
            ray.t_max = 8.0 * rng.next_f32();
        }
        let a = bvh.intersect(&shapes, &ray);
        let b = BruteForce.intersect(&shapes, &ray);
        match (a, b) {
            (Some(a), Some(b)) => {
                assert_eq!((a.shape, a.prim), (b.shape, b.prim), "ray {i}");
                assert!(
                    (a.t - b.t).abs() <= 1e-5 * b.t,
                    "ray {i}: {} vs {}",
                    a.t,
                    b.t
                );
                hits += 1;
            }
            (None, None) => {}
            _ => panic!("ray {i}: bvh {a:?} vs brute {b:?}"),
        }
        let occ = bvh.occluded(&shapes, &ray);
        assert_eq!(occ, BruteForce.occluded(&shapes, &ray), "ray {i}");
        blocked += occ as usize;
    }
    // The scene is dense enough that both outcomes are exercised many times.
    assert!(hits > 2_000 && hits < 19_000, "{hits}");
    assert!(blocked > 2_000, "{blocked}");
}

#[test]
fn empty_and_single_primitive_scenes() {
    let bvh = Bvh::build(&[]);
    assert_eq!((bvh.node_count(), bvh.depth()), (0, 0));
    assert!(bvh.intersect(&[], &Ray::new(Vec3::ZERO, Vec3::Z)).is_none());
    let shapes = [Shape::Sphere(Sphere::simple(Vec3::new(0.0, 0.0, 5.0), 1.0))];
    let bvh = Bvh::build(&shapes);
    // A single leaf: no interior node.
    assert_eq!((bvh.node_count(), bvh.depth()), (0, 1));
    let h = bvh
        .intersect(&shapes, &Ray::new(Vec3::ZERO, Vec3::Z))
        .unwrap();
    assert!((h.t - 4.0).abs() < 1e-6);
    assert!(!bvh.occluded(&shapes, &Ray::new(Vec3::ZERO, -Vec3::Z)));
}

#[test]
fn coincident_centroids_still_build_small_leaves() {
    // 100 identical triangles: no SAH plane separates them; leaves must stay bounded.
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    let idx = vec![[0, 1, 2]; 100];
    let m = TriangleMesh::new(p, None, None, idx, &Transform::IDENTITY, false, false).unwrap();
    let shapes = [Shape::Mesh(m)];
    let bvh = Bvh::build(&shapes);
    assert!(bvh.depth() <= 8, "{}", bvh.depth());
    let h = bvh.intersect(&shapes, &Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z));
    assert!((h.unwrap().t - 1.0).abs() < 1e-6);
}

#[test]
fn spawned_rays_do_not_rehit_their_surface_far_from_the_origin() {
    let mut rng = Pcg32::new(77, 0);
    let off = Vec3::new(1.0e4, -1.0e4, 1.0e4);
    let t = Transform::translate(off)
        .compose(&Transform::rotate(Vec3::new(0.2, 1.0, 0.4), 31.0).unwrap())
        .compose(&Transform::scale(Vec3::splat(5.0)).unwrap());
    let shapes = vec![
        Shape::Mesh(soup(&mut rng, 500, off)),
        Shape::Mesh(TriangleMesh::cube(&t, false).unwrap()),
        Shape::Sphere(Sphere::simple(off + Vec3::new(12.0, 0.0, 0.0), 1.0e-3)),
    ];
    let bvh = Bvh::build(&shapes);
    let mut tested = 0;
    for _ in 0..20_000 {
        let target = if rng.next_f32() < 0.1 {
            off + Vec3::new(12.0, 0.0, 0.0)
        } else {
            off + rand_in(&mut rng, -8.0, 8.0)
        };
        let o = target + warp::square_to_uniform_sphere(rng.next_vec2()) * 30.0;
        let ray = Ray::new(o, (target - o).normalize());
        let Some(h) = bvh.intersect(&shapes, &ray) else {
            continue;
        };
        let si = shapes[h.shape as usize].interaction(&h, &ray);
        for _ in 0..4 {
            let d = warp::square_to_uniform_sphere(rng.next_vec2());
            let r = Ray::spawn(si.p, si.ng, d);
            if let Some(h2) = bvh.intersect(&shapes, &r) {
                let same = h2.shape == h.shape && h2.prim == h.prim;
                // A flat triangle can never be hit again; the tiny sphere only from inside,
                // across a chord.
                let planar = !matches!(shapes[h.shape as usize], Shape::Sphere(_));
                assert!(!(same && planar), "triangle re-hit at t = {}", h2.t);
                if same {
                    assert!(
                        d.dot(si.ng) < 0.0 && h2.t > 1e-5,
                        "sphere re-hit at t = {}",
                        h2.t
                    );
                }
            }
            tested += 1;
        }
    }
    assert!(tested > 10_000, "{tested}");
}

/// A height-field grid of about `n` triangles.
fn grid(n: usize) -> TriangleMesh {
    let k = ((n / 2) as f64).sqrt() as u32;
    let mut p = Vec::with_capacity(((k + 1) * (k + 1)) as usize);
    for j in 0..=k {
        for i in 0..=k {
            let (x, y) = (i as f32 / k as f32, j as f32 / k as f32);
            p.push(Vec3::new(x, y, 0.05 * (20.0 * x).sin() * (17.0 * y).cos()));
        }
    }
    let mut idx = Vec::with_capacity(2 * (k * k) as usize);
    for j in 0..k {
        for i in 0..k {
            let a = j * (k + 1) + i;
            idx.push([a, a + 1, a + k + 2]);
            idx.push([a, a + k + 2, a + k + 1]);
        }
    }
    TriangleMesh::new(p, None, None, idx, &Transform::IDENTITY, false, false).unwrap()
}

/// Build time for one million triangles: `cargo test --release --lib bvh_build_time -- --ignored
/// --nocapture`.
#[test]
#[ignore]
fn bvh_build_time_1m() {
    let shapes = [Shape::Mesh(grid(1_000_000))];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let t0 = std::time::Instant::now();
    let bvh = pool.install(|| Bvh::build(&shapes));
    let one = t0.elapsed();
    let t0 = std::time::Instant::now();
    let _ = Bvh::build(&shapes);
    let all = t0.elapsed();
    let mut rng = Pcg32::new(1, 1);
    let t0 = std::time::Instant::now();
    let mut hits = 0;
    let rays = 1_000_000;
    for _ in 0..rays {
        let o = Vec3::new(rng.next_f32(), rng.next_f32(), 1.0);
        let d = (Vec3::new(rng.next_f32(), rng.next_f32(), 0.0) - o).normalize();
        hits += bvh.intersect(&shapes, &Ray::new(o, d)).is_some() as usize;
    }
    let trace = t0.elapsed();
    println!(
        "{} triangles: build {:?} on 1 thread, {:?} on {} threads; {} nodes, depth {}; \
         {rays} rays in {:?} ({hits} hits)",
        shapes[0].prim_count(),
        one,
        all,
        rayon::current_num_threads(),
        bvh.node_count(),
        bvh.depth(),
        trace
    );
    // Rays near the rim can pass beside the wavy grid.
    assert!(hits > rays * 95 / 100, "{hits}");
}

fn hit_bits(h: Option<Hit>) -> Option<(u32, u32, u32, u32, u32)> {
    h.map(|h| {
        (
            h.shape,
            h.prim,
            h.t.to_bits(),
            h.uv.x.to_bits(),
            h.uv.y.to_bits(),
        )
    })
}

/// Every instruction-set variant this CPU runs (the baseline always; AVX2 and AVX-512 where
/// present) gives bit-identical answers, single and batched; variants the CPU lacks are refused.
#[test]
fn every_isa_variant_gives_identical_hits() {
    let mut shapes = scene(5);
    shapes.push(Shape::Mesh(grid(20_000)));
    let mut bvh = Bvh::build(&shapes);
    assert!(bvh.set_isa(Isa::Baseline));
    let mut rng = Pcg32::new(9, 3);
    let rays: Vec<Ray> = (0..20_000)
        .map(|i| {
            let o = rand_in(&mut rng, -15.0, 15.0);
            let mut r = Ray::new(o, warp::square_to_uniform_sphere(rng.next_vec2()));
            if i % 4 == 0 {
                r.t_max = 10.0 * rng.next_f32();
            }
            r
        })
        .collect();
    let want: Vec<_> = rays
        .iter()
        .map(|r| {
            (
                hit_bits(bvh.intersect(&shapes, r)),
                bvh.occluded(&shapes, r),
            )
        })
        .collect();
    let hits = want.iter().filter(|w| w.0.is_some()).count();
    assert!(hits > 5_000 && hits < 19_000, "{hits}");
    let mut tested = 0;
    for isa in Isa::ALL {
        if !bvh.set_isa(isa) {
            assert!(!isa.supported());
            assert_ne!(bvh.isa(), isa);
            continue;
        }
        tested += 1;
        let mut batch = vec![None; rays.len()];
        let mut blocked = vec![false; rays.len()];
        bvh.intersect_n(&shapes, &rays, &mut batch);
        bvh.occluded_n(&shapes, &rays, &mut blocked);
        for (i, r) in rays.iter().enumerate() {
            let got = (
                hit_bits(bvh.intersect(&shapes, r)),
                bvh.occluded(&shapes, r),
            );
            assert_eq!(got, want[i], "{isa:?}, ray {i}");
            assert_eq!(
                (hit_bits(batch[i]), blocked[i]),
                want[i],
                "{isa:?} batch, ray {i}"
            );
        }
    }
    assert!(tested >= 1);
    assert!(Isa::best().supported());
}
