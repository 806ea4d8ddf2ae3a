use super::*;
use crate::accel::tests::scene;
use crate::accel::{Bvh, Isa};
use crate::math::{warp, Pcg32, Vec3};
use crate::shape::Shape;

/// Batches of rays: bundles from one origin in nearby directions (as a pixel's samples),
/// incoherent ones, rays with short extents, zero directions and axis-aligned directions.
fn rays(rng: &mut Pcg32, n: usize) -> Vec<Ray> {
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let o =
            Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 30.0 - Vec3::splat(15.0);
        let d0 = warp::square_to_uniform_sphere(rng.next_vec2());
        let kind = rng.next_u32() % 4;
        for j in 0..16 {
            let mut r = match kind {
                // A coherent bundle.
                0 => {
                    let jitter = warp::square_to_uniform_sphere(rng.next_vec2()) * 0.02;
                    Ray::new(o, (d0 + jitter).normalize())
                }
                // One origin, any direction (a diffuse bounce).
                1 => Ray::new(o, warp::square_to_uniform_sphere(rng.next_vec2())),
                // Anything.
                2 => {
                    let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 30.0
                        - Vec3::splat(15.0);
                    Ray::new(o, warp::square_to_uniform_sphere(rng.next_vec2()))
                }
                // Axis-aligned and zero directions.
                _ => {
                    let d = match j % 4 {
                        0 => Vec3::X,
                        1 => -Vec3::Z,
                        2 => Vec3::ZERO,
                        _ => d0,
                    };
                    Ray::new(o, d)
                }
            };
            if j % 5 == 0 {
                r.t_max = 10.0 * rng.next_f32();
            }
            out.push(r);
        }
    }
    out.truncate(n);
    out
}

#[test]
fn packets_find_what_single_rays_find_bit_for_bit() {
    let shapes: Vec<Shape> = scene(3);
    let mut bvh = Bvh::build(&shapes);
    let mut rng = Pcg32::new(9, 0);
    // 1021: the last packet is not full.
    let rays = rays(&mut rng, 20 * 1024 - 3);
    let mut tested = 0;
    for isa in Isa::ALL.into_iter().filter(|i| i.supported()) {
        assert!(bvh.set_isa(isa));
        let mut single = vec![None; rays.len()];
        let mut packet = vec![None; rays.len()];
        bvh.set_packets(false);
        bvh.intersect_raw_n(&shapes, &rays, &mut single);
        bvh.set_packets(true);
        bvh.intersect_raw_n(&shapes, &rays, &mut packet);
        let mut hits = 0;
        for (i, (a, b)) in single.iter().zip(&packet).enumerate() {
            match (a, b) {
                (Some(a), Some(b)) => {
                    assert_eq!(
                        (a.hit.shape, a.hit.prim, a.block, a.lane),
                        (b.hit.shape, b.hit.prim, b.block, b.lane),
                        "{isa:?} ray {i}"
                    );
                    assert_eq!(a.hit.t.to_bits(), b.hit.t.to_bits(), "{isa:?} ray {i}");
                    assert_eq!(
                        a.hit.uv.x.to_bits(),
                        b.hit.uv.x.to_bits(),
                        "{isa:?} ray {i}"
                    );
                    assert_eq!(
                        a.hit.uv.y.to_bits(),
                        b.hit.uv.y.to_bits(),
                        "{isa:?} ray {i}"
                    );
                    hits += 1;
                }
                (None, None) => {}
                _ => panic!("{isa:?} ray {i}: single {a:?} vs packet {b:?}"),
            }
        }
        assert!(hits > 4000 && hits < 19000, "{hits}");
        let mut single = vec![false; rays.len()];
        let mut packet = vec![false; rays.len()];
        bvh.set_packets(false);
        bvh.occluded_n(&shapes, &rays, &mut single);
        bvh.set_packets(true);
        bvh.occluded_n(&shapes, &rays, &mut packet);
        for (i, (a, b)) in single.iter().zip(&packet).enumerate() {
            assert_eq!(a, b, "{isa:?} ray {i}");
        }
        tested += 1;
    }
    assert!(tested >= 1);
}
