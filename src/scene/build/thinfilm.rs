//! Thin-film BSDFs from XML: `thinfilm`, `roughthinfilm`, `thinfilmconductor`,
//! `roughthinfilmconductor`, and the seed's `dielectricThinFilm`, `roughdielectricThinFilm`,
//! `conductorThinFilm` (parameter tables in `src/bsdf/thinfilm.rs`, `roughthinfilm.rs`,
//! `thinfilmconductor.rs`).

use super::materials::{float_texture, roughness, spectrum_texture};
use super::values::{ior, spectrum, SpectrumKind};
use crate::bsdf::filmfresnel::FilmMode;
use crate::bsdf::filmmaterial::{
    FilmBase, FilmIor, FilmMaterial, DEFAULT_FILM_IOR, DEFAULT_FILM_THICKNESS, SEED_FILM_THICKNESS,
};
use crate::bsdf::Material;
use crate::scene::mitsuba::{Node, SceneError, Tag, Value};
use crate::spectrum::{ior as named_ior, Spectrum};
use crate::texture::FloatTexture;

/// Whether `plugin` is one of the film BSDFs.
pub(crate) fn is_film_plugin(plugin: &str) -> bool {
    matches!(
        plugin,
        "thinfilm"
            | "roughthinfilm"
            | "thinfilmconductor"
            | "roughthinfilmconductor"
            | "dielectricThinFilm"
            | "roughdielectricThinFilm"
            | "conductorThinFilm"
    )
}

/// Largest film thickness accepted (nm): 100 µm is far beyond a coherent film already.
const MAX_THICKNESS: f32 = 1e5;

/// The one of two spellings that is present (error if both are).
fn pick<'a>(node: &Node, a: &'a str, b: &'a str) -> Result<&'a str, SceneError> {
    if node.props.contains(a) && node.props.contains(b) {
        let loc = node.props.location(b).unwrap_or(&node.loc);
        return Err(SceneError::at(
            loc,
            format!("{}: give '{a}' or '{b}', not both", node.describe()),
        ));
    }
    if node.props.contains(b) || node.child(b).is_some() {
        Ok(b)
    } else {
        Ok(a)
    }
}

/// A film index: a positive number, `keratin`, or a named dielectric.
fn film_ior(node: &Node, name: &str, default: FilmIor) -> Result<FilmIor, SceneError> {
    match node.props.get(name) {
        None => Ok(default),
        Some((Value::String(s), _)) if s == "keratin" => Ok(FilmIor::Keratin),
        Some(_) => Ok(FilmIor::Constant(ior(node, name, "air")?)),
    }
}

/// The film thickness in nm: a number in [0, 1e5] or a float texture.
fn thickness(node: &Node, name: &str, default: f32) -> Result<FloatTexture, SceneError> {
    if node.child(name).is_some_and(|c| c.tag == Tag::Texture) {
        return float_texture(node, name, default);
    }
    let v = node.props.get_float(name, default)?;
    if !(0.0..=MAX_THICKNESS).contains(&v) {
        let loc = node.props.location(name).unwrap_or(&node.loc);
        return Err(SceneError::at(
            loc,
            format!(
                "'{name}' of {} must be a film thickness in nm between 0 and {MAX_THICKNESS}, got {v}",
                node.describe()
            ),
        ));
    }
    Ok(FloatTexture::Constant(v))
}

/// A metal base: `eta` and `k`, or `material` (default `Cu`; `none` is refused).
fn metal(node: &Node) -> Result<FilmBase, SceneError> {
    if node.props.contains("eta") || node.props.contains("k") {
        let eta = spectrum(
            node,
            "eta",
            SpectrumKind::Unbounded,
            Spectrum::Constant(0.0),
        )?;
        let k = spectrum(node, "k", SpectrumKind::Unbounded, Spectrum::Constant(1.0))?;
        return Ok(FilmBase::Conductor { eta, k });
    }
    let name = node.props.get_string("material", "Cu")?;
    let (eta, k) = named_ior::conductor_nk(&name).ok_or_else(|| {
        SceneError::at(
            node.props.location("material").unwrap_or(&node.loc),
            format!(
                "{}: unknown metal '{name}' under the film (known: {}; a perfect mirror 'none' \
                 has no complex index)",
                node.describe(),
                named_ior::conductor_names().join(", ")
            ),
        )
    })?;
    Ok(FilmBase::Conductor { eta, k })
}

/// Builds one of the film plugins (see [`is_film_plugin`]).
pub(crate) fn film_material(node: &Node) -> Result<Material, SceneError> {
    let plugin = node.plugin.as_str();
    let seed = plugin.ends_with("ThinFilm");
    let conductor = plugin.contains("conductor");
    let is_rough = plugin.starts_with("rough");
    let (default_ior, default_d) = if seed {
        (
            FilmIor::Constant(named_ior::dielectric_ior("bk7").unwrap_or(1.5046)),
            SEED_FILM_THICKNESS,
        )
    } else {
        (FilmIor::Constant(DEFAULT_FILM_IOR), DEFAULT_FILM_THICKNESS)
    };
    let ior_name = pick(node, "film_ior", "medium_ior")?;
    let d_name = pick(node, "film_thickness", "thickness")?;
    let mode_name = node.props.get_string("mode", "spectral")?;
    let mode = FilmMode::from_name(&mode_name).ok_or_else(|| {
        SceneError::at(
            node.props.location("mode").unwrap_or(&node.loc),
            format!(
                "'mode' of {} must be 'spectral' or 'thesis', got '{mode_name}'",
                node.describe()
            ),
        )
    })?;
    let base = if conductor {
        metal(node)?
    } else {
        FilmBase::Dielectric {
            int_ior: ior(node, "int_ior", if seed { "diamond" } else { "bk7" })?,
        }
    };
    let one =
        |name: &str| spectrum_texture(node, name, SpectrumKind::Albedo, Spectrum::Constant(1.0));
    Ok(Material::ThinFilm(Box::new(FilmMaterial {
        base,
        ext_ior: ior(node, "ext_ior", "air")?,
        film_ior: film_ior(node, ior_name, default_ior)?,
        thickness: thickness(node, d_name, default_d)?,
        mode,
        rough: if is_rough {
            Some(roughness(node)?)
        } else {
            None
        },
        specular_reflectance: one("specular_reflectance")?,
        specular_transmittance: if conductor {
            crate::texture::SpectrumTexture::Constant(Spectrum::Constant(1.0))
        } else {
            one("specular_transmittance")?
        },
    })))
}
