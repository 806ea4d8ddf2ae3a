//! Scene loading for the procedural shapes `torus` and `snake` (models and parameter tables in
//! `shape/torus.rs` and `shape/snake.rs`).

use super::values::{checked_float, checked_int};
use crate::math::Transform;
use crate::scene::mitsuba::{Node, SceneError};
use crate::shape::snake::SnakeParams;
use crate::shape::{Shape, TriangleMesh};

fn positive(node: &Node, name: &str, default: f32) -> Result<f32, SceneError> {
    checked_float(
        node,
        name,
        default,
        |v| v > 0.0 && v.is_finite(),
        "positive",
    )
}

/// `torus`.
pub(crate) fn torus(node: &Node, to_world: &Transform, flip: bool) -> Result<Shape, SceneError> {
    let major = positive(node, "major_radius", 1.0)?;
    let minor = checked_float(
        node,
        "minor_radius",
        0.25,
        |v| v > 0.0 && v < major,
        &format!("positive and less than major_radius ({major})"),
    )?;
    let d = crate::shape::torus::default_segments_major(major, minor) as i64;
    let nu = checked_int(node, "segments_major", d, 3, 8192)? as u32;
    let nv = checked_int(
        node,
        "segments_minor",
        crate::shape::torus::DEFAULT_SEGMENTS_MINOR as i64,
        3,
        4096,
    )? as u32;
    let mesh = TriangleMesh::torus(major, minor, Some((nu, nv)), to_world, flip)
        .map_err(|e| SceneError::at(&node.loc, format!("{}: {e}", node.describe())))?;
    Ok(Shape::Mesh(mesh))
}

/// `snake`.
pub(crate) fn snake(node: &Node, to_world: &Transform, flip: bool) -> Result<Shape, SceneError> {
    let d = SnakeParams::default();
    let unit = |name: &str, default: f32| {
        checked_float(
            node,
            name,
            default,
            |v| (0.0..=1.0).contains(&v),
            "between 0 and 1",
        )
    };
    let finite =
        |name: &str, default: f32| checked_float(node, name, default, |v| v.is_finite(), "finite");
    let head_length = checked_float(
        node,
        "head_length",
        d.head_length,
        |v| v > 0.0 && v <= 0.3,
        "in (0, 0.3]",
    )?;
    let tail_length = checked_float(
        node,
        "tail_length",
        d.tail_length,
        |v| v > 0.0 && v <= 0.9,
        "in (0, 0.9]",
    )?;
    let p = SnakeParams {
        length: positive(node, "length", d.length)?,
        radius: positive(node, "radius", d.radius)?,
        waves: finite("waves", d.waves)?,
        amplitude: finite("amplitude", d.amplitude)?,
        phase: finite("phase", 0.0)?.to_radians(),
        head_length,
        neck: checked_float(node, "neck", d.neck, |v| v > 0.0 && v <= 1.0, "in (0, 1]")?,
        tail_length,
        flatten: unit("flatten", d.flatten)?.min(0.9),
        segments_along: checked_int(node, "segments_along", d.segments_along as i64, 8, 100_000)?
            as u32,
        segments_around: checked_int(node, "segments_around", d.segments_around as i64, 3, 4096)?
            as u32,
    };
    let mesh = TriangleMesh::snake(&p, to_world, flip)
        .map_err(|e| SceneError::at(&node.loc, format!("{}: {e}", node.describe())))?;
    Ok(Shape::Mesh(mesh))
}
