//! Mitsuba's `rectangle` and `cube`, built as small triangle meshes (their plugins:
//! [`super::rectangle`], [`super::cube`]).
//!
//! `rectangle`: the square [−1, 1]² in the local xy-plane at z = 0, normal +z, with UV (0, 0)
//! at (−1, −1) and (1, 1) at (1, 1). `cube`: [−1, 1]³ with outward normals, 12 triangles, each
//! face carrying its own UV square (0, 0)…(1, 1). Both are flat-shaded (no vertex normals).
//!
//! Limits: Mitsuba 3's rectangle is analytic; as a two-triangle mesh its interior diagonal is an
//! edge, which only matters for code that looks at the primitive index.
use super::mesh::{MeshError, TriangleMesh};
use super::{Parts, Shape};
use crate::math::{Transform, Vec2, Vec3};
use crate::plugin::{Args, SceneError};

/// The loader of the fixed meshes (`rectangle`, `cube`): `mesh` built at the shape's placement.
pub(crate) fn load(
    a: &mut Args,
    parent: &Transform,
    mesh: fn(&Transform, bool) -> Result<TriangleMesh, MeshError>,
) -> Result<Parts, SceneError> {
    let (to_world, flip) = super::placement(a, parent)?;
    super::one(a, mesh(&to_world, flip).map(Shape::Mesh))
}

impl TriangleMesh {
    /// Mitsuba's `rectangle`.
    pub fn rectangle(to_world: &Transform, flip_normals: bool) -> Result<TriangleMesh, MeshError> {
        let positions = vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ];
        let uvs = vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
        let indices = vec![[0, 1, 2], [0, 2, 3]];
        flat(positions, uvs, indices, to_world, flip_normals)
    }

    /// Mitsuba's `cube`.
    pub fn cube(to_world: &Transform, flip_normals: bool) -> Result<TriangleMesh, MeshError> {
        let mut positions = Vec::with_capacity(24);
        let mut uvs = Vec::with_capacity(24);
        let mut indices = Vec::with_capacity(12);
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let mut n = Vec3::ZERO;
                n[axis] = sign;
                // Tangents (s, t) with s × t = n, so corners listed s-then-t wind
                // counter-clockwise seen from outside.
                let mut s = Vec3::ZERO;
                s[(axis + 1) % 3] = 1.0;
                let t = n.cross(s);
                let base = positions.len() as u32;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    positions.push(n + a * s + b * t);
                    uvs.push(Vec2::new(0.5 * (a + 1.0), 0.5 * (b + 1.0)));
                }
                indices.push([base, base + 1, base + 2]);
                indices.push([base, base + 2, base + 3]);
            }
        }
        flat(positions, uvs, indices, to_world, flip_normals)
    }
}

/// A flat-shaded mesh with UVs and face normals, as both primitives are.
fn flat(
    positions: Vec<Vec3>,
    uvs: Vec<Vec2>,
    indices: Vec<[u32; 3]>,
    to_world: &Transform,
    flip_normals: bool,
) -> Result<TriangleMesh, MeshError> {
    TriangleMesh::new(
        positions,
        None,
        Some(uvs),
        indices,
        to_world,
        flip_normals,
        true,
    )
}
