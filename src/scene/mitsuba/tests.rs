//! Reader tests: objects, references, includes, the 0.6 upgrade, errors and warnings.

use super::tests_values::{err_at, load, scene};
use super::*;
use std::path::PathBuf;

/// A fresh folder under the system temp dir, removed on drop.
pub(super) struct TempDir(pub(super) PathBuf);

impl TempDir {
    pub(super) fn new(tag: &str) -> TempDir {
        let p = std::env::temp_dir().join(format!("ophis-xml-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).unwrap();
        TempDir(p)
    }
    /// A fresh folder holding the named files, each with placeholder contents.
    pub(super) fn with_files(tag: &str, names: &[&str]) -> TempDir {
        let d = TempDir::new(tag);
        for name in names {
            d.write(name, "x");
        }
        d
    }
    pub(super) fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Same objects, names and values (locations and spellings aside).
fn same(a: &Node, b: &Node) -> bool {
    let props = |n: &Node| -> Vec<(String, Value)> {
        n.props
            .iter()
            .map(|(k, v, _)| (k.to_string(), v.clone()))
            .collect()
    };
    a.tag == b.tag
        && a.plugin == b.plugin
        && a.id == b.id
        && props(a) == props(b)
        && a.children.len() == b.children.len()
        && a.children
            .iter()
            .zip(&b.children)
            .all(|(x, y)| x.name == y.name && same(&x.node, &y.node))
}

#[test]
fn objects_children_refs_and_aliases() {
    let (root, w) = load(&scene(
        r#"<bsdf type="diffuse" id="red"><rgb name="reflectance" value="0.8 0.1 0.1"/></bsdf>
<alias id="red" as="crimson"/>
<shape type="sphere">
  <float name="radius" value="2"/>
  <ref id="red" name="bsdf"/>
  <medium type="homogeneous" name="interior" id="fog"/>
</shape>
<shape type="cube"><ref id="crimson"/><ref id="fog" name="exterior"/></shape>"#,
    ))
    .unwrap();
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(root.tag, Tag::Scene);
    let shapes: Vec<_> = root.children_with_tag(Tag::Shape).collect();
    assert_eq!(shapes.len(), 2);
    let red = root.children[0].node.clone();
    assert_eq!(red.id.as_deref(), Some("red"));
    assert!(Arc::ptr_eq(shapes[0].child("bsdf").unwrap(), &red));
    assert!(Arc::ptr_eq(&shapes[1].children[0].node, &red));
    assert_eq!(shapes[1].children[0].name, None);
    let fog = shapes[0].child("interior").unwrap();
    assert_eq!((fog.tag, fog.plugin.as_str()), (Tag::Medium, "homogeneous"));
    assert!(Arc::ptr_eq(shapes[1].child("exterior").unwrap(), fog));
    assert_eq!(shapes[0].loc.line, 4);
}

#[test]
fn spectrum_with_type_is_an_object() {
    let (root, _) = load(&scene(
        r#"<emitter type="area"><spectrum type="regular" name="radiance">
  <float name="wavelength_min" value="400"/></spectrum></emitter>"#,
    ))
    .unwrap();
    let s = root.children[0].node.child("radiance").unwrap();
    assert_eq!((s.tag, s.plugin.as_str()), (Tag::Spectrum, "regular"));
    assert_eq!(s.props.get_float("wavelength_min", 0.0).unwrap(), 400.0);
}

#[test]
fn reference_errors() {
    let unknown = "<shape type=\"sphere\">\n<ref id=\"nope\"/>\n</shape>";
    err_at(unknown, "test.xml:3:", "unknown id 'nope'");
    let twice = "<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"a\"/>";
    let e = err_at(twice, "test.xml:3:", "duplicate id 'a'");
    // The error also says where the id was first given.
    assert!(e.contains("test.xml:2:1"), "{e}");
    err_at(
        "<bsdf type=\"diffuse\" id=\"a\"/>\n<alias id=\"a\" as=\"a\"/>",
        "test.xml:",
        "duplicate id 'a'",
    );
    err_at(
        "<alias id=\"zz\" as=\"b\"/>",
        "test.xml:",
        "unknown id 'zz'",
    );
}

#[test]
fn includes_nest_relative_and_detect_cycles() {
    let d = TempDir::new("inc");
    d.write(
        "parts/a.xml",
        "<scene version=\"3.0.0\">\n<include filename=\"b.xml\"/>\n</scene>",
    );
    d.write(
        "parts/b.xml",
        "<scene version=\"3.0.0\">\n\n<bsdf type=\"diffuse\" id=\"inc\"/>\n</scene>",
    );
    let main = d.write(
        "main.xml",
        &scene("<include filename=\"parts/a.xml\"/>\n<shape type=\"sphere\"><ref id=\"inc\" name=\"bsdf\"/></shape>"),
    );
    let (root, _) = load_file(&main, &[]).unwrap();
    let bsdf = &root.children[0].node;
    assert_eq!(bsdf.id.as_deref(), Some("inc"));
    assert!(bsdf.loc.file.ends_with("parts/b.xml") && bsdf.loc.line == 3);
    assert!(Arc::ptr_eq(
        root.children[1].node.child("bsdf").unwrap(),
        bsdf
    ));

    d.write("c1.xml", &scene("<include filename=\"c2.xml\"/>"));
    d.write("c2.xml", &scene("<include filename=\"c1.xml\"/>"));
    let e = load_file(&d.0.join("c1.xml"), &[]).unwrap_err().to_string();
    assert!(
        e.contains("include cycle") && e.contains("c2.xml:2:1"),
        "{e}"
    );
    d.write("self.xml", &scene("<include filename=\"self.xml\"/>"));
    assert!(load_file(&d.0.join("self.xml"), &[]).is_err());

    let e = load_file(
        &d.write("m.xml", &scene("<include filename=\"gone.xml\"/>")),
        &[],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("m.xml:2:1") && e.contains("gone.xml"), "{e}");
}

#[test]
fn old_and_new_spellings_give_the_same_tree() {
    // The 3.0 file is the 0.6 file with each name of this table respelt (and the version).
    let respelt = [
        ("version=\"0.5.0\"", "version=\"3.0.0\""),
        ("maxDepth", "max_depth"),
        ("rrDepth", "rr_depth"),
        ("fovAxis", "fov_axis"),
        ("toWorld", "to_world"),
        ("lookAt", "lookat"),
        ("sampleCount", "sample_count"),
        ("intIOR", "int_ior"),
        ("extIOR", "ext_ior"),
        ("alphaU", "alpha_u"),
        (
            "<srgb name=\"diffuseReflectance\"",
            "<rgb name=\"diffuse_reflectance\"",
        ),
        ("specularReflectance", "specular_reflectance"),
        ("sigmaT_0", "sigma_t_0"),
    ];
    let v06 = r##"<scene version="0.5.0">
  <integrator type="path"><integer name="maxDepth" value="8"/><integer name="rrDepth" value="3"/></integrator>
  <sensor type="perspective">
    <string name="fovAxis" value="x"/>
    <transform name="toWorld"><lookAt origin="0 0 5" target="0 0 0" up="0 1 0"/></transform>
    <sampler type="independent"><integer name="sampleCount" value="4"/></sampler>
  </sensor>
  <bsdf type="roughplastic" id="m">
    <float name="intIOR" value="1.5"/><float name="extIOR" value="1"/><float name="alphaU" value="0.1"/>
    <srgb name="diffuseReflectance" value="#808080"/>
    <rgb name="specularReflectance" value="1"/>
  </bsdf>
  <medium type="heterogeneous" name="sigmaT_0"/>
</scene>"##;
    let v3 = respelt
        .iter()
        .fold(v06.to_string(), |xml, (old, new)| xml.replace(old, new));
    assert!(!v3.contains("Depth") && v3.contains("sigma_t_0"), "{v3}");
    let (a, wa) = load(v06).unwrap();
    let (b, wb) = load(&v3).unwrap();
    assert!(wa.is_empty() && wb.is_empty(), "{wa:?} {wb:?}");
    assert!(same(&a, &b), "{a:#?}\n{b:#?}");
    let bsdf = a.child("sigma_t_0").map(|_| &a.children[2].node).unwrap();
    assert_eq!(bsdf.props.original_name("int_ior"), Some("intIOR"));
}

#[test]
fn unused_parameters_are_listed_exactly() {
    let (root, _) = load(&scene(
        r#"<shape type="sphere" id="s">
  <float name="radius" value="1"/>
  <float name="raduis" value="2"/>
  <boolean name="flip_normals" value="true"/>
  <bsdf type="diffuse" name="bsdf"><rgb name="reflectance" value="0.5"/></bsdf>
</shape>
<shape type="cube"><ref id="s" name="inner"/></shape>"#,
    ))
    .unwrap();
    let s = &root.children[0].node;
    s.props.get_float("radius", 1.0).unwrap();
    s.props.get_bool_opt("flip_normals").unwrap();
    let w = check_unused(&root);
    let names: Vec<_> = w.iter().map(|w| (w.loc.line, w.message.clone())).collect();
    assert_eq!(
        names,
        vec![
            (
                4,
                "parameter 'raduis' of shape 'sphere' (id 's') was never used (did you mean 'radius'?)".to_string()
            ),
            (
                6,
                "parameter 'reflectance' of bsdf 'diffuse' was never used".to_string()
            ),
        ]
    );
}

#[test]
fn unknown_tags_and_attributes_warn_with_location() {
    let (root, w) = load(&scene(
        "<shape type=\"sphere\" colour=\"red\">\n  <flaot name=\"radius\" value=\"1\"/>\n</shape>",
    ))
    .unwrap();
    assert_eq!(root.children.len(), 1);
    assert_eq!(w.len(), 2, "{w:?}");
    assert_eq!((w[0].loc.line, w[0].loc.col), (2, 22));
    assert!(w[0].message.contains("'colour'"));
    assert_eq!((w[1].loc.line, w[1].loc.col), (3, 3));
    assert!(w[1].message.contains("<flaot>"));
}

#[test]
fn structural_errors() {
    let cases: &[(&str, &str)] = &[
        (
            "<scene>\n</scene>",
            "test.xml:1:1: <scene>: attribute 'version' is missing",
        ),
        ("<scene version=\"three\"/>", "test.xml:1:8:"),
        ("<bsdf type=\"diffuse\"/>", "expected <scene version"),
        ("", "test.xml:1:1: the file is empty"),
        ("  \n ", "the file is empty"),
        (
            "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n</scene>",
            "test.xml:3:",
        ),
        (
            "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n",
            "malformed XML",
        ),
        (
            "<scene version=\"3.0.0\"><shape type=\"sphere\" radius=1/></scene>",
            "test.xml:1:",
        ),
        (
            "<scene version=\"3.0.0\">\n<shape/>\n</scene>",
            "test.xml:2:1: <shape>: attribute 'type' is missing",
        ),
        (
            "<scene version=\"3.0.0\">\n<scene version=\"3.0.0\"/>\n</scene>",
            "test.xml:2:1:",
        ),
    ];
    for (xml, needle) in cases {
        let e = load(xml).unwrap_err().to_string();
        assert!(e.contains(needle), "{xml:?} → {e}");
    }
    // A parameter given twice, as a value and then as an object too.
    for body in [
        "<float name=\"a\" value=\"1\"/>\n<float name=\"a\" value=\"2\"/>",
        "<shape type=\"x\"><float name=\"bsdf\" value=\"1\"/>\n<bsdf type=\"d\" name=\"bsdf\"/></shape>",
    ] {
        err_at(body, "test.xml:3:1:", "given twice");
    }
}

#[test]
fn unreadable_files_are_named() {
    let d = TempDir::new("io");
    let missing = d.0.join("missing.xml");
    let e = load_file(&missing, &[]).unwrap_err().to_string();
    assert!(
        e.contains("missing.xml") && e.contains("cannot read"),
        "{e}"
    );
    let e = load_file(&d.0, &[]).unwrap_err().to_string();
    assert!(e.contains("directory"), "{e}");
    let e = load_file(&d.write("e.xml", ""), &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("e.xml:1:1") && e.contains("empty"), "{e}");
}

#[test]
fn no_input_prefix_or_depth_panics() {
    let text = scene(
        r##"<default name="r" value="2"/>
<bsdf type="diffuse" id="a"><rgb name="reflectance" value="#ff8000"/></bsdf>
<shape type="sphere"><float name="radius" value="$r"/><ref id="a" name="bsdf"/>
<transform name="to_world"><rotate x="1" angle="30"/><matrix value="1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"/></transform>
</shape>"##,
    );
    assert!(load(&text).is_ok());
    for (i, _) in text.char_indices() {
        let _ = load(&text[..i]);
    }
    let deep = format!(
        "<scene version=\"3\">{}{}</scene>",
        "<shape type=\"a\">".repeat(500),
        "</shape>".repeat(500)
    );
    let e = load(&deep).unwrap_err().to_string();
    assert!(e.contains("nested deeper"), "{e}");
}

#[test]
fn tree_is_send_and_sync() {
    fn check<T: Send + Sync>() {}
    check::<Node>();
    check::<SceneError>();
}

#[test]
fn columns_on_one_long_line_count_characters() {
    // Many elements on one line, with a multi-byte character before them.
    let shapes = "<shape type=\"é\"/>".repeat(2000);
    let xml = format!("<scene version=\"3.0.0\">{shapes}<float name=\"r\" value=\"x\"/></scene>");
    let e = load(&xml).unwrap_err();
    let col = 1 + "<scene version=\"3.0.0\">".len() + 2000 * "<shape type=\"é\"/>".chars().count();
    assert_eq!(
        e.location().unwrap().col as usize,
        col + "<float name=\"r\" ".len()
    );
}
