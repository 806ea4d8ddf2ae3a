//! `torus`: a ring torus around the local z axis, built as a fine triangle mesh whose vertex
//! normals and UVs are the exact ones of the analytic surface.
//!
//! Surface: p(φ, ψ) = ((R + r cos ψ) cos φ, (R + r cos ψ) sin φ, r sin ψ), with R =
//! `major_radius` (centre of the tube to the axis) and r = `minor_radius` (the tube), normal
//! (cos ψ cos φ, cos ψ sin φ, sin ψ) pointing out of the tube. UV: u = φ/2π around the axis,
//! v = ψ/2π around the tube, v = 0 on the outer equator; both wrap at 1, so a `scales` texture
//! with integer `scale_u`/`scale_v` (even `scale_v`) has no seam. The tube is long and thin in
//! UV (2π(R + r) by 2πr at the outside), so scales come out square for
//! `scale_u` ≈ `scale_v`·R/r.
//!
//! Tessellation: `segments_major` × `segments_minor` quads of two triangles; the defaults
//! (enough that the flat facets deviate from the surface by less than 3·10⁻⁴ r around the tube,
//! so silhouettes stay round at any practical resolution) follow the radii. The seam vertices are
//! computed from the same angle as their twins, so the mesh is watertight for rays.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `major_radius` | float | 1.0 | world units | axis to the tube's centre; positive |
//! | `minor_radius` | float | 0.25 | world units | tube radius (less than `major_radius`); positive |
//! | `segments_major` | integer | 128·R/r (64…2048) | — | quads around the axis; between 3 and 8192 |
//! | `segments_minor` | integer | 128 | — | quads around the tube; between 3 and 4096 |
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |
//!
//! `to_world` may be any invertible affine map.
//!
//! Limits: not an exact quartic intersection (hits lie on the facets, within the sagitta above);
//! horn and spindle tori (r ≥ R) are rejected.

use super::load::MeshData;
use super::mesh::{MeshError, TriangleMesh};
use crate::math::{Transform, Vec2};
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Ty};
use std::f64::consts::TAU;

declare!(PLUGIN: super::Parts, Transform = Shape "torus" []
    "a ring (a fine mesh with the analytic torus's normals and UVs)"
    [&[
        Param::length("major_radius", 1.0)
            .doc("axis to the tube's centre"),
        Param::length("minor_radius", 0.25)
            .doc("tube radius (less than `major_radius`)"),
        Param::new("segments_major", Ty::Integer, DefaultValue::Derived("128·R/r (64…2048)"))
            .check(Check::Range(3.0, 8192.0))
            .doc("quads around the axis"),
        Param::int("segments_minor", DEFAULT_SEGMENTS_MINOR as i64)
            .check(Check::Range(3.0, 4096.0))
            .doc("quads around the tube"),
    ], super::PLACEMENT] load);

fn load(a: &mut Args, parent: Transform) -> Result<super::Parts, SceneError> {
    let (to_world, flip) = super::placement(a, &parent)?;
    let major = a.float("major_radius")?;
    let minor = a.float("minor_radius")?;
    if minor >= major {
        let e = format!("must be less than major_radius ({major}), got {minor}");
        return Err(a.error("minor_radius", e));
    }
    let nu = match a.int_opt("segments_major")? {
        Some(n) => n as u32,
        None => default_segments_major(major, minor),
    };
    let nv = a.u32("segments_minor")?;
    let mesh = TriangleMesh::torus(major, minor, Some((nu, nv)), &to_world, flip);
    super::one(a, mesh.map(super::Shape::Mesh))
}

/// Default quads around the tube.
pub(crate) const DEFAULT_SEGMENTS_MINOR: u32 = 128;

/// Default quads around the axis for radii `major`, `minor`: facets about as wide as around the
/// tube at its outer equator.
pub(crate) fn default_segments_major(major: f32, minor: f32) -> u32 {
    ((DEFAULT_SEGMENTS_MINOR as f32 * (major + minor) / minor).round() as u32).clamp(64, 2048)
}

/// Vertices, exact normals, UVs and triangles of the torus (object space).
pub(crate) fn torus_geometry(major: f32, minor: f32, n_major: u32, n_minor: u32) -> MeshData {
    let (nu, nv) = (n_major.max(3) as usize, n_minor.max(3) as usize);
    let (big, small) = (major as f64, minor as f64);
    let mut positions = Vec::with_capacity((nu + 1) * (nv + 1));
    let mut normals = Vec::with_capacity(positions.capacity());
    let mut uvs = Vec::with_capacity(positions.capacity());
    for i in 0..=nu {
        // Seam vertices take the angle of their twin (index mod n), so positions match bit for bit.
        let phi = TAU * (i % nu) as f64 / nu as f64;
        for j in 0..=nv {
            let psi = TAU * (j % nv) as f64 / nv as f64;
            let ring = big + small * psi.cos();
            positions.push(
                glam::DVec3::new(ring * phi.cos(), ring * phi.sin(), small * psi.sin()).as_vec3(),
            );
            normals.push(
                glam::DVec3::new(psi.cos() * phi.cos(), psi.cos() * phi.sin(), psi.sin()).as_vec3(),
            );
            uvs.push(Vec2::new(i as f32 / nu as f32, j as f32 / nv as f32));
        }
    }
    let at = |i: usize, j: usize| (i * (nv + 1) + j) as u32;
    let mut indices = Vec::with_capacity(2 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            // ∂p/∂φ × ∂p/∂ψ points out of the tube: counter-clockwise in (u, v).
            indices.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            indices.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    MeshData {
        positions,
        normals: Some(normals),
        uvs: Some(uvs),
        indices,
    }
}

impl TriangleMesh {
    /// The `torus` shape; radii must satisfy 0 < `minor` < `major`.
    pub fn torus(
        major: f32,
        minor: f32,
        segments: Option<(u32, u32)>,
        to_world: &Transform,
        flip_normals: bool,
    ) -> Result<TriangleMesh, MeshError> {
        let (nu, nv) =
            segments.unwrap_or((default_segments_major(major, minor), DEFAULT_SEGMENTS_MINOR));
        torus_geometry(major, minor, nu, nv).into_mesh(to_world, flip_normals, false)
    }
}

#[cfg(test)]
/// Signed distance from the analytic torus (negative inside the tube).
pub(crate) fn torus_distance(p: glam::DVec3, major: f64, minor: f64) -> f64 {
    let q = (p.x * p.x + p.y * p.y).sqrt() - major;
    (q * q + p.z * p.z).sqrt() - minor
}

#[cfg(test)]
#[path = "torus_tests.rs"]
mod tests;
