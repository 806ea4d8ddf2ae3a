//! Scene loading for the procedural shapes `torus`, `snake` and `litter` (models and parameter
//! tables in `shape/torus.rs`, `shape/snake.rs` and `shape/litter.rs`).

use super::values::{checked_float, checked_int};
use crate::math::Transform;
use crate::scene::mitsuba::{Node, SceneError, Warning};
use crate::shape::snake::{Part, Pose, SnakeParams};
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

/// `snake`: one shape per part (see `shape/snake.rs`), and a warning when the pose makes the
/// body pass through itself.
pub(crate) fn snake(
    node: &Node,
    to_world: &Transform,
    flip: bool,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<(Part, Shape)>, SceneError> {
    let d = SnakeParams::default();
    let ranged = |name: &str, default: f32, lo: f32, hi: f32| {
        checked_float(
            node,
            name,
            default,
            |v| v > lo && v <= hi,
            &format!("in ({lo}, {hi}]"),
        )
    };
    let finite =
        |name: &str, default: f32| checked_float(node, name, default, |v| v.is_finite(), "finite");
    let pose_name = node.props.get_string("pose", "s_curve")?;
    let pose = Pose::from_name(&pose_name).ok_or_else(|| {
        SceneError::at(
            node.props.location("pose").unwrap_or(&node.loc),
            format!("pose must be s_curve or coil; got '{pose_name}'"),
        )
    })?;
    let head_width = ranged("head_width", d.head_width, 0.0, 2.0)?;
    let p = SnakeParams {
        pose,
        length: positive(node, "length", d.length)?,
        radius: positive(node, "radius", d.radius)?,
        waves: finite("waves", d.waves)?,
        amplitude: finite("amplitude", d.amplitude)?,
        phase: finite("phase", 0.0)?.to_radians(),
        coil_radius: ranged("coil_radius", d.coil_radius, 0.0, 1e3)?,
        coil_spacing: ranged("coil_spacing", d.coil_spacing, 0.0, 1e3)?,
        head_length: ranged("head_length", d.head_length, 0.0, 0.15)?,
        head_width,
        head_height: ranged("head_height", d.head_height, 0.0, 1.0)?,
        snout: ranged("snout", d.snout, 0.0, 1.0)?,
        neck: checked_float(
            node,
            "neck",
            d.neck.min(head_width),
            |v| v > 0.0 && v <= head_width,
            &format!("in (0, head_width = {head_width}]"),
        )?,
        tail_length: ranged("tail_length", d.tail_length, 0.0, 0.5)?,
        flatten: checked_float(
            node,
            "flatten",
            d.flatten,
            |v| (0.0..0.9).contains(&v),
            "in [0, 0.9)",
        )?,
        belly_width: ranged("belly_width", d.belly_width, 0.0, 0.5)?,
        eyes: node.props.get_bool("eyes", true)?,
        eye_size: ranged("eye_size", d.eye_size, 0.0, 0.5)?,
        roll: checked_float(
            node,
            "roll",
            0.0,
            |v| v.abs() <= 180.0,
            "between -180 and 180 degrees",
        )?
        .to_radians(),
        roll_at: checked_float(
            node,
            "roll_at",
            d.roll_at,
            |v| (0.0..=1.0).contains(&v),
            "between 0 and 1",
        )?,
        roll_span: ranged("roll_span", d.roll_span, 0.0, 1.0)?,
        segments_along: checked_int(node, "segments_along", d.segments_along as i64, 16, 100_000)?
            as u32,
        segments_around: checked_int(node, "segments_around", d.segments_around as i64, 12, 4096)?
            as u32,
    };
    if let Some((a, b)) = crate::shape::snake::self_intersection(&p, 2000) {
        let what = if a == b {
            format!(
                "bends tighter than it is wide at {:.0} % of its length",
                100.0 * a
            )
        } else {
            format!(
                "passes through itself between {:.0} % and {:.0} % of its length",
                100.0 * a,
                100.0 * b
            )
        };
        warnings.push(Warning {
            loc: node.loc.clone(),
            message: format!("{}: the body {what}", node.describe()),
        });
    }
    let parts = TriangleMesh::snake_parts(&p, to_world, flip)
        .map_err(|e| SceneError::at(&node.loc, format!("{}: {e}", node.describe())))?;
    Ok(parts
        .into_iter()
        .map(|(part, mesh)| (part, Shape::Mesh(mesh)))
        .collect())
}

/// `litter`.
pub(crate) fn litter(node: &Node, to_world: &Transform, flip: bool) -> Result<Shape, SceneError> {
    use crate::shape::litter::{litter, LitterParams};
    let d = LitterParams::default();
    let fraction = |name: &str, default: f32| {
        checked_float(
            node,
            name,
            default,
            |v| (0.0..=1.0).contains(&v),
            "between 0 and 1",
        )
    };
    let p = LitterParams {
        count: checked_int(node, "count", d.count as i64, 1, 1_000_000)? as u32,
        size: positive(node, "size", d.size)?,
        size_spread: checked_float(
            node,
            "size_spread",
            d.size_spread,
            |v| (0.0..1.0).contains(&v),
            "in [0, 1)",
        )?,
        width: checked_float(node, "width", d.width, |v| v > 0.0 && v <= 2.0, "in (0, 2]")?,
        curl: fraction("curl", d.curl)?,
        arch: fraction("arch", d.arch)?,
        lift: checked_float(
            node,
            "lift",
            d.lift,
            |v| v > 0.0 && v.is_finite(),
            "positive",
        )?,
        extent: positive(node, "extent", d.extent)?,
        clear: checked_float(
            node,
            "clear",
            d.clear,
            |v| (0.0..1e6).contains(&v),
            "zero or positive",
        )?,
        seed: checked_int(node, "seed", 0, 0, u32::MAX as i64)? as u32,
    };
    let g = litter(&p);
    let mesh = TriangleMesh::new(
        g.positions,
        g.normals,
        g.uvs,
        g.indices,
        to_world,
        flip,
        false,
    )
    .map_err(|e| SceneError::at(&node.loc, format!("{}: {e}", node.describe())))?;
    Ok(Shape::Mesh(mesh))
}
