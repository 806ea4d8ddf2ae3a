//! The one table of plugins: every plugin name ophis knows, by the element it appears as.
//! Adding a plugin is one new file (manual, declaration, loader, model) and one line here.

use super::suggest::did_you_mean;
use super::{Args, Info, Node, Plugin, SceneError, Tag, Warning};
use crate::bsdf::{self, Material};
use crate::light::{self, Light};
use crate::math::Transform;
use crate::plugin::SpectrumKind;
use crate::shape::{self, Parts};
use crate::texture::{self, FloatTexture, SpectrumTexture, Texture, Want};

/// BSDFs.
pub(crate) const BSDFS: &[&Plugin<Material>] = &[
    &bsdf::absorption::PLUGIN,
    &bsdf::bumpmap::PLUGIN,
    &bsdf::conductor::PLUGIN,
    &bsdf::dielectric::PLUGIN,
    &bsdf::diffuse::PLUGIN,
    &bsdf::filmstack::PLUGIN,
    &bsdf::layered::PLUGIN,
    &bsdf::normalmap::PLUGIN,
    &bsdf::null::PLUGIN,
    &bsdf::plastic::PLUGIN,
    &bsdf::roughconductor::PLUGIN,
    &bsdf::roughdielectric::PLUGIN,
    &bsdf::roughplastic::PLUGIN,
    &bsdf::roughthinfilm::PLUGIN,
    &bsdf::roughthinfilm::THESIS_PLUGIN,
    &bsdf::roughthinfilmconductor::PLUGIN,
    &bsdf::thindielectric::PLUGIN,
    &bsdf::thinfilm::PLUGIN,
    &bsdf::thinfilm::THESIS_PLUGIN,
    &bsdf::thinfilmconductor::PLUGIN,
    &bsdf::thinfilmconductor::THESIS_PLUGIN,
    &bsdf::twosided::PLUGIN,
];

/// Textures.
pub(crate) const TEXTURES: &[&Plugin<Texture, Want>] = &[
    &texture::bitmap::PLUGIN,
    &texture::checkerboard::PLUGIN,
    &texture::per_scale::PLUGIN,
    &texture::scales::PLUGIN,
];

/// Emitters; the context is the index of the shape an emitter is nested in.
pub(crate) const EMITTERS: &[&Plugin<Vec<Light>, Option<u32>>] = &[
    &light::area::PLUGIN,
    &light::constant::PLUGIN,
    &light::directional::PLUGIN,
    &light::envmap::PLUGIN,
    &light::point::PLUGIN,
    &light::sunsky::PLUGIN,
    &light::sunsky::SKY_PLUGIN,
    &light::sunsky::SUN_PLUGIN,
];

/// Shapes; the context is the transform of the `instance` placing them (identity otherwise).
/// `shapegroup` and `instance` are structure, handled by the scene builder.
pub(crate) const SHAPES: &[&Plugin<Parts, Transform>] = &[
    &shape::cube::PLUGIN,
    &shape::cylinder::PLUGIN,
    &shape::disk::PLUGIN,
    &shape::litter::PLUGIN,
    &shape::obj::PLUGIN,
    &shape::ply::PLUGIN,
    &shape::rectangle::PLUGIN,
    &shape::serialized::PLUGIN,
    &shape::snake::PLUGIN,
    &shape::sphere::PLUGIN,
    &shape::torus::PLUGIN,
];

/// Mitsuba 3 plugins ophis does not have: a scene using one still loads, without it, and a
/// warning says so (any other unknown name is an error with a suggestion).
const MITSUBA_ONLY: &[(Tag, &[&str])] = &[
    (
        Tag::Emitter,
        &["spot", "projector", "mesh_attribute", "volumelight"],
    ),
    (
        Tag::Shape,
        &[
            "bsplinecurve",
            "linearcurve",
            "sdfgrid",
            "ellipsoids",
            "ellipsoidsmesh",
        ],
    ),
];

/// Every plugin's description, grouped by element, sorted by name within a group.
pub fn all() -> Vec<&'static Info> {
    let mut v: Vec<&'static Info> = BSDFS.iter().map(|p| &p.info).collect();
    v.extend(TEXTURES.iter().map(|p| &p.info));
    v.extend(EMITTERS.iter().map(|p| &p.info));
    v.extend(SHAPES.iter().map(|p| &p.info));
    v.sort_by_key(|i| (i.tag.as_str(), i.name.to_lowercase()));
    v
}

/// The plugin called `name` (or an alias) that appears as `tag`.
pub fn info(tag: Tag, name: &str) -> Option<&'static Info> {
    all()
        .into_iter()
        .find(|i| i.tag == tag && i.is_called(name))
}

/// The plugin called `name` among any kind (for `ophis plugins NAME`).
pub fn find(name: &str) -> Vec<&'static Info> {
    all().into_iter().filter(|i| i.is_called(name)).collect()
}

/// "unknown bsdf 'roughconductr' (did you mean 'roughconductor'?)", at the element.
fn unknown(tag: Tag, node: &Node) -> SceneError {
    let names = all()
        .into_iter()
        .filter(|i| i.tag == tag)
        .flat_map(|i| std::iter::once(i.name).chain(i.aliases.iter().copied()));
    let hint = did_you_mean(&node.plugin, names);
    SceneError::at(
        &node.loc,
        format!(
            "unknown {tag} plugin '{}'{hint}; `ophis plugins` lists the known ones",
            node.plugin
        ),
    )
}

fn lookup<T, C>(
    table: &'static [&'static Plugin<T, C>],
    tag: Tag,
    node: &Node,
) -> Result<&'static Plugin<T, C>, SceneError> {
    table
        .iter()
        .copied()
        .find(|p| p.info.is_called(&node.plugin))
        .ok_or_else(|| unknown(tag, node))
}

/// Builds the BSDF a `<bsdf>` node describes (nested BSDFs and textures included).
pub fn bsdf(node: &Node, warnings: &mut Vec<Warning>) -> Result<Material, SceneError> {
    let p = lookup(BSDFS, Tag::Bsdf, node)?;
    (p.load)(&mut Args::new(node, &p.info, warnings), ())
}

/// Builds the lights an `<emitter>` describes (`sunsky` is two; a Mitsuba plugin ophis lacks
/// is none, with a warning); `shape` is the index of the shape it is nested in.
pub fn emitter(
    node: &Node,
    shape: Option<u32>,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<Light>, SceneError> {
    if mitsuba_only(Tag::Emitter, node, warnings) {
        return Ok(Vec::new());
    }
    let p = lookup(EMITTERS, Tag::Emitter, node)?;
    (p.load)(&mut Args::new(node, &p.info, warnings), shape)
}

/// Builds the shapes a `<shape>` describes (a `snake` is one per part; a Mitsuba shape ophis
/// lacks, or a mesh of only zero-area triangles, is none, with a warning), placed after
/// `parent`.
pub fn shape(
    node: &Node,
    parent: Transform,
    warnings: &mut Vec<Warning>,
) -> Result<Parts, SceneError> {
    if mitsuba_only(Tag::Shape, node, warnings) {
        return Ok(Vec::new());
    }
    let p = lookup(SHAPES, Tag::Shape, node)?;
    (p.load)(&mut Args::new(node, &p.info, warnings), parent)
}

/// Whether `node` names a Mitsuba plugin ophis does not have (then warned about).
fn mitsuba_only(tag: Tag, node: &Node, warnings: &mut Vec<Warning>) -> bool {
    let known = MITSUBA_ONLY
        .iter()
        .any(|(t, names)| *t == tag && names.contains(&node.plugin.as_str()));
    if known {
        warnings.push(Warning {
            loc: node.loc.clone(),
            message: format!(
                "{tag} '{}' is a Mitsuba plugin ophis does not have; it is ignored",
                node.plugin
            ),
        });
    }
    known
}

/// Builds a texture of the kind asked for.
pub fn texture(
    node: &Node,
    want: Want,
    warnings: &mut Vec<Warning>,
) -> Result<Texture, SceneError> {
    let p = lookup(TEXTURES, Tag::Texture, node)?;
    (p.load)(&mut Args::new(node, &p.info, warnings), want)
}

/// A texture used as a colour.
pub fn spectrum_texture(
    node: &Node,
    kind: SpectrumKind,
    warnings: &mut Vec<Warning>,
) -> Result<SpectrumTexture, SceneError> {
    match texture(node, Want::Spectrum(kind), warnings)? {
        Texture::Spectrum(t) => Ok(t),
        _ => Err(SceneError::at(
            &node.loc,
            format!("{} cannot be used as a colour", node.describe()),
        )),
    }
}

/// A texture used as a number.
pub fn float_texture(node: &Node, warnings: &mut Vec<Warning>) -> Result<FloatTexture, SceneError> {
    match texture(node, Want::Float, warnings)? {
        Texture::Float(t) => Ok(t),
        _ => Err(SceneError::at(
            &node.loc,
            format!("{} cannot be used as a number", node.describe()),
        )),
    }
}
