use super::*;
use crate::math::{Pcg32, PI};
use crate::shape::test_util::subtended_solid_angle;
use crate::shape::Shape;

fn hit_prim(m: &TriangleMesh, ray: &Ray) -> Option<SurfaceInteraction> {
    let mut best: Option<Hit> = None;
    let mut r = *ray;
    for p in 0..m.triangle_count() as u32 {
        if let Some((t, uv)) = m.intersect_triangle(p, &r) {
            r.t_max = t;
            best = Some(Hit {
                t,
                shape: 0,
                prim: p,
                uv,
            });
        }
    }
    best.map(|h| m.interaction(&h, ray))
}

#[test]
fn rectangle_has_mitsuba_uvs_normal_and_tangents() {
    let m = TriangleMesh::rectangle(&Transform::IDENTITY, false).unwrap();
    assert_eq!(m.triangle_count(), 2);
    assert!((m.area() - 4.0).abs() < 1e-6);
    let ray = Ray::new(Vec3::new(0.5, -0.25, 3.0), -Vec3::Z);
    let si = hit_prim(&m, &ray).unwrap();
    assert!((si.t - 3.0).abs() < 1e-6);
    assert!((si.p - Vec3::new(0.5, -0.25, 0.0)).length() < 1e-6);
    assert!(
        (si.uv - Vec2::new(0.75, 0.375)).length() < 1e-6,
        "{:?}",
        si.uv
    );
    assert!((si.ng - Vec3::Z).length() < 1e-6 && (si.ns - Vec3::Z).length() < 1e-6);
    assert!(
        (si.dpdu - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-5,
        "{}",
        si.dpdu
    );
    assert!(
        (si.dpdv - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-5,
        "{}",
        si.dpdv
    );
    let flipped = TriangleMesh::rectangle(&Transform::IDENTITY, true).unwrap();
    assert!((hit_prim(&flipped, &ray).unwrap().ng + Vec3::Z).length() < 1e-6);
    // A mirroring transform keeps the front on the +z side.
    let mirror = Transform::scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap();
    let mirrored = TriangleMesh::rectangle(&mirror, false).unwrap();
    assert!((hit_prim(&mirrored, &ray).unwrap().ng - Vec3::Z).length() < 1e-6);
}

#[test]
fn cube_normals_point_outwards_with_face_uvs() {
    let t = Transform::translate(Vec3::new(1.0, 2.0, 3.0));
    let m = TriangleMesh::cube(&t, false).unwrap();
    assert_eq!(m.triangle_count(), 12);
    assert!((m.area() - 24.0).abs() < 1e-5);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let centre = Vec3::new(1.0, 2.0, 3.0);
            let off = Vec3::new(0.1, 0.2, 0.3);
            let ray = Ray::new(centre + n * 5.0 + off - n * off.dot(n), -n);
            let si = hit_prim(&m, &ray).unwrap();
            assert!((si.ng - n).length() < 1e-6, "face {n}: {}", si.ng);
            assert!((si.t - 4.0).abs() < 1e-5);
            assert!(si.uv.min_element() > 0.0 && si.uv.max_element() < 1.0);
            // The UV square spans the face: |dp/du| = |dp/dv| = 2.
            assert!((si.dpdu.length() - 2.0).abs() < 1e-5 && (si.dpdv.length() - 2.0).abs() < 1e-5);
        }
    }
}

#[test]
fn construction_validates_and_drops_degenerate_triangles() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(2.0, 0.0, 0.0)];
    let id = Transform::IDENTITY;
    let m = TriangleMesh::new(
        p.clone(),
        None,
        None,
        vec![[0, 1, 2], [0, 1, 3]],
        &id,
        false,
        false,
    )
    .unwrap();
    assert_eq!((m.triangle_count(), m.degenerate_dropped()), (1, 1));
    let e = TriangleMesh::new(p.clone(), None, None, vec![[0, 1, 4]], &id, false, false);
    assert!(
        matches!(e, Err(MeshError::IndexOutOfRange { index: 4, .. })),
        "{e:?}"
    );
    let e = TriangleMesh::new(
        p.clone(),
        Some(vec![Vec3::Z]),
        None,
        vec![[0, 1, 2]],
        &id,
        false,
        false,
    );
    assert!(matches!(e, Err(MeshError::AttributeLength { .. })));
    let e = TriangleMesh::new(p.clone(), None, None, vec![[0, 1, 3]], &id, false, false);
    assert!(matches!(e, Err(MeshError::Empty { dropped: 1 })));
    let mut bad = p;
    bad[1].x = f32::NAN;
    let e = TriangleMesh::new(bad, None, None, vec![[0, 1, 2]], &id, false, false);
    assert!(matches!(e, Err(MeshError::NonFinite(1))));
}

#[test]
fn shading_normals_interpolate_and_default_uvs_follow_mitsuba() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    let n = vec![Vec3::Z, Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0)];
    let id = Transform::IDENTITY;
    let mesh = |face_normals| {
        let (p, n) = (p.clone(), Some(n.clone()));
        TriangleMesh::new(p, n, None, vec![[0, 1, 2]], &id, false, face_normals).unwrap()
    };
    let m = mesh(false);
    let ray = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
    let si = hit_prim(&m, &ray).unwrap();
    let (b1, b2) = (0.25f32, 0.25f32);
    let want = ((1.0 - b1 - b2) * n[0] + b1 * n[1].normalize() + b2 * n[2].normalize()).normalize();
    assert!((si.ns - want).length() < 1e-5, "{} vs {want}", si.ns);
    // Default UVs (0,0), (1,0), (1,1): uv = (b1 + b2, b2).
    assert!(
        (si.uv - Vec2::new(0.5, 0.25)).length() < 1e-6,
        "{:?}",
        si.uv
    );
    let flat = mesh(true);
    assert!((hit_prim(&flat, &ray).unwrap().ns - Vec3::Z).length() < 1e-6);
    let flip = TriangleMesh::new(p, Some(n), None, vec![[0, 1, 2]], &id, true, false).unwrap();
    let sf = hit_prim(&flip, &ray).unwrap();
    assert!((sf.ns + want).length() < 1e-5 && (sf.ng + Vec3::Z).length() < 1e-6);
}

#[test]
fn degenerate_uvs_fall_back_to_a_frame() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    let uv = vec![Vec2::ZERO; 3];
    let m = TriangleMesh::new(
        p,
        None,
        Some(uv),
        vec![[0, 1, 2]],
        &Transform::IDENTITY,
        false,
        false,
    )
    .unwrap();
    let si = hit_prim(&m, &Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z)).unwrap();
    assert!(si.dpdu.is_finite() && si.dpdv.is_finite());
    assert!(si.dpdu.cross(si.dpdv).normalize().dot(si.ng) > 0.99);
}

#[test]
fn shared_edges_are_watertight() {
    // Rays aimed exactly at points of the rectangle's diagonal must hit one of its triangles.
    let t = Transform::rotate(Vec3::new(0.3, 1.0, 0.2), 37.0).unwrap();
    let m = TriangleMesh::rectangle(&t, false).unwrap();
    let mut rng = Pcg32::new(8, 8);
    for _ in 0..20_000 {
        let s = 2.0 * rng.next_f32() - 1.0;
        let target = t.point(Vec3::new(s, s, 0.0));
        let o = target + crate::math::warp::square_to_uniform_sphere(rng.next_vec2()) * 3.0;
        let ray = Ray::new(o, (target - o).normalize());
        assert!(hit_prim(&m, &ray).is_some(), "leak at s = {s}");
    }
}

#[test]
fn sampling_is_uniform_by_area() {
    // Two triangles with areas 1/2 and 3/2: the first gets a quarter of the samples.
    let p = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(3.0, 0.0, 1.0),
        Vec3::new(0.0, 1.0, 1.0),
    ];
    let m = TriangleMesh::new(
        p,
        None,
        None,
        vec![[0, 1, 2], [3, 4, 5]],
        &Transform::IDENTITY,
        false,
        false,
    )
    .unwrap();
    let mut rng = Pcg32::new(4, 4);
    let n = 100_000;
    let (mut first, mut sum_x) = (0usize, 0.0f64);
    for _ in 0..n {
        let s = m
            .sample_direct(Vec3::new(0.3, 0.2, 5.0), rng.next_vec2())
            .unwrap();
        if s.p.z == 0.0 {
            first += 1;
            sum_x += s.p.x as f64;
        }
    }
    let frac = first as f64 / n as f64;
    let sigma = (0.25 * 0.75 / n as f64).sqrt();
    assert!((frac - 0.25).abs() < 4.0 * sigma, "{frac}");
    // Uniform in the first triangle: mean x is the centroid's 1/3, Var x = 1/18.
    let mean = sum_x / first as f64;
    let sigma = (1.0 / 18.0 / first as f64).sqrt();
    assert!((mean - 1.0 / 3.0).abs() < 4.0 * sigma, "{mean}");
}

#[test]
fn sampling_integrates_to_the_rectangle_solid_angle() {
    // A 2a × 2b rectangle seen from distance d on its axis: Ω = 4 asin(ab / √((a²+d²)(b²+d²))).
    let (a, b, d) = (1.5f64, 0.5f64, 0.8f64);
    let t = Transform::scale(Vec3::new(a as f32, b as f32, 1.0)).unwrap();
    let m = TriangleMesh::rectangle(&t, false).unwrap();
    let r = Vec3::new(0.0, 0.0, d as f32);
    let mut rng = Pcg32::new(12, 1);
    let m = Shape::Mesh(m);
    let (mean, sigma) = subtended_solid_angle(&m, r, &mut rng, (200_000, 1e-5), |_| ());
    let want = 4.0 * (a * b / ((a * a + d * d) * (b * b + d * d)).sqrt()).asin();
    assert!(
        (mean - want).abs() < 4.0 * sigma,
        "{mean} ± {sigma} vs {want}"
    );
    assert!(want < 2.0 * PI as f64);
}

#[test]
fn large_meshes_are_checked_and_measured_as_one_by_one() {
    // A mesh past the parallel threshold, with degenerate triangles scattered through it and
    // a mirroring placement (corner order swapped): the kept triangles, their order, the area
    // (summed in triangle order) and the bounds are those of a plain serial pass, on 1 and 3
    // threads; a bad index or value is reported at its first occurrence.
    let mut rng = Pcg32::new(5, 9);
    let nv = 30_000u32;
    let p: Vec<Vec3> = (0..nv)
        .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 10.0 - 5.0)
        .collect();
    let mut tris: Vec<[u32; 3]> = (0..70_000)
        .map(|_| [0; 3].map(|_| (rng.next_f32() * nv as f32) as u32 % nv))
        .collect();
    for i in (0..tris.len()).step_by(97) {
        tris[i][1] = tris[i][0];
    }
    let to_world = Transform::scale(Vec3::new(-2.0, 1.0, 1.0)).unwrap();
    let build = |threads: usize, tris: Vec<[u32; 3]>, p: Vec<Vec3>| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| TriangleMesh::new(p, None, None, tris, &to_world, false, false))
    };
    // The serial reference.
    let wp: Vec<Vec3> = p.iter().map(|&q| to_world.point(q)).collect();
    let (mut kept, mut total, mut bounds) = (Vec::new(), 0.0f64, Bounds3::EMPTY);
    for t in &tris {
        let t = [t[0], t[2], t[1]];
        let [a, b, c] = t.map(|k| wp[k as usize]);
        let area: f32 = 0.5 * (b - a).cross(c - a).length();
        if area > 0.0 && area.is_finite() {
            kept.push(t);
            total += area as f64;
            for q in [a, b, c] {
                bounds.grow(q);
            }
        }
    }
    for threads in [1, 3] {
        let m = build(threads, tris.clone(), p.clone()).unwrap();
        assert_eq!(m.triangle_count(), kept.len());
        assert_eq!(m.degenerate_dropped(), tris.len() - kept.len());
        assert!((0..kept.len()).all(|i| m.triangle(i as u32) == kept[i]));
        assert_eq!(m.area().to_bits(), (total as f32).to_bits());
        assert_eq!(m.bounds(), bounds);
    }
    let mut bad = tris.clone();
    bad[40_000][2] = nv + 3;
    bad[50_000][0] = nv;
    assert!(matches!(
        build(3, bad, p.clone()),
        Err(MeshError::IndexOutOfRange { triangle: 40_000, index, .. }) if index == nv + 3
    ));
    let mut q = p.clone();
    q[20_000].y = f32::NAN;
    q[25_000].x = f32::INFINITY;
    assert!(matches!(
        build(3, tris, q),
        Err(MeshError::NonFinite(20_000))
    ));
}
