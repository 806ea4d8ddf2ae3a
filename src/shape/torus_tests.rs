use super::*;
use crate::accel::{Accel, Bvh};
use crate::math::{Pcg32, Ray, Vec3};
use crate::shape::Shape;
use glam::DVec3;

/// The first root of the analytic torus along a ray, by marching the signed distance (sphere
/// tracing is safe: the distance is exact) and bisecting the last step; f64 throughout.
fn analytic_hit(o: DVec3, d: DVec3, big: f64, small: f64) -> Option<f64> {
    let mut t = 0.0;
    for _ in 0..10_000 {
        let s = torus_distance(o + d * t, big, small);
        if s < 1e-12 {
            return Some(t);
        }
        t += s;
        if t > 100.0 {
            return None;
        }
    }
    None
}

#[test]
fn mesh_hits_agree_with_the_analytic_torus() {
    let (big, small) = (1.0f32, 0.35f32);
    let (nu, nv) = (default_segments_major(big, small), DEFAULT_SEGMENTS_MINOR);
    let shapes = vec![Shape::Mesh(
        TriangleMesh::torus(big, small, None, &Transform::IDENTITY, false).unwrap(),
    )];
    let bvh = Bvh::build(&shapes);
    // Largest gap between a facet and the surface (sagittas of both circles).
    let sag = |r: f64, n: u32| r * (1.0 - (std::f64::consts::PI / n as f64).cos());
    let gap = sag(small as f64, nv) + sag((big + small) as f64, nu);
    let mut rng = Pcg32::new(5, 3);
    let (mut hits, mut worst_t, mut worst_n) = (0, 0.0f64, 0.0f32);
    for _ in 0..3000 {
        let o = crate::math::warp::square_to_uniform_sphere(rng.next_vec2()) * 4.0;
        let target = Vec3::new(
            2.6 * rng.next_f32() - 1.3,
            2.6 * rng.next_f32() - 1.3,
            0.8 * rng.next_f32() - 0.4,
        );
        let ray = Ray::new(o, (target - o).normalize());
        let want = analytic_hit(o.as_dvec3(), ray.d.as_dvec3(), big as f64, small as f64);
        let got = bvh.intersect(&shapes, &ray);
        let (Some(tw), Some(h)) = (want, got) else {
            continue;
        };
        let si = shapes[0].interaction(&h, &ray);
        let p = o.as_dvec3() + ray.d.as_dvec3() * tw;
        // Exact normal at the analytic hit.
        let ring = DVec3::new(p.x, p.y, 0.0).normalize() * big as f64;
        let n = (p - ring).normalize().as_vec3();
        let cos = n.dot(-ray.d);
        if cos < 0.3 {
            continue; // near-grazing: the facet offset becomes a large shift along the ray
        }
        hits += 1;
        worst_t = worst_t.max((si.t as f64 - tw).abs() * cos as f64 / gap);
        worst_n = worst_n.max(si.ns.dot(n).clamp(-1.0, 1.0).acos());
        assert!(si.ng.dot(n) > 0.99, "facet normal points out of the tube");
        assert!((0.0..=1.0).contains(&si.uv.x) && (0.0..=1.0).contains(&si.uv.y));
    }
    assert!(hits > 800, "{hits}");
    // The hit lies on a facet, at most `gap` from the surface along the normal (+ f32 rounding).
    assert!(worst_t < 1.05, "t error {worst_t} sagittas");
    // Interpolated normals are exact at vertices; between them they err by at most half a
    // facet's angle.
    let half_facet = (std::f32::consts::PI / nv.min(nu) as f32) * 1.01;
    assert!(worst_n < half_facet, "normal error {worst_n} rad");
}

#[test]
fn torus_mesh_is_watertight_with_exact_seams() {
    let g = torus_geometry(1.0, 0.3, 40, 16);
    let report = crate::shape::snake::check_closed_mesh(&g);
    assert_eq!(report, Ok(()));
    // UVs wrap exactly once around both circles.
    let uvs = g.uvs.unwrap();
    assert_eq!(uvs.first(), Some(&Vec2::ZERO));
    assert_eq!(uvs.last(), Some(&Vec2::ONE));
}
