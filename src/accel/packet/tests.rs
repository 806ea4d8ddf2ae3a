use crate::accel::tests::scene;
use crate::accel::{Bvh, Isa, RawHit};
use crate::math::{warp, Pcg32, Ray, Vec3};
use crate::shape::Shape;

/// Batches of rays: bundles from one origin in nearby directions (as a pixel's samples),
/// incoherent ones, rays with short, zero or tiny extents, zero, axis-aligned and non-unit
/// directions.
fn rays(rng: &mut Pcg32, n: usize) -> Vec<Ray> {
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let o =
            Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 30.0 - Vec3::splat(15.0);
        let d0 = warp::square_to_uniform_sphere(rng.next_vec2());
        let kind = rng.next_u32() % 5;
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
                // Directions far from unit length; no extent or a tiny one.
                3 => {
                    let scale = [1e-3, 1e3, 0.5, 7.0][j % 4];
                    let mut r =
                        Ray::new(o, warp::square_to_uniform_sphere(rng.next_vec2()) * scale);
                    if j % 7 == 3 {
                        r.t_max = [0.0, 1e-30, f32::MIN_POSITIVE][j % 3];
                    }
                    r
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
    same_hits(&scene(3));
}

/// More shapes than the short table of first triangle ids (see `Bvh::hit`): the packets name
/// each hit's shape and triangle by the long table's search.
#[test]
fn packets_name_shapes_beyond_the_short_table() {
    let mut rng = Pcg32::new(5, 0);
    let mut shapes: Vec<Shape> = Vec::new();
    for i in 0..90 {
        let c =
            Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 24.0 - Vec3::splat(12.0);
        if i % 9 == 0 {
            shapes.push(Shape::Sphere(crate::shape::Sphere::simple(
                c,
                0.5 + rng.next_f32(),
            )));
            continue;
        }
        let t = crate::math::Transform::translate(c)
            .compose(&crate::math::Transform::scale(Vec3::splat(1.0 + rng.next_f32())).unwrap());
        shapes.push(Shape::Mesh(
            crate::shape::TriangleMesh::cube(&t, false).unwrap(),
        ));
    }
    assert!(shapes.len() > crate::accel::bvh::SHORT_TABLE + 2);
    same_hits(&shapes);
}

/// Packets and single rays agree on every instruction set, for closest hits (as found and as
/// named) and for occlusion.
fn same_hits(shapes: &[Shape]) {
    let mut bvh = Bvh::build(shapes);
    let mut rng = Pcg32::new(9, 0);
    // 1021: the last packet is not full.
    let rays = rays(&mut rng, 20 * 1024 - 3);
    let mut tested = 0;
    for isa in Isa::ALL.into_iter().filter(|i| i.supported()) {
        assert!(bvh.set_isa(isa));
        let mut single = vec![None; rays.len()];
        let mut packet = vec![None; rays.len()];
        bvh.set_packets(false);
        bvh.intersect_raw_n(shapes, &rays, &mut single);
        bvh.set_packets(true);
        bvh.intersect_raw_n(shapes, &rays, &mut packet);
        // The same rays as columns of exactly their length (the last packet is loaded from
        // a short tail), and as wider columns (the wavefront's padding).
        let col = |f: fn(&Ray) -> f32, pad: usize| {
            let mut c: Vec<f32> = rays.iter().map(f).collect();
            c.resize(rays.len() + pad, f32::NAN);
            c
        };
        for pad in [0, 16] {
            let o = [
                col(|r| r.o.x, pad),
                col(|r| r.o.y, pad),
                col(|r| r.o.z, pad),
            ];
            let d = [
                col(|r| r.d.x, pad),
                col(|r| r.d.y, pad),
                col(|r| r.d.z, pad),
            ];
            let t_max = col(|r| r.t_max, pad);
            let columns = crate::accel::RayColumns {
                o: [&o[0], &o[1], &o[2]],
                d: [&d[0], &d[1], &d[2]],
                t_max: &t_max,
                n: rays.len(),
            };
            // The walks run at once and queued (interleaved; see `walkers.rs`).
            for interleave in [false, true] {
                bvh.set_interleave(interleave);
                let mut from_columns = vec![None; rays.len()];
                bvh.intersect_raw_columns(shapes, &columns, &mut from_columns);
                for (i, (a, b)) in packet.iter().zip(&from_columns).enumerate() {
                    let bits = |h: &Option<RawHit>| {
                        h.map(|h| {
                            (
                                h.hit.shape,
                                h.hit.prim,
                                h.hit.t.to_bits(),
                                h.hit.uv.x.to_bits(),
                                h.hit.uv.y.to_bits(),
                                h.block,
                                h.lane,
                            )
                        })
                    };
                    assert_eq!(bits(a), bits(b), "{isa:?} pad {pad} {interleave} ray {i}");
                }
                let mut blocked = vec![false; rays.len()];
                bvh.occluded_columns(shapes, &columns, &mut blocked);
                let mut expected = vec![false; rays.len()];
                bvh.occluded_n(shapes, &rays, &mut expected);
                assert_eq!(blocked, expected, "{isa:?} pad {pad} {interleave}");
            }
        }
        let (mut found_single, mut found_packet) = (vec![None; rays.len()], vec![None; rays.len()]);
        bvh.set_packets(false);
        bvh.intersect_n(shapes, &rays, &mut found_single);
        bvh.set_packets(true);
        bvh.intersect_n(shapes, &rays, &mut found_packet);
        for (i, (a, b)) in found_single.iter().zip(&found_packet).enumerate() {
            let bits = |h: &Option<crate::shape::Hit>| {
                h.map(|h| {
                    (
                        h.shape,
                        h.prim,
                        h.t.to_bits(),
                        h.uv.x.to_bits(),
                        h.uv.y.to_bits(),
                    )
                })
            };
            assert_eq!(bits(a), bits(b), "{isa:?} ray {i}");
        }
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
        // Both outcomes are common (a fifth to a third of the rays hit in both scenes).
        assert!(
            hits > rays.len() / 6 && hits < rays.len() * 9 / 10,
            "{hits}"
        );
        let mut single = vec![false; rays.len()];
        let mut packet = vec![false; rays.len()];
        bvh.set_packets(false);
        bvh.occluded_n(shapes, &rays, &mut single);
        bvh.set_packets(true);
        bvh.occluded_n(shapes, &rays, &mut packet);
        for (i, (a, b)) in single.iter().zip(&packet).enumerate() {
            assert_eq!(a, b, "{isa:?} ray {i}");
        }
        tested += 1;
    }
    assert!(tested >= 1);
}
