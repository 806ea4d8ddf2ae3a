//! Scene loading for the reptile-skin plugins: the `scales` texture (alias `reptileSkin`), the
//! `per_scale` adaptor, and the `bumpmap` / `normalmap` BSDF wrappers. The models and their
//! parameter tables are in `texture/scales.rs`, `texture/per_scale.rs` and `bsdf/bumpmap.rs`.

use super::materials::{build_material, float_texture};
use super::values::{checked_float, checked_int, spectrum, SpectrumKind};
use crate::bsdf::bumpmap::NormalSource;
use crate::bsdf::Material;
use crate::math::Vec2;
use crate::scene::mitsuba::{Node, SceneError, Tag, Warning};
use crate::spectrum::Spectrum;
use crate::texture::{FloatTexture, Layout, PerScale, Scales, SpectrumTexture};
use std::sync::Arc;

/// Whether a texture plugin name is the scale pattern.
pub(crate) fn is_scales(plugin: &str) -> bool {
    matches!(plugin, "scales" | "reptileSkin" | "reptile_skin")
}

/// The pattern's parameters from a `scales` / `reptileSkin` node.
pub(crate) fn scales(tex: &Node) -> Result<Scales, SceneError> {
    let d = Scales::default();
    let positive = |name: &str, default: f32| {
        checked_float(
            tex,
            name,
            default,
            |v| v > 0.0 && v <= 1e6,
            "positive (cells per unit UV)",
        )
    };
    let unit = |name: &str, default: f32| {
        checked_float(
            tex,
            name,
            default,
            |v| (0.0..=1.0).contains(&v),
            "between 0 and 1",
        )
    };
    // `gap` and the seed plugin's `line_width` (upgraded from `lineWidth`) are the same thing.
    let gap_name = if tex.props.contains("gap") {
        "gap"
    } else {
        "line_width"
    };
    let gap = checked_float(
        tex,
        gap_name,
        d.gap,
        |v| (0.0..=0.5).contains(&v),
        "between 0 and 0.5 (cells)",
    )?;
    let angle = checked_float(
        tex,
        "overlap_angle",
        90.0,
        |v| v.is_finite(),
        "a finite angle in degrees",
    )?
    .to_radians();
    let tilt = checked_float(
        tex,
        "tilt_degrees",
        0.0,
        |v| (0.0..=45.0).contains(&v),
        "between 0 and 45 degrees",
    )?;
    Ok(Scales {
        scale_u: positive("scale_u", d.scale_u)?,
        scale_v: positive("scale_v", d.scale_v)?,
        irregularity: unit("irregularity", d.irregularity)?,
        gap,
        dome: unit("dome", d.dome)?,
        overlap: unit("overlap", d.overlap)?,
        overlap_dir: Vec2::new(angle.cos(), angle.sin()),
        tilt: tilt.to_radians(),
        seed: checked_int(tex, "seed", 0, 0, u32::MAX as i64)? as u32,
        layout: {
            let name = tex.props.get_string("layout", "hex")?;
            Layout::from_name(&name).ok_or_else(|| {
                SceneError::at(
                    tex.props.location("layout").unwrap_or(&tex.loc),
                    format!("layout must be hex, rows or head; got '{name}'"),
                )
            })?
        },
    })
}

/// `scales` as a colour texture.
pub(crate) fn scales_spectrum(
    tex: &Node,
    kind: SpectrumKind,
) -> Result<SpectrumTexture, SceneError> {
    Ok(SpectrumTexture::Scales {
        cells: Arc::new(scales(tex)?),
        color0: spectrum(tex, "color0", kind, Spectrum::Constant(0.4))?,
        color1: spectrum(tex, "color1", kind, Spectrum::Constant(0.1))?,
    })
}

/// `scales` (height) or `per_scale` as a float texture; `None` for other plugins.
pub(crate) fn scales_float(tex: &Node) -> Result<Option<FloatTexture>, SceneError> {
    if is_scales(&tex.plugin) {
        // Colours mean nothing to a height; mark them read so they do not warn as misspelt.
        tex.props.mark_queried("color0");
        tex.props.mark_queried("color1");
        return Ok(Some(FloatTexture::Scales(Arc::new(scales(tex)?))));
    }
    if tex.plugin != "per_scale" {
        return Ok(None);
    }
    let inner: Vec<&Arc<Node>> = tex.children_with_tag(Tag::Texture).collect();
    let cells = match inner.as_slice() {
        [c] if is_scales(&c.plugin) => scales(c)?,
        _ => {
            return Err(SceneError::at(
                &tex.loc,
                "per_scale needs exactly one nested (or referenced) 'scales' texture",
            ))
        }
    };
    let finite = |name: &str, default: f32| {
        checked_float(tex, name, default, |v| v.is_finite(), "a finite number")
    };
    let (lo, hi) = if tex.props.contains("mean") || tex.props.contains("spread") {
        let mean = finite("mean", 0.5)?;
        let spread = checked_float(tex, "spread", 0.0, |v| v >= 0.0, "non-negative")?;
        (mean - spread, mean + spread)
    } else {
        (finite("min", 0.0)?, finite("max", 1.0)?)
    };
    Ok(Some(FloatTexture::PerScale(PerScale {
        cells: Arc::new(cells),
        lo,
        hi,
    })))
}

/// The single nested BSDF of a wrapper (Mitsuba's default diffuse when absent).
fn nested_bsdf(node: &Node, warnings: &mut Vec<Warning>) -> Result<Material, SceneError> {
    let inner: Vec<&Arc<Node>> = node.children_with_tag(Tag::Bsdf).collect();
    match inner.as_slice() {
        [] => Ok(Material::default_diffuse()),
        [b] => build_material(b, warnings),
        _ => Err(SceneError::at(
            &node.loc,
            format!(
                "{} takes one nested BSDF, found {}",
                node.describe(),
                inner.len()
            ),
        )),
    }
}

/// `bumpmap`: a nested float texture (the height), `scale`, and a nested BSDF.
pub(crate) fn bumpmap(node: &Node, warnings: &mut Vec<Warning>) -> Result<Material, SceneError> {
    let textures: Vec<&Arc<Node>> = node.children_with_tag(Tag::Texture).collect();
    let [tex] = textures.as_slice() else {
        return Err(SceneError::at(
            &node.loc,
            format!(
                "bumpmap needs exactly one nested height texture, found {}",
                textures.len()
            ),
        ));
    };
    let height = match scales_float(tex)? {
        Some(t) => t,
        None => {
            // Any other float texture the builder knows, looked up through the child's name.
            let name = node
                .children
                .iter()
                .find(|c| Arc::ptr_eq(&c.node, tex))
                .and_then(|c| c.name.clone())
                .unwrap_or_default();
            float_texture(node, &name, 0.0)?
        }
    };
    let scale = checked_float(node, "scale", 1.0, |v| v.is_finite(), "a finite number")?;
    Ok(Material::BumpMap {
        height,
        scale,
        inner: Box::new(nested_bsdf(node, warnings)?),
    })
}

/// `normalmap`: a nested `bitmap` (tangent-space normal map) or `scales` texture, and a BSDF.
pub(crate) fn normalmap(node: &Node, warnings: &mut Vec<Warning>) -> Result<Material, SceneError> {
    let textures: Vec<&Arc<Node>> = node.children_with_tag(Tag::Texture).collect();
    let source = match textures.as_slice() {
        [t] if is_scales(&t.plugin) => NormalSource::Scales(Arc::new(scales(t)?)),
        [t] if t.plugin == "bitmap" => NormalSource::Bitmap(super::materials::bitmap(t)?),
        [t] => {
            return Err(SceneError::at(
                &t.loc,
                format!(
                    "normalmap: texture '{}' cannot supply normals (use a 'bitmap' or a 'scales' \
                     texture)",
                    t.plugin
                ),
            ))
        }
        _ => {
            return Err(SceneError::at(
                &node.loc,
                "normalmap needs exactly one nested normal texture",
            ))
        }
    };
    let strength = checked_float(node, "strength", 1.0, |v| v.is_finite(), "a finite number")?;
    Ok(Material::NormalMap {
        source,
        strength,
        inner: Box::new(nested_bsdf(node, warnings)?),
    })
}
