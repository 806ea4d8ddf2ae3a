//! Emitters: Mitsuba's `point`, `directional`, `constant`, `envmap` at the top level, and `area`
//! nested in a shape. RGB and plain-number radiances are D65 emissions, as in Mitsuba's spectral
//! variants.

use super::values::{checked_float, spectrum, SpectrumKind};
use super::Builder;
use crate::image_io::read_image;
use crate::light::{AreaLight, ConstantLight, DirectionalLight, EnvMapLight, Light, PointLight};
use crate::math::{Transform, Vec3};
use crate::scene::mitsuba::{Node, SceneError, Warning};
use crate::spectrum::Spectrum;

fn white() -> Spectrum {
    Spectrum::rgb_illuminant([1.0; 3])
}

pub(crate) fn add_emitter(
    b: &mut Builder,
    node: &Node,
    warnings: &mut Vec<Warning>,
) -> Result<(), SceneError> {
    let light = match node.plugin.as_str() {
        "point" => {
            let intensity = spectrum(node, "intensity", SpectrumKind::Illuminant, white())?;
            let pos = match node.props.get_point_opt("position")? {
                Some(p) => p,
                None => node
                    .props
                    .get_transform("to_world", Transform::IDENTITY)?
                    .point(Vec3::ZERO),
            };
            Light::Point(PointLight::new(pos, intensity))
        }
        "directional" => {
            let irradiance = spectrum(node, "irradiance", SpectrumKind::Illuminant, white())?;
            let dir = match node.props.get_vector_opt("direction")? {
                Some(d) => d,
                None => node
                    .props
                    .get_transform("to_world", Transform::IDENTITY)?
                    .vector(Vec3::Z),
            };
            let l = DirectionalLight::new(dir, irradiance).ok_or_else(|| {
                SceneError::at(
                    &node.loc,
                    format!("{}: direction must be a non-zero vector", node.describe()),
                )
            })?;
            Light::Directional(l)
        }
        "constant" => Light::Constant(ConstantLight::new(spectrum(
            node,
            "radiance",
            SpectrumKind::Illuminant,
            white(),
        )?)),
        "envmap" => {
            let Some(path) = node.props.get_path_opt("filename")? else {
                return Err(SceneError::at(
                    &node.loc,
                    format!("{} needs a 'filename'", node.describe()),
                ));
            };
            let loc = node
                .props
                .location("filename")
                .cloned()
                .unwrap_or_else(|| node.loc.clone());
            let image = read_image(&path)
                .map_err(|e| SceneError::at(&loc, format!("{}: {e}", node.describe())))?;
            let scale = checked_float(
                node,
                "scale",
                1.0,
                |v| v >= 0.0 && v.is_finite(),
                "a non-negative number",
            )?;
            let to_world = node.props.get_transform("to_world", Transform::IDENTITY)?;
            Light::EnvMap(
                EnvMapLight::new(image, scale, to_world)
                    .map_err(|e| SceneError::at(&loc, format!("{}: {e}", node.describe())))?,
            )
        }
        "area" => {
            return Err(SceneError::at(
                &node.loc,
                "an 'area' emitter must be nested inside a shape",
            ));
        }
        other => {
            warnings.push(Warning {
                loc: node.loc.clone(),
                message: format!("emitter '{other}' is not supported by ophis and is ignored"),
            });
            return Ok(());
        }
    };
    b.lights.push(light);
    Ok(())
}

/// The area light of shape `shape_index`.
pub(crate) fn area_light(node: &Node, shape_index: u32) -> Result<Light, SceneError> {
    if node.plugin != "area" {
        return Err(SceneError::at(
            &node.loc,
            format!(
                "only 'area' emitters can be attached to a shape, found '{}'",
                node.plugin
            ),
        ));
    }
    let radiance = spectrum(node, "radiance", SpectrumKind::Illuminant, white())?;
    Ok(Light::Area(AreaLight::new(shape_index, radiance)))
}
