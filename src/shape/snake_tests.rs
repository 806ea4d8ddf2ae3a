use super::*;
use crate::math::{Vec2, Vec3};

fn coarse() -> SnakeParams {
    SnakeParams {
        segments_along: 160,
        segments_around: 24,
        ..SnakeParams::default()
    }
}

fn coil() -> SnakeParams {
    SnakeParams {
        pose: Pose::Coil,
        ..SnakeParams::default()
    }
}

/// Body, belly and head concatenated (they share border vertices by position).
fn skin(parts: &[(Part, MeshData)]) -> MeshData {
    let mut out = MeshData {
        positions: Vec::new(),
        normals: Some(Vec::new()),
        uvs: Some(Vec::new()),
        indices: Vec::new(),
    };
    for (part, g) in parts {
        if *part == Part::Eyes {
            continue;
        }
        let base = out.positions.len() as u32;
        out.positions.extend(&g.positions);
        out.normals
            .as_mut()
            .unwrap()
            .extend(g.normals.as_ref().unwrap());
        out.uvs.as_mut().unwrap().extend(g.uvs.as_ref().unwrap());
        out.indices
            .extend(g.indices.iter().map(|t| t.map(|i| i + base)));
    }
    out
}

fn part(parts: &[(Part, MeshData)], which: Part) -> &MeshData {
    &parts.iter().find(|(p, _)| *p == which).unwrap().1
}

#[test]
fn the_parts_weld_into_one_closed_surface_and_the_eyes_are_closed() {
    for p in [coarse(), SnakeParams::default(), coil()] {
        let parts = snake_parts(&p);
        assert_eq!(
            parts.iter().map(|(p, _)| *p).collect::<Vec<_>>(),
            Part::ALL.to_vec()
        );
        assert_eq!(check_closed_mesh(&skin(&parts)), Ok(()));
        assert_eq!(check_closed_mesh(part(&parts, Part::Eyes)), Ok(()));
    }
    // The checker itself rejects an open mesh.
    let mut g = skin(&snake_parts(&coarse()));
    g.indices.pop();
    assert!(check_closed_mesh(&g).is_err());
    // Without eyes there are three parts.
    let p = SnakeParams {
        eyes: false,
        ..coarse()
    };
    assert_eq!(snake_parts(&p).len(), 3);
}

#[test]
fn vertices_on_the_parts_borders_agree_in_position_and_normal() {
    let parts = snake_parts(&coarse());
    let mut seen: HashMap<[u32; 3], Vec3> = HashMap::new();
    let mut shared = 0;
    for (which, g) in &parts {
        if *which == Part::Eyes {
            continue;
        }
        for (q, n) in g.positions.iter().zip(g.normals.as_ref().unwrap()) {
            let key = q.to_array().map(f32::to_bits);
            if let Some(m) = seen.insert(key, *n) {
                assert!((m - *n).length() < 1e-6, "normals differ at {q}");
                shared += 1;
            }
        }
    }
    // The head/body ring and the two belly edges (tip vertices repeat per column).
    assert!(shared > 2 * 160, "{shared}");
}

#[test]
fn the_body_winds_outwards_with_the_volume_of_its_sections() {
    let p = SnakeParams::default();
    let g = skin(&snake_parts(&p));
    // Divergence theorem: positive when the triangles face out.
    let vol: f64 = g
        .indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| g.positions[k as usize].as_dvec3());
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    let n = 4000;
    let want: f64 = (0..n)
        .map(|i| {
            let t = (i as f64 + 0.5) / n as f64;
            let r = p.height_ratios(t);
            let a = p.half_width(t);
            let m = 720;
            let area: f64 = (0..m)
                .map(|j| {
                    let al = std::f64::consts::TAU * j as f64 / m as f64;
                    let (x, y) = p.section(al, a, r);
                    let (x2, y2) = p.section(al + std::f64::consts::TAU / m as f64, a, r);
                    0.5 * (x * y2 - x2 * y)
                })
                .sum();
            area * p.length as f64 / n as f64
        })
        .sum();
    assert!(
        (vol / want - 1.0).abs() < 0.02,
        "volume {vol} vs sections {want}"
    );
    // Vertex normals agree with the faces around them away from the tips.
    let normals = g.normals.as_ref().unwrap();
    let mut bad = 0;
    for t in &g.indices {
        let [a, b, c] = t.map(|k| g.positions[k as usize]);
        let f = (b - a).cross(c - a).normalize();
        if t.iter().any(|&k| normals[k as usize].dot(f) < 0.5) {
            bad += 1;
        }
    }
    // Only the two fans at the tips may disagree by more than 60°.
    assert!(bad <= 2 * p.segments_around as usize, "{bad}");
}

#[test]
fn the_profile_is_smooth_from_snout_to_tail_without_a_crease_or_bulb() {
    // A crease is a jump in slope: the second difference over δ then stays near the jump as δ
    // shrinks, where for a C¹ profile it goes to 0 like δ. Compare two step sizes away from
    // the rounded tips (whose slopes are infinite by design).
    let p = SnakeParams::default();
    let h = p.head_length as f64;
    let worst = |d: f64| {
        let mut w = 0.0f64;
        let mut t = p.snout as f64 * h + 2.0 * d;
        while t < 1.0 - 0.05 * p.tail_length as f64 {
            for f in [
                &|t: f64| p.half_width(t) / p.radius as f64,
                &|t: f64| p.height_ratios(t).0,
                &|t: f64| p.height_ratios(t).1,
                &|t: f64| p.lift(t) / p.radius as f64,
            ] as [&dyn Fn(f64) -> f64; 4]
            {
                w = w.max((f(t + d) - 2.0 * f(t) + f(t - d)).abs() / d);
            }
            t += d * 0.37;
        }
        w
    };
    let (a, b) = (worst(1e-4), worst(1e-5));
    assert!(b < 0.2 * a + 1e-3, "slope jumps: {a} at 1e-4, {b} at 1e-5");
    // No bulb: the head is never wider than the body, and the neck is only a little narrower
    // than the head (the sunbeam snake's head is scarcely distinct from its neck).
    let widest_head = (0..100)
        .map(|i| p.half_width(1.2 * h * i as f64 / 100.0))
        .fold(0.0, f64::max);
    let neck = p.half_width(1.35 * h);
    assert!(widest_head < 0.85 * p.radius as f64);
    assert!(neck > 0.9 * widest_head && neck < widest_head);
    // A flattened head: its height is about `head_height` of its width.
    let (up, down) = p.height_ratios(0.6 * h);
    assert!((up + down) / 2.0 < 0.7 && (up + down) / 2.0 > 0.4);
    // The tail is its last tenth: full-bodied at the vent, a point at the end.
    assert!(p.half_width(p.vent()) > 0.75 * p.radius as f64);
    assert_eq!(p.half_width(1.0), 0.0);
    assert_eq!(p.half_width(0.0), 0.0);
}

/// dp/du and dp/dv of a triangle from its UVs.
fn tangents(p: [Vec3; 3], uv: [Vec2; 3]) -> (Vec3, Vec3) {
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let det = d1.x * d2.y - d1.y * d2.x;
    ((d2.y * e1 - d1.y * e2) / det, (d1.x * e2 - d2.x * e1) / det)
}

#[test]
fn dorsal_scales_stay_square_from_neck_to_tail() {
    // On the back midline (where bending does not stretch the surface): |dp/du| = |dp/dv|
    // wherever the dorsal arc is above its floor, i.e. scale rows narrow with the body instead
    // of stretching.
    let p = SnakeParams::default();
    let parts = snake_parts(&p);
    let g = part(&parts, Part::Body);
    let uvs = g.uvs.as_ref().unwrap();
    let mut checked = 0;
    for tri in &g.indices {
        let uv = tri.map(|i| uvs[i as usize]);
        let centre = (uv[0] + uv[1] + uv[2]) / 3.0;
        if (centre.x - 0.5).abs() > 0.03 {
            continue;
        }
        let q = tri.map(|i| g.positions[i as usize]);
        let (du, dv) = tangents(q, uv);
        let ratio = du.length() / dv.length();
        let width = du.length() as f64 / p.dorsal_arc();
        if width > 0.25 {
            assert!(
                (ratio - 1.0).abs() < 0.035,
                "|dp/du|/|dp/dv| = {ratio} at v {}",
                centre.y
            );
            checked += 1;
        }
    }
    assert!(checked > 500, "{checked}");
}

#[test]
fn uvs_span_their_parts_and_the_head_map() {
    let parts = snake_parts(&SnakeParams::default());
    for (which, g) in &parts {
        let uvs = g.uvs.as_ref().unwrap();
        let used: Vec<Vec2> = g
            .indices
            .iter()
            .flatten()
            .map(|&i| uvs[i as usize])
            .collect();
        let (lo, hi) = used.iter().fold(
            (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)),
            |(a, b), v| (a.min(*v), b.max(*v)),
        );
        match which {
            Part::Head => {
                assert!(
                    lo.abs().max_element() < 1e-6 && (hi - Vec2::ONE).abs().max_element() < 0.03,
                    "{lo} {hi}"
                );
            }
            Part::Body | Part::Belly => {
                assert!(
                    lo.x > -1e-6 && hi.x < 1.0 + 1e-6 && lo.y > -1e-6,
                    "{which:?} {lo} {hi}"
                );
                // About (length / dorsal arc) rows of square scales.
                assert!(hi.y > 10.0, "{which:?} {hi}");
            }
            Part::Eyes => {}
        }
    }
}

#[test]
fn the_belly_rests_on_the_ground_and_the_eyes_sit_on_the_head() {
    for p in [SnakeParams::default(), coil()] {
        let parts = snake_parts(&p);
        let g = skin(&parts);
        let min_y = g.positions.iter().map(|q| q.y).fold(f32::MAX, f32::min);
        assert!(min_y >= 0.0 && min_y < 1e-2 * p.radius, "{min_y}");
        // The eyes: small, above the ground, within a head length of the snout tip.
        let eyes = part(&parts, Part::Eyes);
        let tip = part(&parts, Part::Head).positions[0];
        for q in &eyes.positions {
            assert!(q.y > 0.0);
            assert!((*q - tip).length() < p.head_length * p.length);
        }
    }
    let mesh = TriangleMesh::snake_parts(
        &SnakeParams::default(),
        &Transform::translate(Vec3::Y * 2.0),
        false,
    )
    .unwrap();
    for (_, m) in &mesh {
        assert!(m.bounds().min.y >= 2.0 - 1e-4);
        assert_eq!(m.degenerate_dropped(), 0);
    }
}

#[test]
fn resting_poses_do_not_pass_through_themselves_and_bad_ones_are_caught() {
    assert_eq!(self_intersection(&SnakeParams::default(), 2000), None);
    assert_eq!(self_intersection(&coil(), 2000), None);
    // The coil's turns touch when they are closer than the body is wide.
    let tight = SnakeParams {
        coil_spacing: 0.8,
        ..coil()
    };
    assert!(self_intersection(&tight, 2000).is_some());
    // An S-curve with a swing much larger than its wavelength folds onto itself.
    let wild = SnakeParams {
        waves: 4.0,
        amplitude: 1.2,
        ..SnakeParams::default()
    };
    assert!(self_intersection(&wild, 2000).is_some());
    // The footprint of the coil: its turns are `coil_spacing`·2R apart.
    let p = coil();
    let parts = snake_parts(&p);
    let g = part(&parts, Part::Body);
    let r_max = g
        .positions
        .iter()
        .map(|q| (q.x * q.x + q.z * q.z).sqrt())
        .fold(0.0, f32::max);
    assert!(r_max < 0.5 * p.length, "{r_max}");
}
