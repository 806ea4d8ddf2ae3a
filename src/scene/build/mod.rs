//! Building a renderable [`Scene`] from a Mitsuba XML tree: sensor, film, sampler and
//! integrator settings, shapes with their materials and area lights, other emitters, the BVH.

mod emitters;
mod materials;
mod shapes;
pub use crate::plugin::values;

use super::mitsuba::{self, Node, SceneError, Tag, Warning};
use super::{IntegratorKind, IntegratorSettings, SamplerSettings, Scene};
use crate::accel::Bvh;
use crate::bsdf::Material;
use crate::camera::{Camera, FovAxis, OrthographicCamera, PerspectiveCamera, ThinLensCamera};
use crate::film::Filter;
use crate::light::{Light, LightSampler};
use crate::math::{Bounds3, Transform};
use crate::sampler::SamplerKind;
pub use materials::build_material;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;
use values::{checked_float, checked_int};

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

/// Largest image side accepted; beyond this a film is almost certainly a typo, and its buffers
/// would not fit in memory.
pub const MAX_RESOLUTION: i64 = 1 << 15;

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

/// Everything collected while walking the tree.
#[derive(Default)]
pub(crate) struct Builder {
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
}

fn build_scene(
    root: &Node,
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Result<Scene, SceneError> {
    let mut b = Builder::default();
    let mut sensor: Option<&Arc<Node>> = None;
    let mut integrator = IntegratorSettings::default();
    for child in &root.children {
        let node = &child.node;
        match node.tag {
            Tag::Shape if node.plugin == "shapegroup" => {
                if !shapes::is_instanced(root, node) {
                    warnings.push(Warning {
                        loc: node.loc.clone(),
                        message: format!(
                            "{} is never instanced; it shows nothing",
                            node.describe()
                        ),
                    });
                }
            }
            Tag::Shape => shapes::add_shape(&mut b, node, warnings)?,
            // Declared for shapes that attach it with <ref id="…"/>.
            Tag::Emitter if node.plugin == "area" && node.id.is_some() => {
                if !attached_anywhere(root, node) {
                    warnings.push(Warning {
                        loc: node.loc.clone(),
                        message: format!(
                            "{} is attached to no shape; it emits nothing",
                            node.describe()
                        ),
                    });
                }
            }
            Tag::Emitter => emitters::add_emitter(&mut b, node, warnings)?,
            Tag::Sensor => {
                if sensor.is_some() {
                    warnings.push(Warning {
                        loc: node.loc.clone(),
                        message: "only the first sensor is used".into(),
                    });
                } else {
                    sensor = Some(node);
                }
            }
            Tag::Integrator => integrator = build_integrator(node, warnings)?,
            // Declared for later <ref>s; built when referenced.
            Tag::Bsdf | Tag::Texture => {}
            _ => warnings.push(Warning {
                loc: node.loc.clone(),
                message: format!(
                    "{} is not supported by ophis and is ignored",
                    node.describe()
                ),
            }),
        }
    }

    // Mitsuba builds every top-level object: a BSDF that nothing built (no shape or other BSDF
    // uses it, e.g. one kept for `ophis bsdf --id`) is still checked — its mistakes are
    // errors, its parameters read — and then dropped.
    for child in &root.children {
        let n = &child.node;
        let untouched = n.props.unqueried().len() == n.props.len();
        if n.tag == Tag::Bsdf && untouched && !b.material_ids.contains_key(&Arc::as_ptr(n)) {
            materials::build_material(n, warnings)?;
        }
    }

    let (camera, width, height, filter, mut sampler) = match sensor {
        Some(s) => build_sensor(s, opts.resolution, warnings)?,
        None => {
            let (w, h) = opts.resolution.unwrap_or((768, 576));
            let cam = Camera::Perspective(PerspectiveCamera::new(
                Transform::IDENTITY,
                45.0,
                FovAxis::X,
                w,
                h,
                1e-2,
                1e4,
            ));
            (
                cam,
                w,
                h,
                Filter::gaussian(0.5),
                SamplerSettings {
                    kind: SamplerKind::Independent,
                    spp: 4,
                    seed: 0,
                },
            )
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
    let light_sampler = LightSampler::new(&powers);
    if b.lights.is_empty() {
        warnings.push(Warning {
            loc: root.loc.clone(),
            message: "the scene has no emitters: the image will be black".into(),
        });
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
        width,
        height,
        filter,
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

fn build_integrator(
    node: &Node,
    warnings: &mut Vec<Warning>,
) -> Result<IntegratorSettings, SceneError> {
    let kind = match node.plugin.as_str() {
        "path" => IntegratorKind::Path,
        "aov" => return build_aov(node, warnings),
        // Mitsuba's `moment` renders its (first) nested integrator and adds second-moment AOVs.
        "moment" => {
            let nested: Vec<&Arc<Node>> = node.children_with_tag(Tag::Integrator).collect();
            let Some(first) = nested.first() else {
                return Err(SceneError::at(
                    &node.loc,
                    "integrator 'moment' needs a nested integrator, e.g. <integrator type=\"path\"/>",
                ));
            };
            let extra = if nested.len() > 1 {
                format!(
                    " (the first of its {}; the others are ignored)",
                    nested.len()
                )
            } else {
                String::new()
            };
            warnings.push(Warning {
                loc: node.loc.clone(),
                message: format!(
                    "integrator 'moment': rendering its nested integrator{extra}; the \
                     second-moment AOVs are not written"
                ),
            });
            return build_integrator(first, warnings);
        }
        "direct" => {
            let shading = node.props.contains("shading_samples");
            if shading
                && (node.props.contains("emitter_samples") || node.props.contains("bsdf_samples"))
            {
                return Err(SceneError::at(
                    &node.loc,
                    "integrator 'direct': found 'shading_samples' and 'emitter_samples' or \
                     'bsdf_samples'; expected either the first or the others",
                ));
            }
            let all = checked_int(node, "shading_samples", 1, 0, 1 << 16)?;
            let emitter_samples = checked_int(node, "emitter_samples", all, 0, 1 << 16)? as u32;
            let bsdf_samples = checked_int(node, "bsdf_samples", all, 0, 1 << 16)? as u32;
            if emitter_samples + bsdf_samples == 0 {
                return Err(SceneError::at(
                    &node.loc,
                    "integrator 'direct': found no emitter or BSDF samples; expected at least one",
                ));
            }
            let hide_emitters = node.props.get_bool("hide_emitters", false)?;
            return Ok(IntegratorSettings {
                kind: IntegratorKind::Direct {
                    emitter_samples,
                    bsdf_samples,
                },
                hide_emitters,
                ..IntegratorSettings::default()
            });
        }
        other => {
            warnings.push(Warning {
                loc: node.loc.clone(),
                message: format!(
                    "integrator '{other}' is not supported; using 'path' with its parameters"
                ),
            });
            IntegratorKind::Path
        }
    };
    let max_depth = checked_int(node, "max_depth", -1, -1, 1 << 20)?;
    let rr_depth = checked_int(node, "rr_depth", 5, 0, 1 << 20)?;
    let hide_emitters = node.props.get_bool("hide_emitters", false)?;
    Ok(IntegratorSettings {
        kind,
        max_depth: if max_depth < 0 {
            None
        } else {
            Some(max_depth as u32)
        },
        rr_depth: rr_depth as u32,
        hide_emitters,
        aov: None,
    })
}

/// Mitsuba's `aov`: the `aovs` list and at most one nested `path` for the colour image (see
/// `integrator/aov.rs`).
fn build_aov(node: &Node, warnings: &mut Vec<Warning>) -> Result<IntegratorSettings, SceneError> {
    use crate::integrator::aov::{parse_aovs, AovSettings};
    let spec = node.props.get_string("aovs", "")?;
    let aovs = parse_aovs(&spec).map_err(|e| {
        SceneError::at(
            node.props.location("aovs").unwrap_or(&node.loc),
            format!("{}: 'aovs': {e}", node.describe()),
        )
    })?;
    let nested: Vec<_> = node
        .children
        .iter()
        .filter(|c| c.node.tag == Tag::Integrator)
        .collect();
    if let Some(extra) = nested.get(1) {
        return Err(SceneError::at(
            &extra.node.loc,
            "ophis's aov integrator takes at most one nested integrator",
        ));
    }
    let (mut settings, has_image, image_name) = match nested.first() {
        Some(c) if c.node.plugin == "aov" => {
            return Err(SceneError::at(
                &c.node.loc,
                "an aov integrator cannot nest another",
            ))
        }
        Some(c) => (build_integrator(&c.node, warnings)?, true, c.name.clone()),
        None => (IntegratorSettings::default(), false, None),
    };
    settings.aov = Some(AovSettings {
        aovs,
        has_image,
        image_name,
    });
    Ok(settings)
}

type SensorParts = (Camera, u32, u32, Filter, SamplerSettings);

fn build_sensor(
    node: &Node,
    resolution: Option<(u32, u32)>,
    warnings: &mut Vec<Warning>,
) -> Result<SensorParts, SceneError> {
    let kind = node.plugin.as_str();
    if !matches!(kind, "perspective" | "thinlens" | "orthographic") {
        warnings.push(Warning {
            loc: node.loc.clone(),
            message: format!(
                "sensor '{}' is not supported; rendering it as a 'perspective' pinhole camera",
                node.plugin
            ),
        });
    }
    let mut width = 768;
    let mut height = 576;
    let mut filter = Filter::gaussian(0.5);
    let mut sampler = SamplerSettings {
        kind: SamplerKind::Independent,
        spp: 4,
        seed: 0,
    };
    for child in &node.children {
        let c = &child.node;
        match c.tag {
            Tag::Film => {
                if c.plugin != "hdrfilm" && c.plugin != "ldrfilm" {
                    warnings.push(Warning {
                        loc: c.loc.clone(),
                        message: format!("film '{}' is treated as 'hdrfilm'", c.plugin),
                    });
                }
                width = checked_int(c, "width", 768, 1, MAX_RESOLUTION)? as u32;
                height = checked_int(c, "height", 576, 1, MAX_RESOLUTION)? as u32;
                for f in c.children_with_tag(Tag::Rfilter) {
                    filter = build_filter(f, warnings)?;
                }
            }
            Tag::Sampler => {
                sampler.kind = match c.plugin.as_str() {
                    "independent" => SamplerKind::Independent,
                    "stratified" | "multijitter" | "ldsampler" | "orthogonal" | "sobol"
                    | "halton" | "hammersley" => SamplerKind::Sobol,
                    other => {
                        warnings.push(Warning {
                            loc: c.loc.clone(),
                            message: format!("sampler '{other}' is unknown; using 'independent'"),
                        });
                        SamplerKind::Independent
                    }
                };
                sampler.spp = checked_int(c, "sample_count", 4, 1, 1 << 24)? as u32;
                sampler.seed = checked_int(c, "seed", 0, 0, i64::MAX)? as u64;
            }
            _ => warnings.push(Warning {
                loc: c.loc.clone(),
                message: format!("{} inside a sensor is ignored", c.describe()),
            }),
        }
    }
    let near = checked_float(
        node,
        "near_clip",
        1e-2,
        |v| v > 0.0 && v.is_finite(),
        "positive",
    )?;
    let far = checked_float(
        node,
        "far_clip",
        1e4,
        |v| v > near && v.is_finite(),
        "greater than near_clip",
    )?;
    let to_world = node.props.get_transform("to_world", Transform::IDENTITY)?;
    if let Some((w, h)) = resolution {
        (width, height) = (w.max(1), h.max(1));
    }
    if kind == "orthographic" {
        let cam = OrthographicCamera::new(to_world, width, height, near, far);
        return Ok((Camera::Orthographic(cam), width, height, filter, sampler));
    }
    let (fov, axis) = field_of_view(node)?;
    // Mitsuba's projective cameras all read the focus distance; the pinhole ignores it.
    let focus = checked_float(
        node,
        "focus_distance",
        far,
        |v| v > 0.0 && v.is_finite(),
        "positive",
    )?;
    let pinhole = PerspectiveCamera::new(to_world, fov, axis, width, height, near, far);
    let cam = if kind == "thinlens" {
        let Some(aperture) = node.props.get_float_opt("aperture_radius")? else {
            return Err(SceneError::at(
                &node.loc,
                format!("{} needs an 'aperture_radius'", node.describe()),
            ));
        };
        if !(aperture >= 0.0 && aperture.is_finite()) {
            return Err(SceneError::at(
                node.props.location("aperture_radius").unwrap_or(&node.loc),
                format!("aperture_radius must be zero or positive, got {aperture}"),
            ));
        }
        Camera::ThinLens(ThinLensCamera {
            pinhole,
            aperture_radius: aperture,
            focus_distance: focus,
        })
    } else {
        Camera::Perspective(pinhole)
    };
    Ok((cam, width, height, filter, sampler))
}

/// `fov` (or `focal_length`) and `fov_axis` of a perspective or thin-lens camera.
fn field_of_view(node: &Node) -> Result<(f32, FovAxis), SceneError> {
    let fov = match node.props.get_float_opt("fov")? {
        Some(f) => f,
        None => {
            // Mitsuba also accepts a focal length such as "50mm" (35 mm film equivalent).
            let fl = node.props.get_string("focal_length", "50mm")?;
            let mm: f32 = fl.trim_end_matches("mm").trim().parse().map_err(|_| {
                SceneError::at(
                    node.props.location("focal_length").unwrap_or(&node.loc),
                    format!("focal_length must look like '50mm', got '{fl}'"),
                )
            })?;
            if !(mm > 0.0) {
                return Err(SceneError::at(&node.loc, "focal_length must be positive"));
            }
            // Horizontal fov of a 36 mm wide frame, applied to the diagonal as Mitsuba does.
            2.0 * (43.266_615 / (2.0 * mm)).atan().to_degrees()
        }
    };
    if !(fov > 0.0 && fov < 180.0) {
        return Err(SceneError::at(
            node.props.location("fov").unwrap_or(&node.loc),
            format!("fov must be between 0 and 180 degrees, got {fov}"),
        ));
    }
    let axis_name = node.props.get_string(
        "fov_axis",
        if node.props.contains("fov") {
            "x"
        } else {
            "diagonal"
        },
    )?;
    let axis = FovAxis::from_name(&axis_name).ok_or_else(|| {
        SceneError::at(
            node.props.location("fov_axis").unwrap_or(&node.loc),
            format!("fov_axis must be one of x, y, diagonal, smaller, larger; got '{axis_name}'"),
        )
    })?;
    Ok((fov, axis))
}

fn build_filter(node: &Node, warnings: &mut Vec<Warning>) -> Result<Filter, SceneError> {
    Ok(match node.plugin.as_str() {
        "box" => Filter::Box,
        "tent" => Filter::Tent {
            radius: checked_float(node, "radius", 1.0, |v| v > 0.0 && v <= 16.0, "in (0, 16]")?,
        },
        "gaussian" => Filter::gaussian(checked_float(
            node,
            "stddev",
            0.5,
            |v| v > 0.0 && v <= 4.0,
            "in (0, 4]",
        )?),
        other => {
            warnings.push(Warning {
                loc: node.loc.clone(),
                message: format!(
                    "reconstruction filter '{other}' is not supported; using 'gaussian'"
                ),
            });
            Filter::gaussian(0.5)
        }
    })
}
