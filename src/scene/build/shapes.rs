//! Shapes: Mitsuba's `sphere`, `disk`, `rectangle`, `cube`, `obj`, `ply`, each with its BSDF
//! (nested or `<ref>`) and optional area emitter. A `snake` becomes one shape per part; a nested
//! BSDF named after a part (`belly`, `head`, `eyes`, `body`) is that part's, the unnamed one
//! every other part's.

use super::emitters::area_light;
use super::materials::material_for;
use super::Builder;
use crate::math::{Transform, Vec3};
use crate::scene::mitsuba::{Node, SceneError, Tag, Warning};
use crate::shape::{MeshOptions, Shape, Sphere, TriangleMesh};

pub(crate) fn add_shape(
    b: &mut Builder,
    node: &Node,
    warnings: &mut Vec<Warning>,
) -> Result<(), SceneError> {
    let err =
        |e: &dyn std::fmt::Display| SceneError::at(&node.loc, format!("{}: {e}", node.describe()));
    let to_world = node.props.get_transform("to_world", Transform::IDENTITY)?;
    let flip = node.props.get_bool("flip_normals", false)?;
    let shape = match node.plugin.as_str() {
        "sphere" => {
            let center = node.props.get_point("center", Vec3::ZERO)?;
            let radius = node.props.get_float("radius", 1.0)?;
            if !(radius > 0.0 && radius.is_finite()) {
                let loc = node.props.location("radius").unwrap_or(&node.loc);
                return Err(SceneError::at(
                    loc,
                    format!(
                        "radius of {} must be positive, got {radius}",
                        node.describe()
                    ),
                ));
            }
            Shape::Sphere(Sphere::new(center, radius, &to_world, flip).map_err(|e| err(&e))?)
        }
        "disk" => Shape::Disk(crate::shape::Disk::new(&to_world, flip)),
        "rectangle" => Shape::Mesh(TriangleMesh::rectangle(&to_world, flip).map_err(|e| err(&e))?),
        "cube" => Shape::Mesh(TriangleMesh::cube(&to_world, flip).map_err(|e| err(&e))?),
        "torus" => super::procedural::torus(node, &to_world, flip)?,
        "litter" => super::procedural::litter(node, &to_world, flip)?,
        "snake" => {
            let parts = super::procedural::snake(node, &to_world, flip, warnings)?;
            return add_parts(b, node, parts, warnings);
        }
        "obj" | "ply" => {
            let Some(path) = node.props.get_path_opt("filename")? else {
                return Err(SceneError::at(
                    &node.loc,
                    format!("{} needs a 'filename'", node.describe()),
                ));
            };
            let opts = MeshOptions {
                flip_normals: flip,
                face_normals: node.props.get_bool("face_normals", false)?,
                flip_tex_coords: node.props.get_bool("flip_tex_coords", true)?,
            };
            let loc = node
                .props
                .location("filename")
                .cloned()
                .unwrap_or_else(|| node.loc.clone());
            let mesh = if node.plugin == "obj" {
                TriangleMesh::from_obj(&path, &to_world, &opts)
            } else {
                TriangleMesh::from_ply(&path, &to_world, &opts)
            }
            .map_err(|e| SceneError::at(&loc, format!("{}: {e}", node.describe())))?;
            if mesh.degenerate_dropped() > 0 {
                warnings.push(Warning {
                    loc: node.loc.clone(),
                    message: format!(
                        "{}: dropped {} degenerate triangles",
                        node.describe(),
                        mesh.degenerate_dropped()
                    ),
                });
            }
            Shape::Mesh(mesh)
        }
        other => {
            warnings.push(Warning {
                loc: node.loc.clone(),
                message: format!("shape '{other}' is not supported by ophis and is ignored"),
            });
            return Ok(());
        }
    };

    add_parts(b, node, vec![(None, shape)], warnings)
}

/// Adds the shapes made from one `<shape>` element, each part with the nested BSDF of its name
/// (the unnamed one otherwise) and the element's emitter.
fn add_parts<P: PartName>(
    b: &mut Builder,
    node: &Node,
    parts: Vec<(P, Shape)>,
    warnings: &mut Vec<Warning>,
) -> Result<(), SceneError> {
    let part_names: Vec<&str> = parts.iter().filter_map(|(p, _)| p.part_name()).collect();
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
            _ => warnings.push(Warning {
                loc: c.node.loc.clone(),
                message: format!(
                    "{} inside {} is ignored",
                    c.node.describe(),
                    node.describe()
                ),
            }),
        }
    }
    let label = node.id.clone().unwrap_or_else(|| node.plugin.clone());
    for (part, shape) in parts {
        let own = part_bsdfs
            .iter()
            .find(|(n, _)| Some(*n) == part.part_name())
            .map(|(_, n)| *n);
        let material = match own.or(bsdf_node) {
            Some(n) => material_for(b, n, warnings)?,
            None => b.default_material(),
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
        b.shape_labels.push(match part.part_name() {
            Some(p) => format!("{label}.{p}"),
            None => label.clone(),
        });
    }
    Ok(())
}

/// The name of a part of a shape made of several (none for a plain shape).
trait PartName {
    fn part_name(&self) -> Option<&'static str>;
}

impl PartName for Option<crate::shape::snake::Part> {
    fn part_name(&self) -> Option<&'static str> {
        self.map(|p| p.name())
    }
}

impl PartName for crate::shape::snake::Part {
    fn part_name(&self) -> Option<&'static str> {
        Some(self.name())
    }
}
