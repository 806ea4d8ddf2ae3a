//! Emitters: Mitsuba's `point`, `directional`, `constant`, `envmap` and the 0.6 daylight
//! plugins `sunsky` (two lights: sun and sky), `sun` and `sky` at the top level, and `area` nested
//! in a shape. RGB and plain-number radiances are D65 emissions, as in Mitsuba's spectral
//! variants.

use super::values::{checked_float, checked_int, spectrum, SpectrumKind};
use super::Builder;
use crate::image_io::read_image;
use crate::light::sunsky::{DateTime, SunPlacement, SunSky, SunSkyParams};
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
        "sunsky" | "sun" | "sky" => {
            b.lights.extend(daylight(node, warnings)?);
            return Ok(());
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

/// A float in `lo..=hi`.
fn ranged(node: &Node, name: &str, default: f32, lo: f32, hi: f32) -> Result<f32, SceneError> {
    checked_float(
        node,
        name,
        default,
        |v| (lo..=hi).contains(&v),
        &format!("between {lo} and {hi}"),
    )
}

/// The lights of a `sunsky` (sun then sky), `sun` or `sky` emitter.
fn daylight(node: &Node, warnings: &mut Vec<Warning>) -> Result<Vec<Light>, SceneError> {
    let kind = node.plugin.as_str();
    let (with_sun, with_sky) = (kind != "sky", kind != "sun");
    let turbidity = ranged(node, "turbidity", 3.0, 1.7, 10.0)?;
    let placement = match node.props.get_vector_opt("sun_direction")? {
        Some(d) => SunPlacement::Direction(d),
        None => {
            let int = |name, default, lo, hi| checked_int(node, name, default, lo, hi);
            SunPlacement::Time {
                latitude: ranged(node, "latitude", 35.6894, -90.0, 90.0)? as f64,
                longitude: ranged(node, "longitude", 139.6917, -360.0, 360.0)? as f64,
                time: DateTime {
                    year: int("year", 2010, 1000, 3000)? as i32,
                    month: int("month", 7, 1, 12)? as u32,
                    day: int("day", 10, 1, 31)? as u32,
                    hour: ranged(node, "hour", 15.0, 0.0, 24.0)? as f64,
                    minute: ranged(node, "minute", 0.0, 0.0, 60.0)? as f64,
                    second: ranged(node, "second", 0.0, 0.0, 60.0)? as f64,
                    timezone: ranged(node, "timezone", 9.0, -14.0, 14.0)? as f64,
                },
            }
        }
    };
    let scale = |name| ranged(node, name, 1.0, 0.0, f32::MAX);
    let (sun_scale, sky_scale) = match kind {
        "sunsky" => (scale("sun_scale")?, scale("sky_scale")?),
        _ => (scale("scale")?, scale("scale")?),
    };
    let sun_radius_scale = if with_sun {
        scale("sun_radius_scale")?
    } else {
        1.0
    };
    let to_world = node.props.get_transform("to_world", Transform::IDENTITY)?;
    if let Some(loc) = node.props.location("albedo").cloned() {
        node.props.mark_queried("albedo");
        warnings.push(Warning {
            loc,
            message: format!(
                "{}: 'albedo' is ignored (Preetham's sky has no ground term)",
                node.describe()
            ),
        });
    }
    let params = SunSkyParams {
        turbidity,
        placement,
        sun_scale,
        sky_scale,
        sun_radius_scale,
        to_world,
    };
    let parts = SunSky::new(&params, with_sun, with_sky).ok_or_else(|| {
        let loc = node.props.location("sun_direction").unwrap_or(&node.loc);
        SceneError::at(
            loc,
            format!(
                "{}: sun_direction must be a non-zero vector",
                node.describe()
            ),
        )
    })?;
    if !parts.sun_is_up() {
        warnings.push(Warning {
            loc: node.loc.clone(),
            message: format!(
                "{}: the sun is below the horizon (elevation {:.1}°); sun and sky are black",
                node.describe(),
                parts.sun_local.y.clamp(-1.0, 1.0).asin().to_degrees()
            ),
        });
    }
    let mut lights = Vec::new();
    lights.extend(parts.sun.map(Light::Sun));
    lights.extend(parts.sky.map(Light::Sky));
    Ok(lights)
}

#[cfg(test)]
mod tests {
    use crate::light::Light;
    use crate::scene::build::{load_scene, load_scene_str, LoadOptions};
    use crate::scene::mitsuba::Warning;
    use std::path::Path;

    fn load(body: &str, version: &str) -> Result<(Vec<Light>, Vec<Warning>), String> {
        let xml = format!("<scene version=\"{version}\">\n{body}\n</scene>");
        load_scene_str(&xml, Path::new("test.xml"), &LoadOptions::default())
            .map(|(s, w)| (s.lights, w))
            .map_err(|e| e.to_string())
    }

    #[test]
    fn sunsky_is_a_sun_and_a_sky_and_the_parts_load_alone() {
        let (l, w) = load("<emitter type=\"sunsky\"/>", "3.0.0").unwrap();
        assert!(matches!(l[..], [Light::Sun(_), Light::Sky(_)]), "{l:?}");
        // Mitsuba's default time and place (Tokyo, 10 July 2010, 15:00) have the sun up.
        assert!(w.iter().all(|w| !w.message.contains("horizon")), "{w:?}");
        let (l, _) = load("<emitter type=\"sun\"/>", "3.0.0").unwrap();
        assert!(matches!(l[..], [Light::Sun(_)]));
        let (l, _) = load(
            "<emitter type=\"sky\"><float name=\"scale\" value=\"2\"/></emitter>",
            "3.0.0",
        )
        .unwrap();
        assert!(matches!(l[..], [Light::Sky(_)]));
    }

    #[test]
    fn mitsuba_06_spellings_and_warnings() {
        let body = "<emitter type=\"sunsky\">\n<vector name=\"sunDirection\" x=\"0\" y=\"-1\" z=\"0.2\"/>\n\
                    <float name=\"sunRadiusScale\" value=\"0\"/><float name=\"skyScale\" value=\"2\"/>\n\
                    <spectrum name=\"albedo\" value=\"0.2\"/></emitter>";
        let (l, w) = load(body, "0.6.0").unwrap();
        let Light::Sun(sun) = &l[0] else {
            panic!("{l:?}")
        };
        assert!(sun.is_delta());
        assert!(
            w.iter().any(|w| w.message.contains("below the horizon")),
            "{w:?}"
        );
        assert!(w.iter().any(|w| w.message.contains("albedo")), "{w:?}");
        assert!(w.iter().all(|w| !w.message.contains("unused")), "{w:?}");
    }

    #[test]
    fn bad_parameters_name_file_line_and_column() {
        for (body, what) in [
            ("<emitter type=\"sunsky\">\n<float name=\"turbidity\" value=\"20\"/></emitter>", "turbidity"),
            ("<emitter type=\"sky\">\n<integer name=\"month\" value=\"13\"/></emitter>", "month"),
            ("<emitter type=\"sun\">\n<float name=\"latitude\" value=\"91\"/></emitter>", "latitude"),
            ("<emitter type=\"sunsky\">\n<float name=\"sun_scale\" value=\"-1\"/></emitter>", "sun_scale"),
            ("<emitter type=\"sunsky\">\n<vector name=\"sun_direction\" x=\"0\" y=\"0\" z=\"0\"/></emitter>", "sun_direction"),
        ] {
            let e = load(body, "3.0.0").unwrap_err();
            assert!(e.contains("test.xml:3:") && e.contains(what), "{e}");
        }
    }

    #[test]
    fn daylight_scene_loads() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/daylight.xml");
        let (scene, w) = load_scene(&path, &LoadOptions::default()).unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(scene.infinite_lights.len(), 2);
        let Light::Sky(sky) = &scene.lights[scene.infinite_lights[1] as usize] else {
            panic!()
        };
        // Zaragoza, 21 June, 09:00 CEST: the sun ≈ 25° up in the east-north-east.
        let s = sky.model().unwrap().sun;
        let elevation = s.y.asin().to_degrees();
        assert!(
            (20.0..30.0).contains(&elevation) && s.x > 0.85 && s.z < 0.0,
            "{s}"
        );
    }
}
