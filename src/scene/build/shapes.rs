//! Shapes join the scene: every shape plugin (declared and loaded in its file under `shape/`)
//! gives one shape or several parts, each with its BSDF (nested or `<ref>`; an emitter without one is black, and
//! any other shape diffuse 0.5, as in Mitsuba 3) and optional area emitter; and
//! `shapegroup` / `instance`, flattened at load: every instance adds a copy of the group's shapes
//! moved by the instance's `to_world` (materials are shared; memory grows with the copies).
//! As in Mitsuba, a group may not hold instances or groups. A `snake` becomes one shape per
//! part; a nested BSDF named after a part (`belly`, `head`, `eyes`, `body`) is that part's, the
//! unnamed one every other part's.

use super::emitters::area_light;
use super::materials::material_for;
use super::Builder;
use crate::bsdf::Material;
use crate::math::Transform;
use crate::plugin::registry;
use crate::scene::mitsuba::{Node, SceneError, Tag};
use crate::shape::Parts;
use crate::spectrum::Spectrum;
use crate::texture::SpectrumTexture;
use std::sync::Arc;

pub(crate) fn add_shape(b: &mut Builder, node: &Node) -> Result<(), SceneError> {
    add_shape_at(b, node, &Transform::IDENTITY)
}

/// Whether an `instance` among the scene's shapes refers to `group`.
pub(crate) fn is_instanced(root: &Node, group: &Arc<Node>) -> bool {
    root.children_with_tag(Tag::Shape)
        .filter(|s| s.plugin == "instance")
        .any(|s| s.children.iter().any(|c| Arc::ptr_eq(&c.node, group)))
}

/// The shapes of the group an `instance` refers to, placed by `to_world`.
fn instance(b: &mut Builder, node: &Node, to_world: &Transform) -> Result<(), SceneError> {
    let groups: Vec<&Arc<Node>> = node
        .children_with_tag(Tag::Shape)
        .filter(|g| g.plugin == "shapegroup")
        .collect();
    let [group] = groups[..] else {
        return Err(SceneError::at(
            &node.loc,
            format!(
                "{} refers to {} shapegroups; expected one, e.g. <ref id=\"group\"/>",
                node.describe(),
                groups.len()
            ),
        ));
    };
    for c in &node.children {
        if !Arc::ptr_eq(&c.node, group) {
            let what = format!(
                "{} inside {} is ignored",
                c.node.describe(),
                node.describe()
            );
            b.warn(&c.node, what);
        }
    }
    for c in &group.children {
        let s = &c.node;
        match (s.tag, s.plugin.as_str()) {
            (Tag::Shape, "instance" | "shapegroup") => {
                return Err(SceneError::at(
                    &s.loc,
                    format!(
                        "{} inside {}: nested instancing is not supported (nor is it in Mitsuba)",
                        s.describe(),
                        group.describe()
                    ),
                ))
            }
            (Tag::Shape, _) => add_shape_at(b, s, to_world)?,
            _ => {
                let (what, group) = (s.describe(), group.describe());
                b.warn(
                    s,
                    format!("{what} inside {group} is ignored (a shapegroup holds shapes)"),
                );
            }
        }
    }
    Ok(())
}

/// A shape whose own `to_world` is applied after `parent` (an instance's placement).
fn add_shape_at(b: &mut Builder, node: &Node, parent: &Transform) -> Result<(), SceneError> {
    match node.plugin.as_str() {
        "instance" => {
            let to_world =
                parent.compose(&node.props.get_transform("to_world", Transform::IDENTITY)?);
            return instance(b, node, &to_world);
        }
        // Built through the instances that refer to it.
        "shapegroup" => return Ok(()),
        _ => {}
    }
    let parts = registry::shape(node, *parent, b.warnings)?;
    add_parts(b, node, parts)
}

/// Adds the shapes made from one `<shape>` element, each part with the nested BSDF of its name
/// (the unnamed one otherwise) and the element's emitter.
fn add_parts(b: &mut Builder, node: &Node, parts: Parts) -> Result<(), SceneError> {
    let part_names: Vec<&str> = parts.iter().filter_map(|(p, _)| *p).collect();
    let mut bsdf_node = None;
    let mut part_bsdfs: Vec<(&str, &std::sync::Arc<Node>)> = Vec::new();
    let mut emitter_node = None;
    for c in &node.children {
        let part = c.name.as_deref().filter(|n| part_names.contains(n));
        match c.node.tag {
            Tag::Bsdf if part.is_some() && !part_bsdfs.iter().any(|(n, _)| Some(*n) == part) => {
                part_bsdfs.push((part.unwrap_or_default(), &c.node))
            }
            Tag::Bsdf if bsdf_node.is_none() && part.is_none() => bsdf_node = Some(&c.node),
            Tag::Emitter if emitter_node.is_none() => emitter_node = Some(&c.node),
            _ => {
                let what = format!(
                    "{} inside {} is ignored",
                    c.node.describe(),
                    node.describe()
                );
                b.warn(&c.node, what);
            }
        }
    }
    let label = node.id.clone().unwrap_or_else(|| node.plugin.clone());
    for (part, shape) in parts {
        let own = part_bsdfs
            .iter()
            .find(|(n, _)| Some(*n) == part)
            .map(|(_, n)| *n);
        let material = match (own.or(bsdf_node), emitter_node) {
            (Some(n), _) => material_for(b, n)?,
            // Mitsuba 3 gives an emitter without a BSDF a black one (shape.cpp): lights do not
            // reflect other lights.
            (None, Some(_)) => *b.black_material.get_or_insert_with(|| {
                b.materials
                    .push(Material::diffuse(SpectrumTexture::Constant(
                        Spectrum::Constant(0.0),
                    )));
                b.materials.len() as u32 - 1
            }),
            (None, None) => b.default_material(),
        };
        let index = b.shapes.len() as u32;
        let light = match emitter_node {
            Some(e) => {
                let l = area_light(e, index)?;
                b.lights.push(l);
                Some(b.lights.len() as u32 - 1)
            }
            None => None,
        };
        b.shapes.push(shape);
        b.shape_material.push(material);
        b.shape_light.push(light);
        b.shape_labels.push(match part {
            Some(p) => format!("{label}.{p}"),
            None => label.clone(),
        });
    }
    Ok(())
}
