//! The one table of plugins: every plugin name ophis knows, by the element it appears as.
//! Adding a plugin is one new file (manual, declaration, loader, model) and one line here.

use super::suggest::did_you_mean;
use super::{Args, Info, Node, Plugin, SceneError, Tag, Warning};
use crate::bsdf::{self, Material};
use crate::plugin::SpectrumKind;
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

/// Every plugin's description, grouped by element, sorted by name within a group.
pub fn all() -> Vec<&'static Info> {
    let mut v: Vec<&'static Info> = BSDFS.iter().map(|p| &p.info).collect();
    v.extend(TEXTURES.iter().map(|p| &p.info));
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
