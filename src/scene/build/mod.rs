//! Building a renderable [`Scene`] from a Mitsuba XML tree: shapes with their materials and
//! area lights, other emitters, the BVH; the sensor (with its film and sampler) and the
//! integrator through their plugins.

mod emitters;
mod materials;
mod shapes;
pub use crate::plugin::values;

use super::mitsuba::{self, Node, SceneError, Tag, Warning};
use super::{IntegratorSettings, SamplerSettings, Scene};
use crate::accel::Bvh;
use crate::bsdf::Material;
use crate::camera::{Camera, FovAxis, PerspectiveCamera, Sensor};
use crate::film::FilmSettings;
use crate::light::{Light, LightSampler};
use crate::math::{Bounds3, Transform};
use crate::plugin::registry;
pub use materials::build_material;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// Command-line overrides applied while loading.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// `-D name=value` pairs.
    pub defines: Vec<(String, String)>,
    /// Samples per pixel, overriding the scene's sampler.
    pub spp: Option<u32>,
    /// Seed, overriding the scene's sampler.
    pub seed: Option<u64>,
    /// Image width and height, overriding the scene's film (e.g. tiny renders in tests).
    pub resolution: Option<(u32, u32)>,
}

/// Loads and builds a scene file, refusing one whose estimated memory exceeds the machine's
/// ([`crate::limits`]). Warnings (unknown plugins, unused parameters) are returned
/// rather than printed.
pub fn load_scene(path: &Path, opts: &LoadOptions) -> Result<(Scene, Vec<Warning>), SceneError> {
    let mut warnings = Vec::new();
    let scene = load_scene_into(path, opts, &mut warnings)?;
    Ok((scene, warnings))
}

/// [`load_scene`] that adds its warnings to `warnings` even when loading fails, so that the
/// warnings leading up to an error (a `<path>` refused, a parameter misspelled) can be shown
/// with it.
pub fn load_scene_into(
    path: &Path,
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Result<Scene, SceneError> {
    let root = mitsuba::load_file_into(path, &opts.defines, warnings)?;
    finish(&root, opts, warnings)
}

/// Loads a scene from XML text (`file_name` names it in messages and anchors relative paths).
pub fn load_scene_str(
    xml: &str,
    file_name: &Path,
    opts: &LoadOptions,
) -> Result<(Scene, Vec<Warning>), SceneError> {
    let mut warnings = Vec::new();
    let scene = load_scene_str_into(xml, file_name, opts, &mut warnings)?;
    Ok((scene, warnings))
}

/// [`load_scene_str`] that adds its warnings to `warnings` even when loading fails.
pub fn load_scene_str_into(
    xml: &str,
    file_name: &Path,
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Result<Scene, SceneError> {
    let root = mitsuba::load_str_into(xml, file_name, &opts.defines, warnings)?;
    finish(&root, opts, warnings)
}

fn finish(
    root: &Node,
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Result<Scene, SceneError> {
    crate::limits::check(root, crate::limits::machine_memory())?;
    let scene = build_scene(root, opts, warnings)?;
    warnings.extend(mitsuba::check_unused(root));
    Ok(scene)
}

/// Everything collected while walking the tree, and where its warnings go.
pub(crate) struct Builder<'w> {
    pub shapes: Vec<crate::shape::Shape>,
    pub shape_material: Vec<u32>,
    pub shape_light: Vec<Option<u32>>,
    pub shape_labels: Vec<String>,
    pub materials: Vec<Material>,
    /// Materials already built, keyed by node identity (shared through `<ref>`).
    pub material_ids: HashMap<*const Node, u32>,
    pub lights: Vec<Light>,
    pub default_material: Option<u32>,
    /// The black diffuse BSDF of emitters declared without a BSDF (shared).
    pub black_material: Option<u32>,
    /// The load's warnings, in the order they arise (kept by the caller if building fails).
    pub warnings: &'w mut Vec<Warning>,
}

impl<'w> Builder<'w> {
    fn new(warnings: &'w mut Vec<Warning>) -> Self {
        Builder {
            shapes: Vec::new(),
            shape_material: Vec::new(),
            shape_light: Vec::new(),
            shape_labels: Vec::new(),
            materials: Vec::new(),
            material_ids: HashMap::new(),
            lights: Vec::new(),
            default_material: None,
            black_material: None,
            warnings,
        }
    }

    /// A warning located at `node`.
    fn warn(&mut self, node: &Node, message: impl Into<String>) {
        self.warnings.push(Warning {
            loc: node.loc.clone(),
            message: message.into(),
        });
    }
}

fn build_scene(
    root: &Node,
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Result<Scene, SceneError> {
    let mut b = Builder::new(warnings);
    let mut sensor: Option<&Arc<Node>> = None;
    let mut integrator = IntegratorSettings::default();
    for child in &root.children {
        let node = &child.node;
        match node.tag {
            Tag::Shape if node.plugin == "shapegroup" => {
                if !shapes::is_instanced(root, node) {
                    let what = node.describe();
                    b.warn(node, format!("{what} is never instanced; it shows nothing"));
                }
            }
            Tag::Shape => shapes::add_shape(&mut b, node)?,
            // Declared for shapes that attach it with <ref id="…"/>.
            Tag::Emitter if node.plugin == "area" && node.id.is_some() => {
                if !attached_anywhere(root, node) {
                    let what = node.describe();
                    b.warn(
                        node,
                        format!("{what} is attached to no shape; it emits nothing"),
                    );
                }
            }
            Tag::Emitter => emitters::add_emitter(&mut b, node)?,
            Tag::Sensor => {
                if sensor.is_some() {
                    b.warn(node, "only the first sensor is used");
                } else {
                    sensor = Some(node);
                }
            }
            Tag::Integrator => integrator = registry::integrator(node, b.warnings)?,
            // Declared for later <ref>s; built when referenced.
            Tag::Bsdf | Tag::Texture => {}
            _ => {
                let what = node.describe();
                b.warn(
                    node,
                    format!("{what} is not supported by ophis and is ignored"),
                );
            }
        }
    }

    // Mitsuba builds every top-level object: a BSDF that nothing built (no shape or other BSDF
    // uses it, e.g. one kept for `ophis bsdf --id`) is still checked — its mistakes are
    // errors, its parameters read — and then dropped.
    for child in &root.children {
        let n = &child.node;
        let untouched = n.props.unqueried().len() == n.props.len();
        if n.tag == Tag::Bsdf && untouched && !b.material_ids.contains_key(&Arc::as_ptr(n)) {
            materials::build_material(n, b.warnings)?;
        }
    }

    let Sensor {
        camera,
        film,
        mut sampler,
    } = match sensor {
        Some(s) => registry::sensor(s, opts.resolution, b.warnings)?,
        None => {
            // Not Mitsuba's (it refuses a scene without a sensor): a 45° pinhole at the origin.
            let film = match opts.resolution {
                Some((w, h)) => FilmSettings {
                    width: w,
                    height: h,
                    ..FilmSettings::default()
                },
                None => FilmSettings::default(),
            };
            let cam = PerspectiveCamera::new(
                Transform::IDENTITY,
                45.0,
                FovAxis::X,
                film.width,
                film.height,
                1e-2,
                1e4,
            );
            Sensor {
                camera: Camera::Perspective(cam),
                film,
                sampler: SamplerSettings::default(),
            }
        }
    };
    if let Some(spp) = opts.spp {
        sampler.spp = spp;
    }
    if let Some(seed) = opts.seed {
        sampler.seed = seed;
    }

    let bvh = Bvh::build(&b.shapes);
    let mut bounds = Bounds3::EMPTY;
    for s in &b.shapes {
        bounds = bounds.union(&s.bounds());
    }
    if bounds.is_empty() {
        bounds = Bounds3::from_point(camera.position());
    }
    for l in &mut b.lights {
        l.preprocess(&bounds);
    }
    let infinite_lights = b
        .lights
        .iter()
        .enumerate()
        .filter(|(_, l)| l.is_infinite())
        .map(|(i, _)| i as u32)
        .collect();
    let powers: Vec<f32> = b.lights.iter().map(|l| l.power(&b.shapes)).collect();
    // The environments a BSDF's own samples carry well (`integrator::path`'s module notes):
    // `constant`, and Preetham's sky beside a light that is neither (the sun, a lamp). With the
    // sky alone, light samples weighted by MIS against the BSDF's stay a little better (a rough
    // gold sphere on a diffuse ground, `scenes/daylight.xml` with `sun_scale` 0: relVar × spp
    // 0.069 with them, 0.071 without).
    let beside_other = b
        .lights
        .iter()
        .zip(&powers)
        .any(|(l, &p)| p > 0.0 && !matches!(l, Light::Constant(_) | Light::Sky(_)));
    let smooth: Vec<bool> = b
        .lights
        .iter()
        .map(|l| match l {
            Light::Constant(_) => true,
            Light::Sky(_) => beside_other,
            _ => false,
        })
        .collect();
    let light_sampler = LightSampler::with_smooth_envs(&powers, &smooth);
    if b.lights.is_empty() {
        b.warn(root, "the scene has no emitters: the image will be black");
    }
    Ok(Scene {
        shapes: b.shapes,
        bvh,
        materials: b.materials,
        shape_material: b.shape_material,
        shape_light: b.shape_light,
        shape_labels: b.shape_labels,
        lights: b.lights,
        light_sampler,
        infinite_lights,
        camera,
        width: film.width,
        height: film.height,
        filter: film.filter,
        integrator,
        sampler,
        bounds,
    })
}

/// Whether some shape (or a shape in a `shapegroup`) holds `emitter` as a child.
fn attached_anywhere(root: &Node, emitter: &Arc<Node>) -> bool {
    let holds = |s: &Node| s.children.iter().any(|c| Arc::ptr_eq(&c.node, emitter));
    root.children_with_tag(Tag::Shape)
        .any(|s| holds(s) || s.children_with_tag(Tag::Shape).any(|g| holds(g)))
}
