//! The reptile-skin scenes load without warnings; the seed's `reptileSkin` (0.6 dialect) loads;
//! bad parameters of `scales`, `per_scale`, `bumpmap`, `normalmap`, `torus` and `snake` are
//! errors naming file:line:column.

use ophis::bsdf::Material;
use ophis::scene::build::{load_scene, load_scene_str, LoadOptions};
use std::path::Path;

#[test]
fn scales_scenes_load_without_warnings() {
    for name in ["scales-sphere", "scales-torus", "scales-snake"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.xml"));
        let opts = LoadOptions {
            defines: vec![("res".into(), "16".into())],
            ..Default::default()
        };
        let (scene, warnings) = load_scene(&path, &opts).unwrap_or_else(|e| panic!("{e}"));
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        assert!(scene
            .materials
            .iter()
            .any(|m| matches!(m, Material::BumpMap { .. })));
    }
}

fn wrap(body: &str, version: &str) -> String {
    format!("<scene version=\"{version}\">\n{body}\n</scene>")
}

fn error(xml: &str) -> String {
    match load_scene_str(xml, Path::new("test.xml"), &LoadOptions::default()) {
        Ok(_) => panic!("expected an error for:\n{xml}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn seed_reptile_skin_loads_with_its_names() {
    let xml = wrap(
        r#"<shape type="sphere"><bsdf type="diffuse">
  <texture type="reptileSkin" name="reflectance">
    <rgb name="color0" value="0.5, 0.4, 0.3"/><rgb name="color1" value="0.1"/>
    <float name="lineWidth" value="0.05"/>
  </texture></bsdf></shape>
<emitter type="constant"/>"#,
        "0.6.0",
    );
    let (_, warnings) =
        load_scene_str(&xml, Path::new("test.xml"), &LoadOptions::default()).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
}

#[test]
fn bad_parameters_are_errors_with_locations() {
    let cases = [
        (
            r#"<shape type="sphere"><bsdf type="bumpmap">
<texture type="scales"><float name="irregularity" value="2"/></texture></bsdf></shape>"#,
            "test.xml:3:",
            "irregularity",
        ),
        (
            r#"<shape type="sphere"><bsdf type="bumpmap"><float name="scale" value="1"/>
</bsdf></shape>"#,
            "test.xml:2:",
            "height texture",
        ),
        (
            r#"<shape type="sphere"><bsdf type="normalmap">
<texture type="checkerboard"/></bsdf></shape>"#,
            "test.xml:3:",
            "bitmap",
        ),
        (
            r#"<shape type="torus">
<float name="major_radius" value="1"/><float name="minor_radius" value="2"/></shape>"#,
            "test.xml:3:",
            "minor_radius",
        ),
        (
            r#"<shape type="snake"><float name="length" value="-1"/></shape>"#,
            "test.xml:2:",
            "length",
        ),
        (
            r#"<shape type="sphere"><bsdf type="diffuse">
<texture type="per_scale" name="reflectance"/></bsdf></shape>"#,
            "test.xml:3:",
            "cannot be used as a colour",
        ),
    ];
    for (body, at, what) in cases {
        let e = error(&wrap(body, "3.0.0"));
        assert!(e.contains(at) && e.contains(what), "{e}");
    }
}
