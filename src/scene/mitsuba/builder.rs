//! An object being read: its parameters and children, with the duplicate checks, and the
//! per-object parts of Mitsuba 3's upgrade of version < 2 files (`src/core/parser.cpp`,
//! `upgrade_from_v1`): a `diffuse` BSDF's `diffuse_reflectance` becomes `reflectance`, and
//! `uoffset`, `voffset`, `uscale`, `vscale` become a `to_uv` transform. (Parameter names are
//! snake_cased by the reader, element by element.)

use std::sync::{Arc, OnceLock};

use super::arena::{Pending, PendingChild, Target};
use super::{describe, Location, SceneError, Tag};
use crate::math::{Transform, Vec3};
use crate::plugin::{FileResolver, Properties, Value};

/// An object being built.
pub(crate) struct Builder {
    pub(super) tag: Tag,
    plugin: String,
    id: Option<String>,
    pub(super) props: Properties,
    children: Vec<PendingChild>,
    child_names: Vec<(String, Location)>,
    loc: Location,
    /// Declared in a version < 2 file: Mitsuba 3's upgrades of the object apply.
    legacy: bool,
    /// 0.x `uoffset`, `voffset`, `uscale`, `vscale`, with where each was written.
    uv: [Option<(f64, Location)>; 4],
}

/// The 0.x texture-placement parameters, in the order of [`Builder::uv`].
const UV_NAMES: [&str; 4] = ["uoffset", "voffset", "uscale", "vscale"];

impl Builder {
    pub(super) fn new(
        tag: Tag,
        plugin: String,
        id: Option<String>,
        loc: Location,
        files: &Arc<OnceLock<FileResolver>>,
        legacy: bool,
    ) -> Builder {
        Builder {
            props: Properties::new(describe(tag, &plugin, id.as_deref()), files.clone()),
            tag,
            plugin,
            id,
            children: Vec::new(),
            child_names: Vec::new(),
            loc,
            legacy,
            uv: [None, None, None, None],
        }
    }

    /// Mitsuba 3 renames a 0.x diffuse's `diffuse_reflectance` to `reflectance`.
    fn upgraded(&self, name: String) -> String {
        if self.legacy && self.plugin == "diffuse" && name == "diffuse_reflectance" {
            "reflectance".into()
        } else {
            name
        }
    }

    fn taken(&self, name: &str) -> Option<&Location> {
        self.props.location(name).or_else(|| {
            self.child_names
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, l)| l)
        })
    }

    fn twice(&self, name: &str, first: &Location, loc: &Location) -> SceneError {
        SceneError::at(
            loc,
            format!(
                "parameter '{name}' of {} is given twice (first at {first})",
                self.props.owner()
            ),
        )
    }

    pub(super) fn add_prop(
        &mut self,
        name: String,
        orig: String,
        v: Value,
        loc: Location,
    ) -> Result<(), SceneError> {
        let name = self.upgraded(name);
        if self.legacy {
            if let (Some(k), Value::Float(x)) = (UV_NAMES.iter().position(|n| *n == name), &v) {
                if let Some((_, first)) = &self.uv[k] {
                    return Err(self.twice(&name, first, &loc));
                }
                self.uv[k] = Some((*x, loc));
                return Ok(());
            }
        }
        if let Some(first) = self.child_names.iter().find(|(n, _)| *n == name) {
            return Err(self.twice(&name, &first.1, &loc));
        }
        self.props.insert(name, orig, v, loc)
    }

    pub(super) fn add_child(
        &mut self,
        name: Option<String>,
        target: Target,
        loc: Location,
    ) -> Result<(), SceneError> {
        let name = name.map(|n| self.upgraded(n));
        if let Some(n) = &name {
            if let Some(first) = self.taken(n) {
                return Err(self.twice(n, first, &loc));
            }
            self.child_names.push((n.clone(), loc.clone()));
        }
        self.children.push(PendingChild { name, target, loc });
        Ok(())
    }

    /// The object, with 0.x `uoffset`/`voffset`/`uscale`/`vscale` turned into
    /// `to_uv = scale(uscale, vscale) · translate(uoffset, voffset)`, as Mitsuba 3 does.
    pub(super) fn finish(mut self) -> Result<Pending, SceneError> {
        if let Some(loc) = self.uv.iter().flatten().map(|(_, l)| l.clone()).next() {
            let get = |k: usize, d: f64| self.uv[k].as_ref().map_or(d, |(x, _)| *x) as f32;
            let (offset, scale) = (
                Vec3::new(get(0, 0.0), get(1, 0.0), 0.0),
                Vec3::new(get(2, 1.0), get(3, 1.0), 1.0),
            );
            let Some(s) = Transform::scale(scale) else {
                return Err(SceneError::at(
                    &loc,
                    format!("{}: uscale and vscale must not be zero", self.props.owner()),
                ));
            };
            let to_uv = s.compose(&Transform::translate(offset));
            let written = UV_NAMES
                .iter()
                .zip(&self.uv)
                .filter(|(_, v)| v.is_some())
                .map(|(n, _)| *n)
                .collect::<Vec<_>>()
                .join(", ");
            self.add_legacy_uv(to_uv, written, loc)?;
        }
        Ok(Pending {
            tag: self.tag,
            plugin: self.plugin,
            id: self.id,
            props: self.props,
            children: self.children,
            loc: self.loc,
        })
    }

    fn add_legacy_uv(
        &mut self,
        t: Transform,
        written: String,
        loc: Location,
    ) -> Result<(), SceneError> {
        if let Some(first) = self.taken("to_uv").cloned() {
            return Err(self.twice("to_uv", &first, &loc));
        }
        self.props
            .insert("to_uv".into(), written, Value::Transform(t), loc)
    }
}
