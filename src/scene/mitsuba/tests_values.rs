//! Reader tests: value tags, transforms and `$name` parameters.

use super::*;
use crate::math::{Transform, Vec3};

pub(super) fn load(xml: &str) -> Result<(Node, Vec<Warning>), SceneError> {
    load_str(xml, Path::new("test.xml"), &[])
}

/// A 3.0 scene whose body starts on line 2.
pub(super) fn scene(body: &str) -> String {
    format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n")
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

fn transform_of(ops: &str) -> Transform {
    let (root, w) = load(&scene(&format!("<transform name=\"t\">{ops}</transform>"))).unwrap();
    assert!(w.is_empty(), "{w:?}");
    root.props.get_transform_opt("t").unwrap().unwrap()
}

pub(super) fn err_of(body: &str) -> String {
    load(&scene(body)).unwrap_err().to_string()
}

/// The error of loading a 3.0 scene with `body`, checked to start with `at` (the place:
/// file:line:column or a prefix of it) and to mention `says`.
pub(super) fn err_at(body: &str, at: &str, says: &str) -> String {
    let e = err_of(body);
    assert!(e.starts_with(at) && e.contains(says), "{body:?}: {e}");
    e
}

#[test]
fn every_value_tag() {
    let (root, w) = load(&scene(
        r##"<float name="f" value="-1.5e1"/>
<integer name="i" value="42"/>
<boolean name="b" value="false"/>
<string name="s" value="hello, world"/>
<point name="p" value="1, 2, 3"/>
<point name="p1" value="2"/>
<vector name="v" x="1" z="3"/>
<rgb name="c" value="0.1 0.2 0.3"/>
<rgb name="c1" value="0.5"/>
<rgb name="hex" value="#ff0000"/>
<srgb name="sc" value="0.5, 0.5, 0.5"/>
<spectrum name="k" value="0.5"/>
<spectrum name="sp" value="400:0.1, 500:0.2"/>
<blackbody name="bb" temperature="3000K" scale="2"/>
<blackbody name="bb2" temperature="6500"/>"##,
    ))
    .unwrap();
    assert!(w.is_empty(), "{w:?}");
    let p = &root.props;
    assert_eq!(p.get_float("f", 0.0).unwrap(), -15.0);
    assert_eq!(p.get_int_opt("i").unwrap(), Some(42));
    assert_eq!(p.get_bool_opt("b").unwrap(), Some(false));
    assert_eq!(
        p.get_string_opt("s").unwrap().as_deref(),
        Some("hello, world")
    );
    assert_eq!(
        p.get_point_opt("p").unwrap(),
        Some(Vec3::new(1.0, 2.0, 3.0))
    );
    assert_eq!(p.get_point_opt("p1").unwrap(), Some(Vec3::splat(2.0)));
    assert_eq!(
        p.get("v").unwrap().0,
        &Value::Vector(Vec3::new(1.0, 0.0, 3.0))
    );
    assert_eq!(p.get("c").unwrap().0, &Value::Rgb([0.1, 0.2, 0.3]));
    assert_eq!(p.get("c1").unwrap().0, &Value::Rgb([0.5; 3]));
    assert_eq!(p.get("hex").unwrap().0, &Value::Rgb([1.0, 0.0, 0.0]));
    let Value::Rgb(sc) = p.get("sc").unwrap().0 else {
        panic!()
    };
    // sRGB 0.5 decodes to linear 0.21404.
    assert!((sc[0] - 0.214_041).abs() < 1e-5, "{sc:?}");
    assert_eq!(
        p.get("k").unwrap().0,
        &Value::Spectrum(SpectrumValue::Constant(0.5))
    );
    assert_eq!(
        p.get("sp").unwrap().0,
        &Value::Spectrum(SpectrumValue::Pairs(vec![(400.0, 0.1), (500.0, 0.2)]))
    );
    assert_eq!(
        p.get("bb").unwrap().0,
        &Value::Blackbody {
            temperature: 3000.0,
            scale: 2.0
        }
    );
    assert_eq!(
        p.get("bb2").unwrap().0,
        &Value::Blackbody {
            temperature: 6500.0,
            scale: 1.0
        }
    );
    assert!(p.unqueried().is_empty());
}

#[test]
fn spectrum_file_resolves_next_to_the_scene() {
    let dir = std::env::temp_dir().join(format!("ophis-xml-spd-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("data")).unwrap();
    std::fs::write(dir.join("data/eta.spd"), "400 1.5\n700 1.4\n").unwrap();
    let xml = scene(r#"<spectrum name="eta" filename="data/eta.spd"/>"#);
    let (root, _) = load_str(&xml, &dir.join("s.xml"), &[]).unwrap();
    assert_eq!(
        root.props.get("eta").unwrap().0,
        &Value::Spectrum(SpectrumValue::File(dir.join("data/eta.spd")))
    );
    let missing = scene(r#"<spectrum name="eta" filename="data/nope.spd"/>"#);
    let e = load_str(&missing, &dir.join("s.xml"), &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains(":2:") && e.contains("nope.spd"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn rotate_90_about_z_maps_x_to_y() {
    for op in [
        r#"<rotate z="1" angle="90"/>"#,
        r#"<rotate value="0 0 1" angle="90"/>"#,
    ] {
        let t = transform_of(op);
        assert!(close(t.point(Vec3::X), Vec3::Y), "{op}");
    }
}

#[test]
fn translate_then_scale_composes_in_document_order() {
    let t = transform_of(r#"<translate x="1"/><scale value="2"/>"#);
    assert!(close(t.point(Vec3::ZERO), Vec3::new(2.0, 0.0, 0.0)));
    assert!(close(t.point(Vec3::X), Vec3::new(4.0, 0.0, 0.0)));
    let t = transform_of(r#"<translate value="1 2 3"/>"#);
    assert!(close(t.point(Vec3::ZERO), Vec3::new(1.0, 2.0, 3.0)));
    let t = transform_of(r#"<scale x="2"/>"#);
    assert!(close(t.point(Vec3::ONE), Vec3::new(2.0, 1.0, 1.0)));
    let t = transform_of(r#"<scale value="1, 2, 3"/>"#);
    assert!(close(t.point(Vec3::ONE), Vec3::new(1.0, 2.0, 3.0)));
}

#[test]
fn matrices_are_row_major() {
    let t = transform_of(r#"<matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/>"#);
    assert!(close(t.point(Vec3::ZERO), Vec3::new(5.0, 6.0, 7.0)));
    let t = transform_of(r#"<matrix value="0 -1 0, 1 0 0, 0 0 1"/>"#);
    assert!(close(t.point(Vec3::X), Vec3::Y));
}

#[test]
fn lookat_matches_transform_look_at() {
    let t = transform_of(r#"<lookat origin="1, 2, 3" target="0 0 0" up="0 1 0"/>"#);
    let want = Transform::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y).unwrap();
    assert!(t.m.abs_diff_eq(want.m, 1e-6));
    // Without `up`, some perpendicular is chosen; the view direction is still right.
    let t = transform_of(r#"<lookat origin="0 0 5" target="0 0 0"/>"#);
    assert!(close(t.vector(Vec3::Z), -Vec3::Z));
    assert!(close(t.point(Vec3::ZERO), Vec3::new(0.0, 0.0, 5.0)));
}

#[test]
fn bad_transforms_are_located_errors() {
    for (ops, needle) in [
        (r#"<scale value="0"/>"#, "non-zero"),
        (r#"<rotate z="1"/>"#, "'angle' is missing"),
        (r#"<matrix value="1 2 3"/>"#, "expected 16"),
        (r#"<shear value="1"/>"#, "<shear> inside <transform>"),
        (
            r#"<lookat origin="0 0 0" target="0 1 0" up="0 2 0"/>"#,
            "parallel",
        ),
        (r#"<translate value="1 2"/>"#, "expected 3 numbers"),
    ] {
        let e = err_of(&format!("<transform name=\"t\">\n{ops}\n</transform>"));
        assert!(e.starts_with("test.xml:3:"), "{e}");
        assert!(e.contains(needle), "{e}");
    }
    let e = err_of(r#"<translate x="1"/>"#);
    assert!(e.contains("outside <transform>"), "{e}");
}

#[test]
fn params_defaults_and_defines() {
    let xml = scene(
        r#"<default name="spp" value="16"/>
<default name="name" value="bunny"/>
<integer name="n" value="$spp"/>
<string name="file" value="meshes/$name.obj"/>"#,
    );
    let (root, _) = load(&xml).unwrap();
    assert_eq!(root.props.get_int_opt("n").unwrap(), Some(16));
    assert_eq!(
        root.props.get_string_opt("file").unwrap().as_deref(),
        Some("meshes/bunny.obj")
    );
    let defines = [("spp".to_string(), "64".to_string())];
    let (root, _) = load_str(&xml, Path::new("test.xml"), &defines).unwrap();
    assert_eq!(root.props.get_int_opt("n").unwrap(), Some(64));
    let e = err_of("<float name=\"x\" value=\"1\"/>\n<integer name=\"n\" value=\"$nope\"/>");
    assert!(e.starts_with("test.xml:3:"), "{e}");
    assert!(e.contains("'$nope'"), "{e}");
}

#[test]
fn bad_numbers_name_position_element_and_expectation() {
    let e = err_of("\n\n  <float name=\"radius\" value=\"abc\"/>");
    assert_eq!(
        e,
        "test.xml:4:24: <float name=\"radius\">: attribute 'value': found 'abc'; expected a \
         decimal number"
    );
    for body in [
        r#"<float name="x" value="nan"/>"#,
        r#"<float name="x" value="inf"/>"#,
        r#"<float name="x" value="1.0 2.0"/>"#,
        r#"<integer name="x" value="1.5"/>"#,
        r#"<boolean name="x" value="yes"/>"#,
        r#"<rgb name="x" value="1 2"/>"#,
        r#"<point name="x" value="1,,2"/>"#,
        r#"<point name="x"/>"#,
        r#"<blackbody name="x" temperature="hot"/>"#,
        r#"<spectrum name="x" value="500:1, 400:1"/>"#,
        r#"<float value="1"/>"#,
    ] {
        let e = err_of(body);
        assert!(e.starts_with("test.xml:2:"), "{body}: {e}");
    }
}
