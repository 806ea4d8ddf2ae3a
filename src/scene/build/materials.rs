//! BSDFs: Mitsuba's `diffuse`, `dielectric`, `thindielectric`, `roughdielectric`, `conductor`,
//! `roughconductor`, `plastic`, `roughplastic`, `twosided`, `null`, with colours given as values
//! or as nested/referenced `checkerboard` textures. The thin-film BSDFs are in `thinfilm.rs`.

use super::values::{checked_float, ior, spectrum, spectrum_opt, SpectrumKind};
use super::Builder;
use crate::bsdf::material::{ConductorIor, DEFAULT_ALPHA, PLASTIC_INT_IOR};
use crate::bsdf::microfacet::MicrofacetType;
use crate::bsdf::Material;
use crate::image_io::read_image;
use crate::math::{Mat3, Vec3};
use crate::scene::mitsuba::{Node, SceneError, Tag, Warning};
use crate::spectrum::{ior as named_ior, Spectrum};
use crate::texture::bitmap::{Bitmap, Wrap};
use crate::texture::{FloatTexture, SpectrumTexture};
use std::sync::Arc;

impl Builder {
    /// Mitsuba's implicit BSDF for shapes without one: a diffuse 0.5.
    pub(crate) fn default_material(&mut self) -> u32 {
        if let Some(m) = self.default_material {
            return m;
        }
        self.materials.push(Material::default_diffuse());
        let i = self.materials.len() as u32 - 1;
        self.default_material = Some(i);
        i
    }
}

/// The material index for a BSDF node, building it once per node (shared through `<ref>`).
pub(crate) fn material_for(
    b: &mut Builder,
    node: &Arc<Node>,
    warnings: &mut Vec<Warning>,
) -> Result<u32, SceneError> {
    let key = Arc::as_ptr(node);
    if let Some(&i) = b.material_ids.get(&key) {
        return Ok(i);
    }
    let m = build_material(node, warnings)?;
    b.materials.push(m);
    let i = b.materials.len() as u32 - 1;
    b.material_ids.insert(key, i);
    Ok(i)
}

/// The material a `<bsdf>` node describes (nested BSDFs and textures included).
pub fn build_material(node: &Node, warnings: &mut Vec<Warning>) -> Result<Material, SceneError> {
    let sr =
        |name: &str| spectrum_texture(node, name, SpectrumKind::Albedo, Spectrum::Constant(1.0));
    Ok(match node.plugin.as_str() {
        "diffuse" => Material::diffuse(spectrum_texture(
            node,
            "reflectance",
            SpectrumKind::Albedo,
            Spectrum::Constant(0.5),
        )?),
        "dielectric" => Material::dielectric(
            ior(node, "int_ior", "bk7")?,
            ior(node, "ext_ior", "air")?,
            sr("specular_reflectance")?,
            sr("specular_transmittance")?,
        ),
        "thindielectric" => Material::thin_dielectric(
            ior(node, "int_ior", "bk7")?,
            ior(node, "ext_ior", "air")?,
            sr("specular_reflectance")?,
            sr("specular_transmittance")?,
        ),
        "roughdielectric" => {
            let (dist, au, av) = roughness(node)?;
            Material::rough_dielectric(
                dist,
                au,
                av,
                ior(node, "int_ior", "bk7")?,
                ior(node, "ext_ior", "air")?,
                sr("specular_reflectance")?,
                sr("specular_transmittance")?,
            )
        }
        "conductor" => Material::conductor(conductor_ior(node)?, sr("specular_reflectance")?),
        "roughconductor" => {
            let (dist, au, av) = roughness(node)?;
            Material::rough_conductor(
                dist,
                au,
                av,
                conductor_ior(node)?,
                sr("specular_reflectance")?,
            )
        }
        "plastic" => Material::plastic(
            ior_or(node, "int_ior", PLASTIC_INT_IOR)?,
            ior(node, "ext_ior", "air")?,
            spectrum_texture(
                node,
                "diffuse_reflectance",
                SpectrumKind::Albedo,
                Spectrum::Constant(0.5),
            )?,
            sr("specular_reflectance")?,
            node.props.get_bool("nonlinear", false)?,
        ),
        "roughplastic" => {
            let (dist, alpha, _) = roughness(node)?;
            Material::rough_plastic(
                dist,
                alpha,
                ior_or(node, "int_ior", PLASTIC_INT_IOR)?,
                ior(node, "ext_ior", "air")?,
                spectrum_texture(
                    node,
                    "diffuse_reflectance",
                    SpectrumKind::Albedo,
                    Spectrum::Constant(0.5),
                )?,
                sr("specular_reflectance")?,
                node.props.get_bool("nonlinear", false)?,
            )
        }
        "twosided" => {
            let inner: Vec<&Arc<Node>> = node.children_with_tag(Tag::Bsdf).collect();
            match inner.as_slice() {
                [front] => Material::two_sided(build_material(front, warnings)?, None),
                [front, back] => Material::two_sided(
                    build_material(front, warnings)?,
                    Some(build_material(back, warnings)?),
                ),
                _ => {
                    return Err(SceneError::at(
                        &node.loc,
                        format!(
                            "twosided needs one or two nested BSDFs, found {}",
                            inner.len()
                        ),
                    ))
                }
            }
        }
        "null" => Material::Null,
        film if super::thinfilm::is_film_plugin(film) => super::thinfilm::film_material(node)?,
        "bumpmap" => super::scales::bumpmap(node, warnings)?,
        "normalmap" => super::scales::normalmap(node, warnings)?,
        "multilayered" => super::layered::multilayered(node, warnings)?,
        "absorption" | "Absorption" => super::layered::absorption(node)?,
        other => {
            warnings.push(Warning {
                loc: node.loc.clone(),
                message: format!(
                    "BSDF '{other}' is not supported by ophis; using a grey diffuse BSDF"
                ),
            });
            Material::default_diffuse()
        }
    })
}

/// A numeric index of refraction or a named one, with a numeric default.
fn ior_or(node: &Node, name: &str, default: f32) -> Result<f32, SceneError> {
    if node.props.contains(name) {
        ior(node, name, "air")
    } else {
        Ok(default)
    }
}

/// `distribution` and `alpha` / `alpha_u` + `alpha_v` (floats or textures).
pub(super) fn roughness(
    node: &Node,
) -> Result<(MicrofacetType, FloatTexture, FloatTexture), SceneError> {
    let name = node.props.get_string("distribution", "beckmann")?;
    let dist = MicrofacetType::from_name(&name).ok_or_else(|| {
        SceneError::at(
            node.props.location("distribution").unwrap_or(&node.loc),
            format!("distribution must be 'beckmann' or 'ggx', got '{name}'"),
        )
    })?;
    node.props.get_bool("sample_visible", true)?;
    if node.props.contains("alpha_u")
        || node.props.contains("alpha_v")
        || node.child("alpha_u").is_some()
    {
        let au = float_texture(node, "alpha_u", DEFAULT_ALPHA)?;
        let av = float_texture(node, "alpha_v", DEFAULT_ALPHA)?;
        Ok((dist, au, av))
    } else {
        let a = float_texture(node, "alpha", DEFAULT_ALPHA)?;
        Ok((dist, a.clone(), a))
    }
}

/// A conductor's complex index: `material` (a named metal or "none"), or `eta` and `k`.
fn conductor_ior(node: &Node) -> Result<Option<ConductorIor>, SceneError> {
    let ext_ior = ior(node, "ext_eta", "air")?;
    if node.props.contains("eta") || node.props.contains("k") {
        let eta = spectrum(
            node,
            "eta",
            SpectrumKind::Unbounded,
            Spectrum::Constant(0.0),
        )?;
        let k = spectrum(node, "k", SpectrumKind::Unbounded, Spectrum::Constant(1.0))?;
        return Ok(Some(ConductorIor { eta, k, ext_ior }));
    }
    let name = node.props.get_string("material", "none")?;
    if name == "none" {
        return Ok(None);
    }
    let (eta, k) = named_ior::conductor_nk(&name).ok_or_else(|| {
        SceneError::at(
            node.props.location("material").unwrap_or(&node.loc),
            format!(
                "unknown conductor material '{name}' (known: none, {})",
                named_ior::conductor_names().join(", ")
            ),
        )
    })?;
    Ok(Some(ConductorIor { eta, k, ext_ior }))
}

/// A colour parameter: a nested or referenced texture named `name`, or a value.
pub(crate) fn spectrum_texture(
    node: &Node,
    name: &str,
    kind: SpectrumKind,
    default: Spectrum,
) -> Result<SpectrumTexture, SceneError> {
    if let Some(tex) = node.child(name).filter(|c| c.tag == Tag::Texture) {
        return texture(tex, kind);
    }
    Ok(SpectrumTexture::Constant(spectrum(
        node, name, kind, default,
    )?))
}

fn uv_transform(node: &Node) -> Result<Mat3, SceneError> {
    let t = node
        .props
        .get_transform("to_uv", crate::math::Transform::IDENTITY)?;
    // Mitsuba's to_uv acts on (u, v, 1) homogeneous coordinates: keep the 2D affine part.
    let m = t.m;
    Ok(Mat3::from_cols(
        Vec3::new(m.x_axis.x, m.x_axis.y, 0.0),
        Vec3::new(m.y_axis.x, m.y_axis.y, 0.0),
        Vec3::new(m.w_axis.x, m.w_axis.y, 1.0),
    ))
}

fn texture(tex: &Node, kind: SpectrumKind) -> Result<SpectrumTexture, SceneError> {
    if super::scales::is_scales(&tex.plugin) {
        return super::scales::scales_spectrum(tex, kind);
    }
    match tex.plugin.as_str() {
        "checkerboard" => Ok(SpectrumTexture::Checkerboard {
            color0: spectrum(tex, "color0", kind, Spectrum::Constant(0.4))?,
            color1: spectrum(tex, "color1", kind, Spectrum::Constant(0.2))?,
            to_uv: uv_transform(tex)?,
        }),
        "bitmap" => Ok(SpectrumTexture::Bitmap(bitmap(tex)?)),
        other => Err(SceneError::at(
            &tex.loc,
            format!(
                "texture '{other}' is not supported by ophis (supported: bitmap, checkerboard, \
                 scales, per_scale)"
            ),
        )),
    }
}

/// A scalar parameter given as a float or as a nested texture.
pub(super) fn float_texture(
    node: &Node,
    name: &str,
    default: f32,
) -> Result<FloatTexture, SceneError> {
    if let Some(tex) = node.child(name).filter(|c| c.tag == Tag::Texture) {
        if let Some(t) = super::scales::scales_float(tex)? {
            return Ok(t);
        }
        return match tex.plugin.as_str() {
            "checkerboard" => {
                let c0 = spectrum_opt(tex, "color0", SpectrumKind::Unbounded)?
                    .map(|s| s.max_value())
                    .unwrap_or(0.4);
                let c1 = spectrum_opt(tex, "color1", SpectrumKind::Unbounded)?
                    .map(|s| s.max_value())
                    .unwrap_or(0.2);
                Ok(FloatTexture::Checkerboard {
                    color0: c0,
                    color1: c1,
                    to_uv: uv_transform(tex)?,
                })
            }
            "bitmap" => Ok(FloatTexture::Bitmap(bitmap(tex)?)),
            other => Err(SceneError::at(
                &tex.loc,
                format!("texture '{other}' is not supported for '{name}'"),
            )),
        };
    }
    let v = checked_float(
        node,
        name,
        default,
        |v| (0.0..=10.0).contains(&v),
        "between 0 and 10",
    )?;
    Ok(FloatTexture::Constant(v))
}

/// Mitsuba's `bitmap` texture (see `src/texture/bitmap.rs` for its parameters).
pub(super) fn bitmap(tex: &Node) -> Result<Arc<Bitmap>, SceneError> {
    let Some(path) = tex.props.get_path_opt("filename")? else {
        return Err(SceneError::at(&tex.loc, "bitmap needs a 'filename'"));
    };
    let loc = tex
        .props
        .location("filename")
        .cloned()
        .unwrap_or_else(|| tex.loc.clone());
    let mut image = read_image(&path).map_err(|e| SceneError::at(&loc, format!("bitmap: {e}")))?;
    let raw = tex.props.get_bool("raw", false)?;
    let is_8bit = path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        ["png", "jpg", "jpeg"]
            .iter()
            .any(|x| e.eq_ignore_ascii_case(x))
    });
    if raw && is_8bit {
        // PNG and JPEG are read as sRGB-encoded colour; raw data (normal maps) keeps the stored values.
        for c in &mut image.data {
            *c = c.map(crate::spectrum::cie::srgb_encode);
        }
    }
    let filter = tex.props.get_string("filter_type", "bilinear")?;
    let bilinear = match filter.as_str() {
        "bilinear" => true,
        "nearest" => false,
        other => {
            let l = tex.props.location("filter_type").unwrap_or(&tex.loc);
            return Err(SceneError::at(
                l,
                format!("filter_type must be 'bilinear' or 'nearest', got '{other}'"),
            ));
        }
    };
    let wrap = match tex.props.get_string("wrap_mode", "repeat")?.as_str() {
        "repeat" => Wrap::Repeat,
        "mirror" => Wrap::Mirror,
        "clamp" => Wrap::Clamp,
        other => {
            let l = tex.props.location("wrap_mode").unwrap_or(&tex.loc);
            return Err(SceneError::at(
                l,
                format!("wrap_mode must be 'repeat', 'mirror' or 'clamp', got '{other}'"),
            ));
        }
    };
    Ok(Arc::new(Bitmap::new(
        image,
        bilinear,
        wrap,
        uv_transform(tex)?,
    )))
}
