//! `snake`: a procedural snake modelled on the sunbeam snake (*Xenopeltis unicolor*) — a
//! flattened, wedge-shaped head that flows into the body with very little neck, small eyes, a
//! round body with a flattened belly, and a short tapering tail — lying on the ground in an
//! S-curve or coiled. Built as closed triangle meshes, one per *part*, each with UVs made for
//! the `scales` texture and its own material.
//!
//! **Parts and materials** (the Mitsuba way: nested BSDFs named after the part, the unnamed one
//! as the fallback for parts without their own):
//!
//! ```xml
//! <shape type="snake">
//!     <ref id="skin"/>                        <!-- every part without its own -->
//!     <ref id="belly_skin" name="belly"/>     <!-- the ventral plates -->
//!     <ref id="head_skin" name="head"/>       <!-- the head shields -->
//!     <bsdf type="plastic" name="eyes"> … </bsdf>
//! </shape>
//! ```
//!
//! | part    | surface                                   | UV                                        |
//! |---------|-------------------------------------------|-------------------------------------------|
//! | `body`  | dorsal and lateral skin behind the head   | u ∈ [0, 1] across the dorsal arc (belly edge, back, belly edge); v = ∫ ds/P_d from the back of the head |
//! | `belly` | the flattened belly, a band of `belly_width` of the section's perimeter, snout to tail | u ∈ [0, 1] across the band; v = ∫ ds/P_d from the snout |
//! | `head`  | the head above the belly band             | the head map of the `scales` texture's `head` layout: u as `body`, v = s/(`head_length`·`length`) ∈ [0, 1] |
//! | `eyes`  | two spheres set into the sides of the head | a sphere's |
//!
//! P_d is the local length of the dorsal arc (floored at a fifth of its largest value), so a
//! `scales` texture with `scale_u` = `scale_v` = N gives N square dorsal rows around the body
//! everywhere — narrowing, not stretching, towards the head and tail as real scale rows do.
//! The sunbeam snake has 15 dorsal rows at mid-body (`scale_u` = 15) and one wide ventral plate
//! per row (`layout="rows"`, `scale_u` = 1, the same `scale_v`). The parts become separate
//! shapes in the order body, belly, head, eyes (the `shape_index` AOV tells them apart); their
//! shared borders are welded (same vertices, same normals).
//!
//! **Anatomy.** t = s/`length` from the snout (0) to the tail tip (1); R = `radius`; h =
//! `head_length`. The half-width a(t) = R·e(t)·cap(t)·tip(t): the envelope e is a C¹ piecewise
//! cubic through the landmarks (snout 0.55·`head_width`, the jaw joint at 0.85h at
//! `head_width`, the neck at 1.35h at `neck`, full width from max(0.3, 3h) to 0.62, 0.8 at the
//! vent 1 − `tail_length`), and the tail tapers as 0.8·(x^0.75/3 + 2x(2 − x)/3) with
//! x = (1 − t)/`tail_length` (pointed at the tip, meeting the body's slope at the vent);
//! cap rounds the snout over `snout`·h and tip the last 3 % of the tail. The section at angle
//! α (−90° = belly midline) is (a·cos α, a·sin α·k(α)·(1 − `flatten`·sin²α on the belly
//! half)), k blending from the lower to the upper height ratio: 1 on the body, on the head
//! `head_height` above (less towards the snout: a wedge in side view) and 0.8·`head_height`
//! below (a flat lower jaw), blended over 0.8h–2.6h. Every function is C¹, so there is no crease
//! or bulb where the head meets the body. The belly rests on the ground (y = 0; the chin rises a
//! little towards the snout). Each eye is a sphere of radius `eye_size`·a(t_eye) at the head
//! map's eye position, bulging out of the head by 40 % of its radius.
//!
//! **Poses** (`pose`): `s_curve` — x = X·τ − X/2, z = `amplitude`·sin(2π·`waves`·τ + `phase`),
//! X chosen so the arc length is `length`, head towards −x; `coil` — an Archimedean spiral
//! r = r0 + g·φ on the ground, tail at the centre (r0 = `coil_radius`·R), turns
//! `coil_spacing`·2R apart (> 1 leaves a gap between them), head outside, rotated by `phase`.
//! `roll` turns a stretch of either pose about its centreline, as a resting snake often lies
//! with part of its body tilted on its side, the section dropped back onto the ground.
//! A pose that makes the body pass through itself (or bend tighter than it is wide) loads with
//! a warning naming where (see `self_intersection`).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `pose` | string | `s_curve` | — | how it lies; one of 's_curve', 'coil' |
//! | `length` | float | 4.0 | world units | length along the centreline; positive |
//! | `radius` | float | 0.06 | world units | largest body half-width; positive |
//! | `waves` | float | 1.25 | — | `s_curve`: periods along the body |
//! | `amplitude` | float | 0.45 | world units | `s_curve`: sideways swing |
//! | `phase` | float | 0.0 | degrees | `s_curve`: phase at the snout; `coil`: rotation |
//! | `coil_radius` | float | 2.0 | of `radius` | `coil`: radius of the innermost turn; in (0, 1000] |
//! | `coil_spacing` | float | 1.12 | of 2·`radius` | `coil`: distance between turns; in (0, 1000] |
//! | `head_length` | float | 0.035 | of length | snout to the back of the head; in (0, 0.15] |
//! | `head_width` | float | 0.78 | of radius | half-width at the jaw joint; in (0, 2] |
//! | `head_height` | float | 0.6 | of width | height of the head over its width; in (0, 1] |
//! | `snout` | float | 0.3 | of head | length over which the snout is rounded; in (0, 1] |
//! | `neck` | float | 0.74, at most `head_width` | of radius | half-width of the neck (at most `head_width`); in (0, 1] |
//! | `tail_length` | float | 0.1 | of length | vent to the tail tip; in (0, 0.5] |
//! | `flatten` | float | 0.25 | — | belly height deficit (0 = round); in [0, 0.9) |
//! | `belly_width` | float | 0.22 | of perimeter | width of the ventral plates' band; in (0, 0.5] |
//! | `eyes` | boolean | true | — | add the eyes |
//! | `eye_size` | float | 0.12 | of head half-width | eye radius; in (0, 0.5] |
//! | `roll` | float | 0.0 | degrees | turn a stretch of the body about its centreline (shows the belly); between -180 and 180 |
//! | `roll_at` | float | 0.5 | of length | centre of the rolled stretch; between 0 and 1 |
//! | `roll_span` | float | 0.25 | of length | its length (eased in and out over its outer quarters); in (0, 1] |
//! | `segments_along` | integer | 800 | — | rings along the body; between 16 and 100000 |
//! | `segments_around` | integer | 48 | — | vertices around a ring; between 12 and 4096 |
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |
//!
//! Proportions: a 1 m *Xenopeltis* has a head of ~3 cm and a tail ~10 % of its length
//! (subcaudals are about a seventh of the ventrals' count), and is ~2.5–3 cm thick; the
//! defaults keep these ratios for `length` 4. Pictures: `docs/snake-poses.png`
//! (`scenes/snake-poses.xml`, the two poses with each part in its own colour) and
//! `docs/snake-head.png` (`scenes/snake-head.xml`). Users can still load their own snake with
//! `obj`/`ply`.
//!
//! Limits: planar poses only (no coil stacked on another, no raised head); one head-shield
//! layout; the belly band's plates continue under the chin, where a real snake has small chin
//! shields; no mouth opening, nostrils or cloaca.

mod build;
mod pose;
mod profile;

use super::load::MeshData;
use super::mesh::{MeshError, TriangleMesh};
use crate::math::Transform;
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Ty};
pub(crate) use crate::texture::head_shields::{EYE_OFFSET, EYE_V};
#[cfg(test)]
use std::collections::HashMap;

declare!(PLUGIN: super::Parts, Transform = Shape "snake" []
    "a procedural sunbeam snake on the ground, one mesh per part (body, belly, head, eyes)"
    [&[
        Param::string("pose", "s_curve")
            .check(Check::OneOf(&["s_curve", "coil"]))
            .doc("how it lies"),
        Param::length("length", 4.0)
            .doc("length along the centreline"),
        Param::length("radius", 0.06)
            .doc("largest body half-width"),
        Param::float("waves", 1.25).doc("`s_curve`: periods along the body"),
        Param::float("amplitude", 0.45)
            .unit("world units")
            .doc("`s_curve`: sideways swing"),
        Param::angle("phase", 0.0)
            .doc("`s_curve`: phase at the snout; `coil`: rotation"),
        Param::up_to("coil_radius", 2.0, 1e3, "of `radius`").doc("`coil`: radius of the innermost turn"),
        Param::up_to("coil_spacing", 1.12, 1e3, "of 2·`radius`").doc("`coil`: distance between turns"),
        Param::up_to("head_length", 0.035, 0.15, "of length").doc("snout to the back of the head"),
        Param::up_to("head_width", 0.78, 2.0, "of radius").doc("half-width at the jaw joint"),
        Param::up_to("head_height", 0.6, 1.0, "of width").doc("height of the head over its width"),
        Param::up_to("snout", 0.3, 1.0, "of head").doc("length over which the snout is rounded"),
        Param::new("neck", Ty::Float, DefaultValue::Derived("0.74, at most `head_width`"))
            .check(Check::OpenClosed(0.0, 1.0))
            .unit("of radius")
            .doc("half-width of the neck (at most `head_width`)"),
        Param::up_to("tail_length", 0.1, 0.5, "of length").doc("vent to the tail tip"),
        Param::float("flatten", 0.25)
            .check(Check::ClosedOpen(0.0, 0.9))
            .doc("belly height deficit (0 = round)"),
        Param::up_to("belly_width", 0.22, 0.5, "of perimeter").doc("width of the ventral plates' band"),
        Param::bool("eyes", true).doc("add the eyes"),
        Param::up_to("eye_size", 0.12, 0.5, "of head half-width").doc("eye radius"),
        Param::angle("roll", 0.0)
            .check(Check::Range(-180.0, 180.0))
            .doc("turn a stretch of the body about its centreline (shows the belly)"),
        Param::fraction("roll_at", 0.5)
            .unit("of length")
            .doc("centre of the rolled stretch"),
        Param::up_to("roll_span", 0.25, 1.0, "of length")
            .doc("its length (eased in and out over its outer quarters)"),
        Param::int("segments_along", 800)
            .check(Check::Range(16.0, 100_000.0))
            .doc("rings along the body"),
        Param::int("segments_around", 48)
            .check(Check::Range(12.0, 4096.0))
            .doc("vertices around a ring"),
    ], super::PLACEMENT] load);

fn load(a: &mut Args, parent: Transform) -> Result<super::Parts, SceneError> {
    let (to_world, flip) = super::placement(a, &parent)?;
    let pose = Pose::from_name(&a.string("pose")?).unwrap_or(Pose::SCurve);
    let head_width = a.float("head_width")?;
    let neck = match a.float_opt("neck")? {
        Some(v) if v > head_width => {
            let e = format!("must be at most head_width ({head_width}), got {v}");
            return Err(a.error("neck", e));
        }
        Some(v) => v,
        None => SnakeParams::default().neck.min(head_width),
    };
    let p = SnakeParams {
        pose,
        length: a.float("length")?,
        radius: a.float("radius")?,
        waves: a.float("waves")?,
        amplitude: a.float("amplitude")?,
        phase: a.angle("phase")?,
        coil_radius: a.float("coil_radius")?,
        coil_spacing: a.float("coil_spacing")?,
        head_length: a.float("head_length")?,
        head_width,
        head_height: a.float("head_height")?,
        snout: a.float("snout")?,
        neck,
        tail_length: a.float("tail_length")?,
        flatten: a.float("flatten")?,
        belly_width: a.float("belly_width")?,
        eyes: a.bool("eyes")?,
        eye_size: a.float("eye_size")?,
        roll: a.angle("roll")?,
        roll_at: a.float("roll_at")?,
        roll_span: a.float("roll_span")?,
        segments_along: a.u32("segments_along")?,
        segments_around: a.u32("segments_around")?,
    };
    if let Some((s, t)) = self_intersection(&p, 2000) {
        let what = if s == t {
            format!(
                "bends tighter than it is wide at {:.0} % of its length",
                100.0 * s
            )
        } else {
            format!(
                "passes through itself between {:.0} % and {:.0} % of its length",
                100.0 * s,
                100.0 * t
            )
        };
        let d = a.describe();
        a.warn(format!("{d}: the body {what}"));
    }
    let parts = TriangleMesh::snake_parts(&p, &to_world, flip)
        .map_err(|e| SceneError::at(&a.node().loc, format!("{}: {e}", a.describe())))?;
    Ok(parts
        .into_iter()
        .map(|(part, mesh)| (Some(part.name()), super::Shape::Mesh(mesh)))
        .collect())
}

/// How the snake lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pose {
    SCurve,
    Coil,
}

impl Pose {
    /// The XML name.
    pub(crate) fn from_name(s: &str) -> Option<Pose> {
        match s {
            "s_curve" => Some(Pose::SCurve),
            "coil" => Some(Pose::Coil),
            _ => None,
        }
    }
}

/// A part of the snake with its own shape and material.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Part {
    Body,
    Belly,
    Head,
    Eyes,
}

impl Part {
    /// The part's name (the `name` of its nested BSDF).
    pub fn name(self) -> &'static str {
        match self {
            Part::Body => "body",
            Part::Belly => "belly",
            Part::Head => "head",
            Part::Eyes => "eyes",
        }
    }

    #[cfg(test)]
    /// All parts, in the order they become shapes.
    pub const ALL: [Part; 4] = [Part::Body, Part::Belly, Part::Head, Part::Eyes];
}

/// Shape parameters (see the module header).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SnakeParams {
    pub pose: Pose,
    pub length: f32,
    pub radius: f32,
    pub waves: f32,
    pub amplitude: f32,
    /// Radians.
    pub phase: f32,
    pub coil_radius: f32,
    pub coil_spacing: f32,
    pub head_length: f32,
    pub head_width: f32,
    pub head_height: f32,
    pub snout: f32,
    pub neck: f32,
    pub tail_length: f32,
    pub flatten: f32,
    pub belly_width: f32,
    pub eyes: bool,
    pub eye_size: f32,
    /// Radians.
    pub roll: f32,
    pub roll_at: f32,
    pub roll_span: f32,
    pub segments_along: u32,
    pub segments_around: u32,
}

impl Default for SnakeParams {
    fn default() -> SnakeParams {
        SnakeParams {
            pose: Pose::SCurve,
            length: 4.0,
            radius: 0.06,
            waves: 1.25,
            amplitude: 0.45,
            phase: 0.0,
            coil_radius: 2.0,
            coil_spacing: 1.12,
            head_length: 0.035,
            head_width: 0.78,
            head_height: 0.6,
            snout: 0.3,
            neck: 0.74,
            tail_length: 0.1,
            flatten: 0.25,
            belly_width: 0.22,
            eyes: true,
            eye_size: 0.12,
            roll: 0.0,
            roll_at: 0.5,
            roll_span: 0.25,
            segments_along: 800,
            segments_around: 48,
        }
    }
}

/// The parts' meshes in object space (body, belly, head, and the eyes if asked for).
pub(crate) fn snake_parts(p: &SnakeParams) -> Vec<(Part, MeshData)> {
    build::parts(p)
}

/// Where the pose makes the body pass through itself, as two positions t = s/`length` (equal
/// for a bend tighter than the body is wide), checked at `stations` points along it.
pub(crate) fn self_intersection(p: &SnakeParams, stations: usize) -> Option<(f64, f64)> {
    pose::self_intersection(p, stations)
}

impl TriangleMesh {
    /// The `snake` shape's parts as meshes.
    pub(crate) fn snake_parts(
        p: &SnakeParams,
        to_world: &Transform,
        flip_normals: bool,
    ) -> Result<Vec<(Part, TriangleMesh)>, MeshError> {
        snake_parts(p)
            .into_iter()
            .map(|(part, g)| Ok((part, g.into_mesh(to_world, flip_normals, false)?)))
            .collect()
    }
}

#[cfg(test)]
/// Checks that a mesh is closed and consistently wound: vertices welded by exact position, every
/// edge is used by exactly two triangles, once in each direction, and no triangle has zero area.
pub(crate) fn check_closed_mesh(g: &MeshData) -> Result<(), String> {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let weld: Vec<u32> = g
        .positions
        .iter()
        .map(|p| {
            let n = ids.len() as u32;
            *ids.entry(p.to_array().map(f32::to_bits)).or_insert(n)
        })
        .collect();
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    for (i, tri) in g.indices.iter().enumerate() {
        let [a, b, c] = tri.map(|k| g.positions[k as usize]);
        if (b - a).cross(c - a).length() <= 0.0 {
            return Err(format!("triangle {i} is degenerate"));
        }
        let w = tri.map(|k| weld[k as usize]);
        for (x, y) in [(w[0], w[1]), (w[1], w[2]), (w[2], w[0])] {
            if x == y {
                return Err(format!("triangle {i} has a collapsed edge"));
            }
            *edges.entry((x, y)).or_default() += 1;
        }
    }
    for (&(x, y), &n) in &edges {
        if n != 1 || edges.get(&(y, x)) != Some(&1) {
            return Err(format!(
                "edge {x}–{y} is used {n} times this way and {:?} the other",
                edges.get(&(y, x))
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
#[path = "snake_tests.rs"]
mod tests;
