//! Geometric shapes, their ray intersection, surface parametrisation and area sampling.
//!
//! Scene shapes are flattened into primitives for the BVH: an analytic sphere, disk or cylinder is one
//! primitive, a triangle mesh contributes one primitive per triangle. Intersection returns a
//! compact [`Hit`]; the full [`SurfaceInteraction`] is computed only for the closest hit.

use crate::math::{Bounds3, Ray, Transform, Vec2, Vec3};

/// The compact result of a ray–primitive test.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Index of the shape in the scene's shape list.
    pub shape: u32,
    /// Primitive index within the shape (triangle index; 0 for analytic shapes).
    pub prim: u32,
    /// Shape-specific coordinates of the hit (barycentrics b1, b2 for triangles).
    pub uv: Vec2,
}

/// Local surface geometry at a ray hit.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction {
    /// Hit point (world space).
    pub p: Vec3,
    /// Ray parameter.
    pub t: f32,
    /// Unit geometric normal, facing the shape's outside (flipped by `flip_normals`).
    pub ng: Vec3,
    /// Unit shading normal (interpolated vertex normal; equal to `ng` without one), on the same
    /// side as `ng`.
    pub ns: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
    /// Position derivatives with respect to u and v (tangents).
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    /// Shape index.
    pub shape: u32,
    /// Primitive index.
    pub prim: u32,
}

/// A point sampled on a shape for direct lighting.
#[derive(Clone, Copy, Debug)]
pub struct ShapeSample {
    pub p: Vec3,
    /// Unit normal at `p` (same orientation convention as [`SurfaceInteraction::ng`]).
    pub n: Vec3,
    pub uv: Vec2,
    /// Density with respect to solid angle as seen from the reference point.
    pub pdf: f32,
}

pub mod alias;
pub mod cube;
pub mod cylinder;
pub mod disk;
pub(crate) mod litter;
pub mod load;
pub mod mesh;
pub mod obj;
pub mod ply;
pub mod primitives;
pub mod rectangle;
pub mod serialized;
pub mod snake;
pub mod sphere;
#[cfg(test)]
mod test_util;
pub mod torus;

pub use cylinder::Cylinder;
pub(crate) use disk::Disk;
pub use load::{LoadError, MeshData, MeshOptions};
pub use mesh::{MeshError, TriangleMesh};
pub use sphere::Sphere;

/// Invalid parameters for an analytic shape.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShapeError {
    /// The radius is not a positive finite number.
    #[error("{shape}: radius must be positive and finite, got {radius}")]
    BadRadius { shape: &'static str, radius: f32 },
    /// The transform scales differently along different axes where the shape needs a uniform scale.
    #[error("{shape}: to_world must be a similarity (rotation, translation, uniform scale); its axis scales are {scales:?}")]
    NonUniformScale {
        shape: &'static str,
        scales: [f32; 3],
    },
    /// The transform is singular or not finite.
    #[error("{shape}: to_world is singular or not finite")]
    BadTransform { shape: &'static str },
}

/// A shape in the scene.
#[derive(Clone, Debug)]
pub enum Shape {
    Sphere(Sphere),
    Disk(Disk),
    Cylinder(Cylinder),
    Mesh(TriangleMesh),
}

impl Shape {
    /// Number of BVH primitives this shape contributes.
    pub fn prim_count(&self) -> usize {
        match self {
            Shape::Mesh(m) => m.triangle_count(),
            _ => 1,
        }
    }

    /// World-space bounds of one primitive.
    pub(crate) fn prim_bounds(&self, prim: u32) -> Bounds3 {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Disk(d) => d.bounds(),
            Shape::Cylinder(c) => c.bounds(),
            Shape::Mesh(m) => m.triangle_bounds(prim),
        }
    }

    /// Intersects one primitive; returns the ray parameter in (0, ray.t_max) and the
    /// shape-specific hit coordinates.
    #[inline]
    pub(crate) fn intersect_prim(&self, prim: u32, ray: &Ray) -> Option<(f32, Vec2)> {
        match self {
            Shape::Sphere(s) => s.intersect(ray),
            Shape::Disk(d) => d.intersect(ray),
            Shape::Cylinder(c) => c.intersect(ray),
            Shape::Mesh(m) => m.intersect_triangle(prim, ray),
        }
    }

    /// Full surface geometry for a hit on this shape.
    pub fn interaction(&self, hit: &Hit, ray: &Ray) -> SurfaceInteraction {
        match self {
            Shape::Sphere(s) => s.interaction(hit, ray),
            Shape::Disk(d) => d.interaction(hit, ray),
            Shape::Cylinder(c) => c.interaction(hit, ray),
            Shape::Mesh(m) => m.interaction(hit, ray),
        }
    }

    /// World-space bounds of the whole shape.
    pub fn bounds(&self) -> Bounds3 {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Disk(d) => d.bounds(),
            Shape::Cylinder(c) => c.bounds(),
            Shape::Mesh(m) => m.bounds(),
        }
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        match self {
            Shape::Sphere(s) => s.area(),
            Shape::Disk(d) => d.area(),
            Shape::Cylinder(c) => c.area(),
            Shape::Mesh(m) => m.area(),
        }
    }

    /// Samples a point on the shape as seen from `ref_p`, with the density in solid angle.
    /// Spheres sample the cone of directions they subtend; other shapes sample area uniformly.
    pub(crate) fn sample_direct(&self, ref_p: Vec3, u: Vec2) -> Option<ShapeSample> {
        match self {
            Shape::Sphere(s) => s.sample_direct(ref_p, u),
            Shape::Disk(d) => d.sample_direct(ref_p, u),
            Shape::Cylinder(c) => c.sample_direct(ref_p, u),
            Shape::Mesh(m) => m.sample_direct(ref_p, u),
        }
    }

    /// Solid-angle density of [`Shape::sample_direct`] choosing the point `p` (normal `n`) on the
    /// shape, hit from `ref_p`.
    pub(crate) fn pdf_direct(&self, ref_p: Vec3, p: Vec3, n: Vec3) -> f32 {
        match self {
            Shape::Sphere(s) => s.pdf_direct(ref_p, p, n),
            Shape::Disk(d) => d.pdf_direct(ref_p, p, n),
            Shape::Cylinder(c) => c.pdf_direct(ref_p, p, n),
            Shape::Mesh(m) => m.pdf_direct(ref_p, p, n),
        }
    }
}

/// Converts an area density at `p` (normal `n`) to a solid-angle density seen from `ref_p`.
#[inline]
pub fn area_to_solid_angle(pdf_area: f32, ref_p: Vec3, p: Vec3, n: Vec3) -> f32 {
    area_to_solid_angle_lanes(pdf_area, ref_p.into(), p.into(), n.into())
}

/// [`area_to_solid_angle`] on lanes.
#[inline(always)]
pub fn area_to_solid_angle_lanes<F: crate::simd::Float>(
    pdf_area: F,
    ref_p: crate::simd::V3<F>,
    p: crate::simd::V3<F>,
    n: crate::simd::V3<F>,
) -> F {
    let zero = F::splat(0.0);
    let d = p - ref_p;
    let dist2 = d.length_squared();
    let cos = (n.dot(d) / dist2.sqrt()).abs();
    let pdf = pdf_area * dist2 / cos;
    F::select(dist2.eq(zero) | cos.eq(zero), zero, pdf)
}

/// Whether `x` is a positive finite number (false for NaN).
#[inline]
pub(crate) fn positive_finite(x: f32) -> bool {
    x > 0.0 && x.is_finite()
}

/// The roots t0 ≤ t1 of a t² + 2b t + c = 0 (a > 0), given its discriminant b² − ac as the
/// caller computed it (each quadric in a form without cancellation for distant rays), by the
/// formula that keeps both roots accurate; `None` when they are not real.
#[inline]
pub(crate) fn quadratic_roots(a: f64, b: f64, c: f64, disc: f64) -> Option<(f64, f64)> {
    if disc < 0.0 {
        return None;
    }
    let q = -(b + disc.sqrt().copysign(b));
    let (mut t0, mut t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q / a) };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    Some((t0, t1))
}

/// The shapes one `<shape>` element makes, each with the name of its part (`None` for a
/// plain shape; a `snake` names its `body`, `belly`, `head` and `eyes`), or none at all.
pub(crate) type Parts = Vec<(Option<&'static str>, Shape)>;

/// `to_world` and `flip_normals`, which every shape plugin takes.
pub(crate) const PLACEMENT: &[crate::plugin::Param] = &[
    crate::plugin::Param::new(
        "to_world",
        crate::plugin::Ty::Transform,
        crate::plugin::DefaultValue::None,
    )
    .doc("object-to-world transform (after an `instance`'s own)"),
    crate::plugin::Param::bool("flip_normals", false)
        .doc("turn the normals the other way (an area light then emits from the other side)"),
];

/// The `radius` of the analytic sphere and cylinder.
pub(crate) const RADIUS: crate::plugin::Param = crate::plugin::Param::float("radius", 1.0)
    .check(crate::plugin::Check::Positive)
    .unit("object space")
    .doc("radius");

/// A shape's world placement (its `to_world` after `parent`, an instance's) and normal flip.
pub(crate) fn placement(
    a: &crate::plugin::Args,
    parent: &Transform,
) -> Result<(Transform, bool), crate::plugin::SceneError> {
    Ok((
        parent.compose(&a.transform("to_world")?),
        a.bool("flip_normals")?,
    ))
}

/// One plain shape, or the located error of building it.
pub(crate) fn one<E: std::fmt::Display>(
    a: &crate::plugin::Args,
    shape: Result<Shape, E>,
) -> Result<Parts, crate::plugin::SceneError> {
    match shape {
        Ok(s) => Ok(vec![(None, s)]),
        Err(e) => Err(crate::plugin::SceneError::at(
            &a.node().loc,
            format!("{}: {e}", a.describe()),
        )),
    }
}
