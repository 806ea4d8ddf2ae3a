//! Emitters: each plugin (`point`, `directional`, `constant`, `envmap`, `sunsky`, `sun`, `sky`,
//! `area`) declares and loads itself in its file under `light/`; here they join the scene.

use super::Builder;
use crate::light::Light;
use crate::plugin::{registry, Node, SceneError};

pub(crate) fn add_emitter(b: &mut Builder, node: &Node) -> Result<(), SceneError> {
    b.lights.extend(registry::emitter(node, None, b.warnings)?);
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
    let mut warnings = Vec::new();
    let mut lights = registry::emitter(node, Some(shape_index), &mut warnings)?;
    match lights.pop() {
        Some(l) if lights.is_empty() => Ok(l),
        _ => Err(SceneError::at(&node.loc, "an 'area' emitter is one light")),
    }
}

#[cfg(test)]
mod tests {
    use crate::light::infinite::InfiniteLight;
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
