//! Typed parameter values and the per-object property bag that remembers which were read.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

use super::files::FileResolver;
use super::{Location, SceneError};
use crate::math::{Transform, Vec3};

/// A spectrum given by a `<spectrum>` value tag.
#[derive(Clone, Debug, PartialEq)]
pub enum SpectrumValue {
    /// The same value at every wavelength.
    Constant(f32),
    /// (wavelength in nm, value) pairs, wavelengths strictly increasing.
    Pairs(Vec<(f32, f32)>),
    /// A `.spd` file (`filename=`), resolved against the declaring file's folder.
    File(PathBuf),
}

/// A parameter value, already parsed.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Float(f64),
    Integer(i64),
    Boolean(bool),
    String(String),
    Point(Vec3),
    Vector(Vec3),
    /// Linear RGB (`<srgb>` and `#rrggbb` are decoded to linear on load).
    Rgb([f32; 3]),
    Spectrum(SpectrumValue),
    /// Temperature in kelvin and a scale factor.
    Blackbody {
        temperature: f32,
        scale: f32,
    },
    Transform(Transform),
}

impl Value {
    /// The XML tag that produces this kind of value, for messages.
    pub(crate) fn type_name(&self) -> &'static str {
        match self {
            Value::Float(_) => "float",
            Value::Integer(_) => "integer",
            Value::Boolean(_) => "boolean",
            Value::String(_) => "string",
            Value::Point(_) => "point",
            Value::Vector(_) => "vector",
            Value::Rgb(_) => "rgb",
            Value::Spectrum(_) => "spectrum",
            Value::Blackbody { .. } => "blackbody",
            Value::Transform(_) => "transform",
        }
    }
}

#[derive(Debug)]
struct Entry {
    name: String,
    /// The name as written (differs from `name` for upgraded 0.6 scenes).
    original: String,
    value: Value,
    loc: Location,
    queried: AtomicBool,
}

/// An object's parameters: name → (value, location), in document order, with "was it read?"
/// tracking so that misspelled or unsupported parameters can be reported.
///
/// The tracking uses atomics so that the tree is `Send + Sync`; a getter marks the parameter
/// as read even when it then reports a type error.
#[derive(Debug, Default)]
pub struct Properties {
    /// "bsdf 'diffuse'", for messages.
    owner: String,
    entries: Vec<Entry>,
    /// The scene's folders for file names, set once the whole scene is read.
    files: Arc<OnceLock<FileResolver>>,
}

impl Properties {
    pub(crate) fn new(owner: String, files: Arc<OnceLock<FileResolver>>) -> Properties {
        Properties {
            owner,
            entries: Vec::new(),
            files,
        }
    }

    /// Adds a parameter; a second parameter of the same name is an error.
    pub(crate) fn insert(
        &mut self,
        name: String,
        original: String,
        value: Value,
        loc: Location,
    ) -> Result<(), SceneError> {
        if let Some(prev) = self.entries.iter().find(|e| e.name == name) {
            let written = if original != name {
                format!(" (written '{original}')")
            } else {
                String::new()
            };
            return Err(SceneError::at(
                &loc,
                format!(
                    "parameter '{name}'{written} of {} is given twice (first at {})",
                    self.owner, prev.loc
                ),
            ));
        }
        self.entries.push(Entry {
            name,
            original,
            value,
            loc,
            queried: AtomicBool::new(false),
        });
        Ok(())
    }

    fn entry(&self, name: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// Who owns these parameters, e.g. "bsdf 'diffuse'".
    pub(crate) fn owner(&self) -> &str {
        &self.owner
    }

    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether there are no parameters.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Whether a parameter exists (does not mark it as read).
    pub fn contains(&self, name: &str) -> bool {
        self.entry(name).is_some()
    }

    /// All parameters in document order (does not mark them as read).
    pub fn iter(&self) -> impl Iterator<Item = (&str, &Value, &Location)> + '_ {
        self.entries
            .iter()
            .map(|e| (e.name.as_str(), &e.value, &e.loc))
    }

    /// Where a parameter was written (does not mark it as read).
    pub fn location(&self, name: &str) -> Option<&Location> {
        self.entry(name).map(|e| &e.loc)
    }

    /// The spelling in the file (e.g. `intIOR` for `int_ior` in a 0.6 scene).
    pub(crate) fn original_name(&self, name: &str) -> Option<&str> {
        self.entry(name).map(|e| e.original.as_str())
    }

    /// Marks a parameter as read without reading it.
    pub(crate) fn mark_queried(&self, name: &str) {
        if let Some(e) = self.entry(name) {
            e.queried.store(true, Ordering::Relaxed);
        }
    }

    /// A parameter of any type; marks it as read.
    pub fn get(&self, name: &str) -> Option<(&Value, &Location)> {
        let e = self.entry(name)?;
        e.queried.store(true, Ordering::Relaxed);
        Some((&e.value, &e.loc))
    }

    /// Parameters never read, in document order.
    pub fn unqueried(&self) -> Vec<(String, Location)> {
        self.entries
            .iter()
            .filter(|e| !e.queried.load(Ordering::Relaxed))
            .map(|e| (e.name.clone(), e.loc.clone()))
            .collect()
    }

    /// The error for a parameter of the wrong type.
    pub(crate) fn type_error(&self, name: &str, expected: &str) -> SceneError {
        match self.entry(name) {
            Some(e) => SceneError::at(
                &e.loc,
                format!(
                    "parameter '{}' of {} is a {}, expected {expected}",
                    e.original,
                    self.owner,
                    e.value.type_name()
                ),
            ),
            None => SceneError::At {
                loc: unreachable_loc(),
                message: format!("parameter '{name}' of {} is missing", self.owner),
            },
        }
    }

    fn typed<T>(
        &self,
        name: &str,
        expected: &str,
        f: impl FnOnce(&Value) -> Option<T>,
    ) -> Result<Option<T>, SceneError> {
        match self.get(name) {
            None => Ok(None),
            Some((v, _)) => f(v)
                .map(Some)
                .ok_or_else(|| self.type_error(name, expected)),
        }
    }

    /// A float (an integer is accepted too), or `None` if absent.
    pub(crate) fn get_float_opt(&self, name: &str) -> Result<Option<f32>, SceneError> {
        let v = self.typed(name, "a float", |v| match *v {
            Value::Float(x) => Some(x),
            Value::Integer(i) => Some(i as f64),
            _ => None,
        })?;
        match v {
            Some(x) if !(x as f32).is_finite() => {
                let loc = self.location(name).cloned().unwrap_or_else(unreachable_loc);
                Err(SceneError::at(
                    &loc,
                    format!(
                        "parameter '{name}' of {} is {x}, outside the range of a 32-bit float",
                        self.owner
                    ),
                ))
            }
            other => Ok(other.map(|x| x as f32)),
        }
    }

    /// A float (an integer is accepted too), or `default` if absent.
    pub fn get_float(&self, name: &str, default: f32) -> Result<f32, SceneError> {
        Ok(self.get_float_opt(name)?.unwrap_or(default))
    }

    /// An integer, or `None` if absent.
    pub(crate) fn get_int_opt(&self, name: &str) -> Result<Option<i64>, SceneError> {
        self.typed(name, "an integer", |v| match *v {
            Value::Integer(i) => Some(i),
            _ => None,
        })
    }

    /// A boolean, or `None` if absent.
    pub(crate) fn get_bool_opt(&self, name: &str) -> Result<Option<bool>, SceneError> {
        self.typed(name, "a boolean", |v| match *v {
            Value::Boolean(b) => Some(b),
            _ => None,
        })
    }

    /// A string, or `None` if absent.
    pub(crate) fn get_string_opt(&self, name: &str) -> Result<Option<String>, SceneError> {
        self.typed(name, "a string", |v| match v {
            Value::String(s) => Some(s.clone()),
            _ => None,
        })
    }

    /// A string naming a file, looked up as Mitsuba 3 does: in the scene's `<path>` folders,
    /// the scene's folder and the working directory; then, as a last resort, next to the file
    /// that declared it (see `resolver.rs`). A file found nowhere is named relative to the
    /// declaring file's folder, for the message.
    pub(crate) fn get_path_opt(&self, name: &str) -> Result<Option<PathBuf>, SceneError> {
        let Some(s) = self.get_string_opt(name)? else {
            return Ok(None);
        };
        let loc = self.location(name).cloned().unwrap_or_else(unreachable_loc);
        let declared = loc
            .file
            .parent()
            .map(|d| d.join(&s))
            .unwrap_or_else(|| PathBuf::from(&s));
        let Some(files) = self.files.get() else {
            return Ok(Some(declared));
        };
        Ok(Some(files.find(Path::new(&s)).unwrap_or(declared)))
    }

    /// A point (a `<vector>` is accepted too, as in Mitsuba 3), or `None` if absent.
    pub(crate) fn get_point_opt(&self, name: &str) -> Result<Option<Vec3>, SceneError> {
        self.get_vec3_opt(name, "a point")
    }

    /// A vector (a `<point>` is accepted too, as in Mitsuba 3), or `None` if absent.
    pub(crate) fn get_vector_opt(&self, name: &str) -> Result<Option<Vec3>, SceneError> {
        self.get_vec3_opt(name, "a vector")
    }

    /// A `<point>` or a `<vector>` (Mitsuba 3 takes either for the other), or `None` if absent;
    /// `expected` words the error.
    fn get_vec3_opt(&self, name: &str, expected: &str) -> Result<Option<Vec3>, SceneError> {
        self.typed(name, expected, |v| match *v {
            Value::Point(p) | Value::Vector(p) => Some(p),
            _ => None,
        })
    }

    /// A transform, or `None` if absent.
    pub(crate) fn get_transform_opt(&self, name: &str) -> Result<Option<Transform>, SceneError> {
        self.typed(name, "a transform", |v| match *v {
            Value::Transform(t) => Some(t),
            _ => None,
        })
    }

    /// A transform, or `default` if absent.
    pub fn get_transform(&self, name: &str, default: Transform) -> Result<Transform, SceneError> {
        Ok(self.get_transform_opt(name)?.unwrap_or(default))
    }
}

/// Only reached if an entry vanished between two lookups, which cannot happen.
fn unreachable_loc() -> Location {
    Location {
        file: Default::default(),
        line: 0,
        col: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn loc(line: u32) -> Location {
        Location {
            file: Arc::new("t.xml".into()),
            line,
            col: 3,
        }
    }

    fn bag() -> Properties {
        let mut p = Properties::new("shape 'sphere'".into(), Arc::default());
        let entries = [
            ("radius", Value::Float(2.5)),
            ("count", Value::Integer(7)),
            ("flip", Value::Boolean(true)),
            ("filename", Value::String("m.obj".into())),
            ("center", Value::Point(Vec3::new(1.0, 2.0, 3.0))),
        ];
        for (i, (n, v)) in entries.into_iter().enumerate() {
            p.insert(n.into(), n.into(), v, loc(i as u32 + 1)).unwrap();
        }
        p
    }

    #[test]
    fn getters_convert_and_mark() {
        let p = bag();
        assert_eq!(p.get_float("radius", 1.0).unwrap(), 2.5);
        assert_eq!(p.get_float("count", 1.0).unwrap(), 7.0);
        assert_eq!(p.get_float("missing", 1.5).unwrap(), 1.5);
        assert_eq!(p.get_int_opt("missing").unwrap(), None);
        assert_eq!(p.get_bool_opt("flip").unwrap(), Some(true));
        assert_eq!(
            p.get_vector_opt("center").unwrap().unwrap(),
            Vec3::new(1.0, 2.0, 3.0)
        );
        let unq: Vec<String> = p.unqueried().into_iter().map(|(n, _)| n).collect();
        assert_eq!(unq, vec!["filename".to_string()]);
        assert_eq!(
            p.get_path_opt("filename").unwrap(),
            Some(PathBuf::from("m.obj"))
        );
        assert!(p.unqueried().is_empty());
    }

    #[test]
    fn wrong_type_names_parameter_and_location() {
        let p = bag();
        let e = p.get_int_opt("radius").unwrap_err().to_string();
        assert_eq!(
            e,
            "t.xml:1:3: parameter 'radius' of shape 'sphere' is a float, expected an integer"
        );
        assert!(p.get_string_opt("count").is_err());
    }

    #[test]
    fn duplicate_is_an_error() {
        let mut p = bag();
        let e = p
            .insert("radius".into(), "radius".into(), Value::Float(1.0), loc(9))
            .unwrap_err();
        assert!(e.to_string().contains("given twice (first at t.xml:1:3)"));
    }

    #[test]
    fn huge_double_is_not_a_float() {
        let mut p = Properties::new("x".into(), Arc::default());
        p.insert("a".into(), "a".into(), Value::Float(1e300), loc(1))
            .unwrap();
        assert!(p.get_float("a", 0.0).is_err());
    }
}
