//! Value tags (`<float>`, `<rgb>`, `<spectrum>`, `<transform>`, …) → [`Value`]s.

use super::element::{Attr, Elem, Source};
use super::literal::{self, parse_bool, parse_float, parse_int, parse_rgb, srgb_to_linear};
use super::reader::{Builder, Reader};
use super::resolver::FileResolver;
use super::{transform, SceneError};
use crate::math::{Transform, Vec3};
use crate::plugin::{SpectrumValue, Value};

impl Reader {
    /// A value tag inside `b`: parsed, checked and added as a parameter.
    pub(super) fn value(
        &mut self,
        node: roxmltree::Node,
        src: &Source,
        b: &mut Builder,
    ) -> Result<(), SceneError> {
        let e = Elem::new(node, src, &self.params)?;
        let Some((name, orig)) = Self::name_of(&e, src).filter(|n| !n.0.is_empty()) else {
            return Err(e.err("attribute 'name' is missing or empty; it is required"));
        };
        let parse = |a: &Attr, f: fn(&str) -> Result<f64, String>| {
            f(&a.value).map_err(|m| e.attr_err(a, m))
        };
        let (value, allowed): (Value, &[&str]) = match e.tag.as_str() {
            "float" => (
                Value::Float(parse(e.require("value")?, parse_float)?),
                &["name", "value"],
            ),
            "integer" => {
                let a = e.require("value")?;
                (
                    Value::Integer(parse_int(&a.value).map_err(|m| e.attr_err(a, m))?),
                    &["name", "value"],
                )
            }
            "boolean" => {
                let a = e.require("value")?;
                (
                    Value::Boolean(parse_bool(&a.value).map_err(|m| e.attr_err(a, m))?),
                    &["name", "value"],
                )
            }
            "string" => (
                Value::String(e.require("value")?.value.clone()),
                &["name", "value"],
            ),
            "point" | "vector" => {
                let v = point(&e)?;
                let v = if e.tag == "point" {
                    Value::Point(v)
                } else {
                    Value::Vector(v)
                };
                (v, &["name", "value", "x", "y", "z"])
            }
            "rgb" | "srgb" => {
                let a = e.require("value")?;
                let mut c = parse_rgb(&a.value).map_err(|m| e.attr_err(a, m))?;
                if e.tag == "srgb" && !a.value.trim().starts_with('#') {
                    c = c.map(srgb_to_linear);
                }
                (Value::Rgb(c), &["name", "value", "intent"])
            }
            "spectrum" => (
                Value::Spectrum(spectrum(&e, src, &self.search)?),
                &["name", "value", "filename", "intent"],
            ),
            "blackbody" => {
                let t = e.require("temperature")?;
                let temperature =
                    literal::parse_temperature(&t.value).map_err(|m| e.attr_err(t, m))?;
                let scale = match e.get("scale") {
                    Some(a) => parse(a, parse_float)? as f32,
                    None => 1.0,
                };
                (
                    Value::Blackbody { temperature, scale },
                    &["name", "temperature", "scale"],
                )
            }
            _ => (Value::Transform(self.transform(node, src)?), &["name"]),
        };
        if e.tag != "transform" {
            self.no_children(node, src, &e);
        }
        self.check_attrs(&e, allowed);
        b.add_prop(name, orig, value, e.loc)
    }

    fn transform(&mut self, node: roxmltree::Node, src: &Source) -> Result<Transform, SceneError> {
        let mut t = Transform::IDENTITY;
        for c in node.children().filter(|c| c.is_element()) {
            let op = Elem::new(c, src, &self.params)?;
            self.check_attrs(&op, transform::allowed_attrs(&op.tag));
            self.no_children(c, src, &op);
            t = transform::op(&op)?.compose(&t);
        }
        Ok(t)
    }
}

/// `value="x, y, z"` (or one number for all three) or `x=`, `y=`, `z=` (absent ones are 0).
fn point(e: &Elem) -> Result<Vec3, SceneError> {
    let comps = ["x", "y", "z"].map(|n| e.get(n));
    match e.get("value") {
        Some(a) if comps.iter().any(Option::is_some) => {
            Err(e.attr_err(a, "both 'value' and x/y/z attributes; expected one form"))
        }
        Some(a) => Ok(Vec3::from(
            literal::parse_vec3(&a.value).map_err(|m| e.attr_err(a, m))?,
        )),
        None if comps.iter().all(Option::is_none) => {
            Err(e.err("found no coordinates; expected value=\"x, y, z\" or x=, y=, z= attributes"))
        }
        None => {
            let mut v = [0.0f32; 3];
            for (slot, a) in v.iter_mut().zip(comps) {
                if let Some(a) = a {
                    *slot = parse_float(&a.value).map_err(|m| e.attr_err(a, m))? as f32;
                }
            }
            Ok(Vec3::from(v))
        }
    }
}

/// `value=` (constant or pairs) or `filename=` (must exist; looked up while reading, as
/// Mitsuba does, then next to the declaring file).
fn spectrum(e: &Elem, src: &Source, search: &FileResolver) -> Result<SpectrumValue, SceneError> {
    match (e.get("value"), e.get("filename")) {
        (Some(a), None) => literal::parse_spectrum(&a.value).map_err(|m| e.attr_err(a, m)),
        (None, Some(f)) => {
            let name = std::path::Path::new(&f.value);
            let path = search.find(name).unwrap_or_else(|| src.dir.join(name));
            if path.is_file() {
                Ok(SpectrumValue::File(path))
            } else {
                Err(e.attr_err(
                    f,
                    format!(
                        "'{}', which is not a readable file; expected a spectrum file",
                        path.display()
                    ),
                ))
            }
        }
        _ => Err(e.err("found neither or both of 'value' and 'filename'; expected exactly one")),
    }
}
