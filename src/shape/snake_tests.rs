use super::*;

fn coarse() -> SnakeParams {
    SnakeParams {
        segments_along: 120,
        segments_around: 24,
        ..SnakeParams::default()
    }
}

#[test]
fn snake_mesh_is_closed_and_has_no_degenerate_triangles() {
    for p in [coarse(), SnakeParams::default()] {
        let g = snake_geometry(&p);
        assert_eq!(check_closed_mesh(&g), Ok(()));
        let n = (p.segments_along as usize - 2) * p.segments_around as usize * 2
            + 2 * p.segments_around as usize;
        assert_eq!(g.indices.len(), n);
    }
    // The checker itself rejects an open mesh.
    let mut g = snake_geometry(&coarse());
    g.indices.pop();
    assert!(check_closed_mesh(&g).is_err());
}

#[test]
fn snake_winds_outwards_with_the_volume_of_its_sections() {
    let p = SnakeParams::default();
    let g = snake_geometry(&p);
    // Divergence theorem: positive when the triangles face out.
    let vol: f64 = g
        .indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| g.positions[k as usize].as_dvec3());
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    // Section area: half a disc on the back, a squashed half on the belly, integrated along s.
    let n = 4000;
    let area_ratio = {
        let m = 2000;
        (0..m)
            .map(|i| {
                let a = TAU * (i as f64 + 0.5) / m as f64;
                let (x, y) = p.section(a, 1.0);
                let (x2, y2) = p.section(a + TAU / m as f64, 1.0);
                0.5 * (x * y2 - x2 * y)
            })
            .sum::<f64>()
    };
    let want: f64 = (0..n)
        .map(|i| {
            let t = (i as f64 + 0.5) / n as f64;
            area_ratio * p.radius_at(t).powi(2) * p.length as f64 / n as f64
        })
        .sum();
    assert!(
        (vol / want - 1.0).abs() < 0.02,
        "volume {vol} vs sections {want}"
    );
    // Vertex normals agree with the faces around them: within 60° on the body; on the outside
    // (within 90°) at the tips, where a single apex normal serves a fan of steep facets.
    let normals = g.normals.as_ref().unwrap();
    let fans = g.indices.len() - 2 * p.segments_around as usize;
    for (i, t) in g.indices.iter().enumerate() {
        let [a, b, c] = t.map(|k| g.positions[k as usize]);
        let f = (b - a).cross(c - a).normalize();
        let min = if i < fans { 0.5 } else { 0.0 };
        for &k in t {
            assert!(normals[k as usize].dot(f) > min, "triangle {i}");
        }
    }
}

#[test]
fn snake_uvs_are_in_range_and_continuous_except_at_the_belly_seam() {
    let p = SnakeParams::default();
    let g = snake_geometry(&p);
    let uvs = g.uvs.as_ref().unwrap();
    let v_max = (p.length as f64 / p.perimeter()) as f32;
    for uv in uvs {
        assert!((0.0..=1.0).contains(&uv.x) && (0.0..=v_max + 1e-5).contains(&uv.y));
    }
    let du = 1.0 / p.segments_around as f32;
    for t in &g.indices {
        let [a, b, c] = t.map(|k| uvs[k as usize]);
        for (x, y) in [(a, b), (b, c), (c, a)] {
            // No triangle spans the seam: neighbours differ by one step around.
            assert!((x.x - y.x).abs() <= du + 1e-6, "{x:?} {y:?}");
            assert!((x.y - y.y).abs() < 0.05 * v_max);
        }
    }
    // The seam (u = 0 and u = 1) runs along the belly: the lowest vertex of every ring.
    let ring = p.segments_around as usize + 1;
    for k in 0..p.segments_along as usize - 1 {
        let block = &g.positions[k * ring..(k + 1) * ring];
        let lowest = block.iter().map(|q| q.y).fold(f32::MAX, f32::min);
        assert!(block[0].y <= lowest + 1e-6 && block[ring - 1] == block[0]);
    }
}

/// dp/du and dp/dv of a triangle from its UVs.
fn tangents(p: [Vec3; 3], uv: [Vec2; 3]) -> (Vec3, Vec3) {
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let det = d1.x * d2.y - d1.y * d2.x;
    ((d2.y * e1 - d1.y * e2) / det, (d1.x * e2 - d2.x * e1) / det)
}

#[test]
fn scales_come_out_square_on_the_thick_body_and_it_rests_on_the_ground() {
    let p = SnakeParams::default();
    let g = snake_geometry(&p);
    let uvs = g.uvs.as_ref().unwrap();
    let na = p.segments_around as usize;
    // On the back midline (where bending does not stretch the surface), along the thick body:
    // the cross-section is evenly parametrised by arc length, so |dp/du| = perimeter = |dp/dv|.
    for frac in [0.3, 0.4, 0.5] {
        let k = (frac * p.segments_along as f64) as usize;
        let tri = &g.indices[(k * na + na / 2) * 2];
        let (dpdu, dpdv) = tangents(
            tri.map(|i| g.positions[i as usize]),
            tri.map(|i| uvs[i as usize]),
        );
        let ratio = dpdu.length() / dpdv.length();
        assert!(
            (ratio - 1.0).abs() < 0.03,
            "|dp/du|/|dp/dv| = {ratio} at {frac}"
        );
    }
    let min_y = g.positions.iter().map(|q| q.y).fold(f32::MAX, f32::min);
    assert!(min_y.abs() < 1e-3 * p.radius, "{min_y}");
    // The centreline is `length` long: the tips' v coordinates span length/perimeter.
    let v_tail = uvs.iter().map(|uv| uv.y).fold(0.0f32, f32::max);
    assert!((v_tail as f64 * p.perimeter() / p.length as f64 - 1.0).abs() < 1e-4);
    // Head is rounder than the neck, the tail ends in a point.
    assert!(p.radius_at(1.4 * p.head_length as f64) < 0.85 * p.radius as f64);
    assert!(p.radius_at(0.0) == 0.0 && p.radius_at(1.0) == 0.0);
    let mesh =
        TriangleMesh::snake(&p, &Transform::translate(Vec3::new(0.0, 2.0, 0.0)), false).unwrap();
    assert!((mesh.bounds().min.y - 2.0).abs() < 1e-3);
    assert_eq!(mesh.degenerate_dropped(), 0);
}
