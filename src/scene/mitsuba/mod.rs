//! Mitsuba XML reader: parses a scene file (the 3.x dialect, and the 0.5/0.6 dialect upgraded the
//! way Mitsuba 3 upgrades it) into a resolved, typed tree of [`Node`]s.
//!
//! Everything textual is settled here, so that the next stage only sees typed values:
//!
//! - `$name` / `${name}` in any attribute is replaced by a command-line define or a
//!   `<default name=".." value=".."/>` (defines win; an unknown name is an error);
//! - `<include filename=".."/>` splices the included scene's children in place (looked up next
//!   to the including file first; cycles are errors); `<path value=".."/>` adds a folder to
//!   search; plugin file names are resolved as Mitsuba 3 resolves them (see [`resolver`]);
//! - `<ref id=".." name=".."/>` resolves to the same shared `Arc<Node>` as the object declared
//!   with that id, before or after the reference (cycles are errors); `<alias id=".." as=".."/>`
//!   needs the id declared before it, as in Mitsuba;
//! - the file may be UTF-8 or UTF-16 with a byte-order mark;
//! - value tags become [`Value`]s: numbers are parsed strictly, colours decoded, spectra and
//!   blackbodies parsed, `<transform>` blocks composed into one [`Transform`](crate::math::Transform);
//! - a scene with `version` < 2.0 has its parameter names turned from camelCase into snake_case
//!   (`intIOR` → `int_ior`, the original spelling is kept for messages) and `lookAt` into `lookat`;
//!   as in Mitsuba 3, a 0.x `diffuse`'s `diffuse_reflectance` becomes `reflectance` and
//!   `uoffset`/`voffset`/`uscale`/`vscale` become `to_uv`.
//!
//! The consumer reads parameters through [`Properties`]' typed getters, which remember what was
//! read; afterwards [`check_unused`] lists every parameter that nobody asked for.
//!
//! ```no_run
//! use ophis::scene::mitsuba::{self, Tag};
//! let (scene, mut warnings) = mitsuba::load_file("scene.xml".as_ref(), &[("spp".into(), "64".into())])?;
//! for child in scene.children.iter().filter(|c| c.node.tag == Tag::Shape) {
//!     let shape = &child.node;
//!     let radius = shape.props.get_float("radius", 1.0)?;
//!     let to_world = shape.props.get_transform("to_world", Default::default())?;
//!     if radius <= 0.0 {
//!         let loc = shape.props.location("radius").unwrap_or(&shape.loc);
//!         return Err(mitsuba::SceneError::at(loc, "radius must be positive"));
//!     }
//!     let bsdf = shape.child("bsdf"); // an Arc<Node>, possibly shared through <ref>
//! #   let _ = (to_world, bsdf);
//! }
//! warnings.extend(mitsuba::check_unused(&scene));
//! # Ok::<(), mitsuba::SceneError>(())
//! ```
//!
//! Deliberate differences from Mitsuba 3: unknown tags and attributes are warnings (Mitsuba
//! stops), except inside `<transform>`, where skipping an operation would silently move geometry;
//! only `<scene>` roots are accepted; numbers beyond
//! the f32 range are errors; elements may nest at most 100 deep (includes count as a level).

mod arena;
mod builder;
mod element;
mod literal;
mod reader;
pub mod resolver;
mod transform;
mod value_tags;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_files;
#[cfg(test)]
mod tests_values;

use std::collections::HashSet;
use std::path::Path;
use std::sync::Arc;

pub(crate) use crate::plugin::describe;
pub use crate::plugin::{
    Child, Location, Node, Properties, SceneError, SpectrumValue, Tag, Value, Warning,
};

/// Reads a scene file. `defines` are `-D name=value` pairs; they override `<default>`s.
pub fn load_file(
    path: &Path,
    defines: &[(String, String)],
) -> Result<(Node, Vec<Warning>), SceneError> {
    let mut warnings = Vec::new();
    let root = load_file_into(path, defines, &mut warnings)?;
    Ok((root, warnings))
}

/// [`load_file`] that adds its warnings to `warnings` even when it fails, so that a caller
/// can show the warnings that led up to an error.
pub(crate) fn load_file_into(
    path: &Path,
    defines: &[(String, String)],
    warnings: &mut Vec<Warning>,
) -> Result<Node, SceneError> {
    let text = resolver::read_text(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    load_str_into(&text, path, defines, warnings)
}

/// Reads a scene from a string; `file_name` is used in messages and to resolve relative paths.
pub fn load_str(
    xml: &str,
    file_name: &Path,
    defines: &[(String, String)],
) -> Result<(Node, Vec<Warning>), SceneError> {
    let mut warnings = Vec::new();
    let root = load_str_into(xml, file_name, defines, &mut warnings)?;
    Ok((root, warnings))
}

/// [`load_str`] that adds its warnings to `warnings` even when it fails.
pub(crate) fn load_str_into(
    xml: &str,
    file_name: &Path,
    defines: &[(String, String)],
    warnings: &mut Vec<Warning>,
) -> Result<Node, SceneError> {
    reader::Reader::new(defines).read_root(xml, file_name, warnings)
}

/// Every parameter of the tree (shared nodes once) that was never queried, in document order,
/// each naming the plugin's declared parameters nearest to it.
pub fn check_unused(root: &Node) -> Vec<Warning> {
    fn visit(node: &Node, seen: &mut HashSet<*const Node>, out: &mut Vec<Warning>) {
        let info = crate::plugin::registry::info(node.tag, &node.plugin);
        for (name, loc) in node.props.unqueried() {
            let written = node.props.original_name(&name).unwrap_or(&name);
            let spelling = if written != name {
                format!(" (written '{written}')")
            } else {
                String::new()
            };
            // A declared parameter that this configuration does not read gets no hint.
            let hint = match info {
                Some(i) if i.param(&name).is_none() => {
                    crate::plugin::did_you_mean(&name, i.all_params().flat_map(|p| p.names()))
                }
                _ => String::new(),
            };
            out.push(Warning {
                loc,
                message: format!(
                    "parameter '{name}'{spelling} of {} was never used{hint}",
                    node.describe()
                ),
            });
        }
        for child in &node.children {
            if seen.insert(Arc::as_ptr(&child.node)) {
                visit(&child.node, seen, out);
            }
        }
    }
    let mut out = Vec::new();
    visit(root, &mut HashSet::new(), &mut out);
    out
}
