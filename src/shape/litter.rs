//! `litter`: fallen leaves scattered on the ground — a procedural leaf-litter layer for scenes
//! that need a forest floor rather than a flat plane (the flagship's ground). One triangle
//! mesh of `count` thin, curled leaf blades at random positions, orientations and sizes.
//!
//! Model. Object space is y-up with the ground at y = 0. A leaf of length ℓ (`size` ±
//! `size_spread`, uniform) and half-width w = `width`·ℓ/2 has its outline, over x ∈ [0, 1]
//! from stalk to tip, at ±w·sin(π·x^0.75) (round at the base, pointed at the tip, widest at
//! 40 %); its surface rises `curl`·w·(y/w)² towards the edges (curled up) plus an arch of
//! `arch`·ℓ·sin(πx) along its length, and rests `lift`·(1 + index/`count`) above the ground,
//! so that overlapping leaves never share a plane (the later one lies on top). Leaves are
//! spread uniformly over the square |x|, |z| ≤ `extent` outside the disc of radius `clear`, each
//! turned by a uniform angle about
//! y. UVs: u along the leaf (0 at the stalk, 1 at the tip), v across it (0.5 on the midrib).
//! Leaves are single sheets facing up: give them a `twosided` BSDF.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `count` | integer | 100 | — | number of leaves; between 1 and 1000000 |
//! | `size` | float | 0.06 | world units | mean leaf length; positive |
//! | `size_spread` | float | 0.35 | of `size` | relative spread of the lengths; in [0, 1) |
//! | `width` | float | 0.5 | of length | leaf width; in (0, 2] |
//! | `curl` | float | 0.25 | of half-width | how far the edges curl up; between 0 and 1 |
//! | `arch` | float | 0.04 | of length | arch along the leaf; between 0 and 1 |
//! | `lift` | float | 0.0005 | world units | height of the first leaf's base (each later one a little higher); positive |
//! | `extent` | float | 0.5 | world units | half-size of the square covered; positive |
//! | `clear` | float | 0.0 | world units | no leaf centred within this of the origin (room for a coiled snake); in [0, 1000000) |
//! | `seed` | integer | 0 | — | changes the layout; between 0 and 4294967295 |
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |
//!
//! Limits: leaves may pass through other objects lying on the ground (place the litter under
//! them, where the intersection is hidden); no stalks, veins or holes (add them with a texture).

use super::load::MeshData;
use crate::math::{Pcg32, Transform, Vec2, Vec3};
use crate::plugin::{declare, Args, Check, Param, SceneError};
use std::f32::consts::PI;

declare!(PLUGIN: super::Parts, Transform = Shape "litter" []
    "fallen leaves: one mesh of curled leaf blades on the ground"
    [&[
        Param::int("count", 100).check(Check::Range(1.0, 1e6)).doc("number of leaves"),
        Param::length("size", 0.06)
            .doc("mean leaf length"),
        Param::float("size_spread", 0.35)
            .check(Check::ClosedOpen(0.0, 1.0))
            .unit("of `size`")
            .doc("relative spread of the lengths"),
        Param::up_to("width", 0.5, 2.0, "of length")
            .doc("leaf width"),
        Param::fraction("curl", 0.25)
            .unit("of half-width")
            .doc("how far the edges curl up"),
        Param::fraction("arch", 0.04)
            .unit("of length")
            .doc("arch along the leaf"),
        Param::length("lift", 0.0005)
            .doc("height of the first leaf's base (each later one a little higher)"),
        Param::length("extent", 0.5)
            .doc("half-size of the square covered"),
        Param::float("clear", 0.0)
            .check(Check::ClosedOpen(0.0, 1e6))
            .unit("world units")
            .doc("no leaf centred within this of the origin (room for a coiled snake)"),
        Param::u32("seed", 0).doc("changes the layout"),
    ], super::PLACEMENT] load);

fn load(a: &mut Args, parent: Transform) -> Result<super::Parts, SceneError> {
    let (to_world, flip) = super::placement(a, &parent)?;
    let p = LitterParams {
        count: a.u32("count")?,
        size: a.float("size")?,
        size_spread: a.float("size_spread")?,
        width: a.float("width")?,
        curl: a.float("curl")?,
        arch: a.float("arch")?,
        lift: a.float("lift")?,
        extent: a.float("extent")?,
        clear: a.float("clear")?,
        seed: a.u32("seed")?,
    };
    let g = litter(&p);
    let mesh = super::TriangleMesh::new(
        g.positions,
        g.normals,
        g.uvs,
        g.indices,
        &to_world,
        flip,
        false,
    );
    super::one(a, mesh.map(super::Shape::Mesh))
}

/// Parameters of the litter (see the module header).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LitterParams {
    pub count: u32,
    pub size: f32,
    pub size_spread: f32,
    pub width: f32,
    pub curl: f32,
    pub arch: f32,
    pub lift: f32,
    pub extent: f32,
    pub clear: f32,
    pub seed: u32,
}

impl Default for LitterParams {
    fn default() -> LitterParams {
        LitterParams {
            count: 100,
            size: 0.06,
            size_spread: 0.35,
            width: 0.5,
            curl: 0.25,
            arch: 0.04,
            lift: 0.0005,
            extent: 0.5,
            clear: 0.0,
            seed: 0,
        }
    }
}

/// Grid of a leaf: segments along and across.
const ALONG: usize = 8;
const ACROSS: usize = 4;

/// The litter's mesh in object space.
pub(crate) fn litter(p: &LitterParams) -> MeshData {
    let mut rng = Pcg32::new(0x1eaf ^ p.seed as u64, 7);
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    let mut indices = Vec::new();
    for leaf in 0..p.count {
        let len = p.size * (1.0 + p.size_spread * (2.0 * rng.next_f32() - 1.0));
        let half = 0.5 * p.width * len;
        // Uniform over the square outside the cleared disc (rejection; a disc covering the
        // whole square leaves the last draw, so a bad `clear` cannot hang).
        let mut centre = (0.0, 0.0);
        for _ in 0..64 {
            centre = (
                p.extent * (2.0 * rng.next_f32() - 1.0),
                p.extent * (2.0 * rng.next_f32() - 1.0),
            );
            if centre.0 * centre.0 + centre.1 * centre.1 >= p.clear * p.clear {
                break;
            }
        }
        let (cx, cz) = centre;
        let turn = 2.0 * PI * rng.next_f32();
        let (s, c) = turn.sin_cos();
        let base = p.lift * (1.0 + leaf as f32 / p.count.max(1) as f32);
        // Local (x along, y across, z up) → world, centred on the leaf's middle.
        let place = |x: f32, y: f32, z: f32| {
            let lx = (x - 0.5) * len;
            Vec3::new(cx + c * lx - s * y, base + z, cz + s * lx + c * y)
        };
        let surface = |i: usize, j: usize| {
            let x = i as f32 / ALONG as f32;
            let across = 2.0 * j as f32 / ACROSS as f32 - 1.0; // −1 … 1
            let w = half * (PI * x.powf(0.75)).sin().max(0.0);
            let z = p.curl * half * across * across * (w / half.max(1e-12))
                + p.arch * len * (PI * x).sin();
            (place(x, across * w, z), Vec2::new(x, 0.5 * (across + 1.0)))
        };
        let first = positions.len() as u32;
        for i in 0..=ALONG {
            for j in 0..=ACROSS {
                let (q, uv) = surface(i, j);
                positions.push(q);
                uvs.push(uv);
                // Normal by central differences of the surface (leaves are thin and smooth).
                let (a, _) = surface(i.saturating_sub(1), j);
                let (b, _) = surface((i + 1).min(ALONG), j);
                let (d, _) = surface(i, j.saturating_sub(1));
                let (e, _) = surface(i, (j + 1).min(ACROSS));
                let n = (b - a).cross(e - d);
                normals.push(if n.length() > 0.0 {
                    n.normalize()
                } else {
                    Vec3::Y
                });
            }
        }
        let id = |i: usize, j: usize| first + (i * (ACROSS + 1) + j) as u32;
        for i in 0..ALONG {
            for j in 0..ACROSS {
                let (a, b, cc, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                // The stalk and tip columns are points: skip the triangles that collapse there.
                if i > 0 {
                    indices.push([a, d, b]);
                }
                if i + 1 < ALONG {
                    indices.push([b, d, cc]);
                }
            }
        }
    }
    MeshData {
        positions,
        normals: Some(normals),
        uvs: Some(uvs),
        indices,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leaves_lie_on_the_ground_face_up_and_stay_in_their_square() {
        let p = LitterParams {
            count: 50,
            ..LitterParams::default()
        };
        let g = litter(&p);
        assert_eq!(g.indices.len(), 50 * ACROSS * (2 * ALONG - 2));
        let reach = p.extent + 0.5 * p.size * (1.0 + p.size_spread);
        for q in &g.positions {
            assert!(q.y >= p.lift - 1e-7 && q.y < 0.05, "{q}");
            assert!(q.x.abs() <= reach && q.z.abs() <= reach);
        }
        // Faces look up (towards +y), and no triangle is degenerate.
        for t in &g.indices {
            let [a, b, c] = t.map(|i| g.positions[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.length() > 0.0);
            assert!(n.normalize().y > 0.3, "{n}");
        }
        // Leaves differ in size and the seed changes the layout.
        let other = litter(&LitterParams {
            seed: 1,
            ..p.clone()
        });
        assert_ne!(other.positions[0], g.positions[0]);
        // A cleared disc keeps leaf centres out.
        let cleared = litter(&LitterParams {
            clear: 0.3,
            ..p.clone()
        });
        for k in 0..50 {
            let mid = (ALONG / 2) * (ACROSS + 1) + ACROSS / 2;
            let q = cleared.positions[k * (ALONG + 1) * (ACROSS + 1) + mid];
            assert!(q.x.hypot(q.z) > 0.3 - 0.01, "{q}");
        }
        // Every leaf sits at its own height (no two coplanar).
        let bases: std::collections::HashSet<u32> = (0..50)
            .map(|k| g.positions[k * (ALONG + 1) * (ACROSS + 1)].y.to_bits())
            .collect();
        assert_eq!(bases.len(), 50);
    }
}
