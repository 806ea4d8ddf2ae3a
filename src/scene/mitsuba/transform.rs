//! `<transform>` blocks: translate, rotate, scale, matrix and lookat, composed in document
//! order (each operation is applied after the ones before it: M ← T_new · M).

use super::element::Elem;
use super::literal::{parse_float, parse_list, parse_vec3};
use super::SceneError;
use crate::math::{Mat4, Transform, Vec3};

/// One operation inside `<transform>`, as a transform.
pub(crate) fn op(e: &Elem) -> Result<Transform, SceneError> {
    match e.tag.as_str() {
        "translate" => {
            let v = xyz_or_value(e, 0.0, false)?;
            Ok(Transform::translate(v))
        }
        "scale" => {
            let v = xyz_or_value(e, 1.0, true)?;
            Transform::scale(v).ok_or_else(|| {
                e.err(format!(
                    "found scale factors {v}; expected non-zero factors"
                ))
            })
        }
        "rotate" => {
            let axis = xyz_or_value(e, 0.0, false)?;
            let angle = e.require("angle")?;
            let deg = parse_float(&angle.value).map_err(|m| e.attr_err(angle, m))? as f32;
            Transform::rotate(axis, deg).ok_or_else(|| {
                e.err(format!(
                    "found rotation axis {axis}; expected a non-zero axis"
                ))
            })
        }
        "matrix" => {
            let a = e.require("value")?;
            let v = parse_list(&a.value).map_err(|m| e.attr_err(a, m))?;
            let m = match v.len() {
                16 => Mat4::from_cols_array(&std::array::from_fn(|i| v[i] as f32)).transpose(),
                9 => {
                    let mut m = [0.0f32; 16];
                    for r in 0..3 {
                        for c in 0..3 {
                            m[c * 4 + r] = v[r * 3 + c] as f32;
                        }
                    }
                    m[15] = 1.0;
                    Mat4::from_cols_array(&m)
                }
                n => {
                    return Err(e.attr_err(
                        a,
                        format!("{n} numbers; expected 16 (4×4, row-major) or 9 (3×3)"),
                    ))
                }
            };
            Transform::new(m).ok_or_else(|| {
                e.err("found a singular or non-finite matrix; expected an invertible one")
            })
        }
        "lookat" | "lookAt" => {
            e.require("origin")?;
            e.require("target")?;
            let origin = point_attr(e, "origin")?.unwrap_or_default();
            let target = point_attr(e, "target")?.unwrap_or_default();
            let dir = target - origin;
            if dir.length_squared() == 0.0 || !dir.is_finite() {
                return Err(e.err("found origin = target; expected distinct points"));
            }
            let up = match point_attr(e, "up")? {
                Some(up) => up,
                None => any_perpendicular(dir),
            };
            Transform::look_at(origin, target, up).ok_or_else(|| {
                e.err(format!(
                    "found up {up} parallel to the viewing direction {}; expected a \
                     non-parallel up vector",
                    dir.normalize()
                ))
            })
        }
        other => Err(e.err(format!(
            "found <{other}> inside <transform>; expected translate, rotate, scale, matrix \
             or lookat"
        ))),
    }
}

/// The attributes that [`op`] reads, for unknown-attribute warnings.
pub(crate) fn allowed_attrs(tag: &str) -> &'static [&'static str] {
    match tag {
        "translate" | "scale" => &["x", "y", "z", "value"],
        "rotate" => &["x", "y", "z", "value", "angle"],
        "matrix" => &["value"],
        _ => &["origin", "target", "up"],
    }
}

/// A vector from `value="x y z"` (or one number, if `single` allows it) or from `x=`, `y=`,
/// `z=` with `missing` for absent components; mixing both forms is an error.
fn xyz_or_value(e: &Elem, missing: f32, single: bool) -> Result<Vec3, SceneError> {
    let comps = ["x", "y", "z"].map(|n| e.get(n));
    if let Some(a) = e.get("value") {
        if comps.iter().any(Option::is_some) {
            return Err(e.err("found both 'value' and x/y/z attributes; expected one form"));
        }
        let v = if single {
            parse_vec3(&a.value)
        } else {
            super::literal::parse_n::<3>(&a.value)
        }
        .map_err(|m| e.attr_err(a, m))?;
        return Ok(Vec3::from(v));
    }
    let mut v = [missing; 3];
    for (slot, a) in v.iter_mut().zip(comps) {
        if let Some(a) = a {
            *slot = parse_float(&a.value).map_err(|m| e.attr_err(a, m))? as f32;
        }
    }
    Ok(Vec3::from(v))
}

fn point_attr(e: &Elem, name: &str) -> Result<Option<Vec3>, SceneError> {
    match e.get(name) {
        None => Ok(None),
        Some(a) => super::literal::parse_n::<3>(&a.value)
            .map(|v| Some(Vec3::from(v)))
            .map_err(|m| e.attr_err(a, m)),
    }
}

/// Some unit vector perpendicular to `d`, for a lookat without `up`.
fn any_perpendicular(d: Vec3) -> Vec3 {
    let d = d.normalize();
    let helper = if d.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    d.cross(helper).normalize()
}
