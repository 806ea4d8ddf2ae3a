//! Reader tests: forward references, `<path>` folders, where plugin file names are looked up,
//! UTF-16 files, and warnings kept when loading fails.

use super::tests::TempDir;
use super::tests_values::{err_at, load, scene};
use super::*;

#[test]
fn a_reference_may_precede_its_object() {
    let (root, w) = load(&scene(
        r#"<shape type="sphere"><ref id="later" name="bsdf"/></shape>
<shape type="cube"><ref id="later"/></shape>
<bsdf type="twosided" id="later"><ref id="inner"/></bsdf>
<bsdf type="diffuse" id="inner"/>"#,
    ))
    .unwrap();
    assert!(w.is_empty(), "{w:?}");
    let shapes: Vec<_> = root.children_with_tag(Tag::Shape).collect();
    let later = shapes[0].child("bsdf").unwrap();
    assert_eq!(later.id.as_deref(), Some("later"));
    assert!(Arc::ptr_eq(&shapes[1].children[0].node, later));
    assert!(Arc::ptr_eq(&root.children[2].node, later));
    assert_eq!(later.children[0].node.plugin, "diffuse");
    assert!(Arc::ptr_eq(&later.children[0].node, &root.children[3].node));
}

#[test]
fn reference_cycles_and_unknown_ids_are_located_errors() {
    let cycle = "<bsdf type=\"twosided\" id=\"a\">\n<ref id=\"b\"/></bsdf>\n\
                 <bsdf type=\"twosided\" id=\"b\">\n<ref id=\"a\"/></bsdf>";
    err_at(cycle, "test.xml:", "reference cycle");
    let itself = "<bsdf type=\"twosided\" id=\"s\">\n<ref id=\"s\"/></bsdf>";
    err_at(itself, "test.xml:3:1", "cycle");
    let gone = "<shape type=\"sphere\">\n  <ref id=\"gone\"/></shape>";
    err_at(gone, "test.xml:3:3", "unknown id 'gone'");
}

#[test]
fn a_long_chain_of_references_does_not_overflow() {
    let n = 20_000;
    let mut body = String::new();
    for i in 0..n {
        body.push_str(&format!(
            "<texture type=\"t\" id=\"t{i}\"><ref id=\"t{}\"/></texture>\n",
            i + 1
        ));
    }
    body.push_str(&format!("<texture type=\"t\" id=\"t{n}\"/>"));
    let (root, _) = load(&scene(&body)).unwrap();
    assert_eq!(root.children.len(), n + 1);
}

/// The resolved `filename` of the scene's `i`-th object.
fn filename(root: &Node, i: usize) -> std::path::PathBuf {
    let props = &root.children[i].node.props;
    props.get_path_opt("filename").unwrap().unwrap()
}

#[test]
fn path_folders_are_searched_first_and_must_exist() {
    let d = TempDir::with_files("path", &["meshes/a.ply", "textures/t.png", "other/t.png"]);
    let main = d.write(
        "scene/main.xml",
        &scene(
            "<path value=\"../meshes\"/>\n<path value=\"../textures\"/>\n\
             <shape type=\"ply\"><string name=\"filename\" value=\"a.ply\"/></shape>\n\
             <texture type=\"bitmap\" id=\"t\"><string name=\"filename\" value=\"t.png\"/></texture>\n\
             <texture type=\"bitmap\" id=\"u\"><string name=\"filename\" value=\"u.png\"/></texture>",
        ),
    );
    let (root, w) = load_file(&main, &[]).unwrap();
    assert!(w.is_empty(), "{w:?}");
    let path = |i: usize| filename(&root, i);
    assert_eq!(path(0), d.0.join("scene/../meshes/a.ply"));
    assert_eq!(path(1), d.0.join("scene/../textures/t.png"));
    // Found nowhere: named next to the declaring file, for the message.
    assert_eq!(path(2), d.0.join("scene/u.png"));

    let bad = d.write("scene/bad.xml", &scene("<path value=\"nowhere\"/>"));
    let e = load_file(&bad, &[]).unwrap_err().to_string();
    assert!(
        e.contains("bad.xml:2:") && e.contains("not a folder"),
        "{e}"
    );
    let nested = d.write(
        "scene/nested.xml",
        &scene("<shape type=\"sphere\"><path value=\".\"/></shape>"),
    );
    let e = load_file(&nested, &[]).unwrap_err().to_string();
    assert!(e.contains("directly inside <scene>"), "{e}");
}

#[test]
fn file_names_in_included_files_resolve_against_the_scene_folder() {
    // Mitsuba finds the mesh next to the scene, not next to the included file, and ophis
    // falls back to the included file's folder only where the scene's has nothing.
    let meshes = ["mesh.ply", "parts/mesh.ply", "parts/only-here.ply"];
    let d = TempDir::with_files("incpath", &meshes);
    d.write(
        "parts/objects.xml",
        &scene(
            "<shape type=\"ply\" id=\"a\"><string name=\"filename\" value=\"mesh.ply\"/></shape>\n\
             <shape type=\"ply\" id=\"b\"><string name=\"filename\" value=\"only-here.ply\"/></shape>\n\
             <include filename=\"more.xml\"/>",
        ),
    );
    // A nested include is looked up next to its includer.
    d.write(
        "parts/more.xml",
        &scene(
            "<shape type=\"ply\" id=\"c\"><string name=\"filename\" value=\"mesh.ply\"/></shape>",
        ),
    );
    let main = d.write(
        "main.xml",
        &scene("<include filename=\"parts/objects.xml\"/>"),
    );
    let (root, _) = load_file(&main, &[]).unwrap();
    let path = |i: usize| filename(&root, i);
    assert_eq!(path(0), d.0.join("mesh.ply"));
    assert_eq!(path(1), d.0.join("parts/only-here.ply"));
    assert_eq!(path(2), d.0.join("mesh.ply"));
}

#[test]
fn utf16_scene_with_a_byte_order_mark_loads() {
    let d = TempDir::new("utf16");
    let text = "<?xml version=\"1.0\" encoding=\"UTF-16\"?>\n<scene version=\"3.0.0\">\n\
                <bsdf type=\"diffuse\" id=\"é\"/>\n</scene>\n";
    let bytes: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(text.encode_utf16().flat_map(u16::to_le_bytes))
        .collect();
    let p = d.0.join("utf16.xml");
    std::fs::write(&p, bytes).unwrap();
    let (root, w) = load_file(&p, &[]).unwrap();
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(root.children[0].node.id.as_deref(), Some("é"));
    assert_eq!(root.children[0].node.loc.line, 3);
}

#[test]
fn warnings_before_an_error_are_kept() {
    let mut warnings = Vec::new();
    let r = load_str_into(
        &scene("<shape type=\"sphere\" colour=\"red\"/>\n<shape type=\"sphere\"><ref id=\"x\"/></shape>"),
        Path::new("test.xml"),
        &[],
        &mut warnings,
    );
    assert!(r.is_err());
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].message.contains("colour"), "{warnings:?}");
}

#[test]
fn version_0_files_get_mitsubas_per_object_upgrades() {
    let v06 = |body: &str| format!("<scene version=\"0.6.0\">\n{body}\n</scene>\n");
    let (root, w) = load(&v06(
        r#"<bsdf type="diffuse"><rgb name="diffuseReflectance" value="0.2"/></bsdf>
<bsdf type="diffuse"><texture type="checkerboard" name="diffuseReflectance"/></bsdf>
<bsdf type="plastic"><rgb name="diffuseReflectance" value="0.2"/></bsdf>
<texture type="bitmap"><float name="uscale" value="4"/><float name="vscale" value="2"/>
  <float name="uoffset" value="0.5"/></texture>"#,
    ))
    .unwrap();
    assert!(w.is_empty(), "{w:?}");
    let [a, b, c, t] = [0, 1, 2, 3].map(|i| &root.children[i].node);
    assert!(a.props.contains("reflectance") && !a.props.contains("diffuse_reflectance"));
    assert_eq!(
        a.props.original_name("reflectance"),
        Some("diffuseReflectance")
    );
    assert!(b.child("reflectance").is_some());
    // Only diffuse renames it (plastic has a diffuse_reflectance of its own).
    assert!(c.props.contains("diffuse_reflectance"));
    // to_uv = scale(4, 2) · translate(0.5, 0): (0, 0) ↦ (2, 0), (1, 1) ↦ (6, 2).
    let to_uv = t.props.get_transform_opt("to_uv").unwrap().unwrap();
    assert!(
        (to_uv.point(crate::math::Vec3::ZERO) - crate::math::Vec3::new(2.0, 0.0, 0.0)).length()
            < 1e-6
    );
    assert!(
        (to_uv.point(crate::math::Vec3::new(1.0, 1.0, 0.0))
            - crate::math::Vec3::new(6.0, 2.0, 0.0))
        .length()
            < 1e-6
    );
    assert!(!t.props.contains("uscale"));
    // 3.x files keep the names as written; a zero scale and a second to_uv are errors.
    let (root, _) = load(&scene(
        r#"<texture type="bitmap"><float name="uscale" value="4"/></texture>"#,
    ))
    .unwrap();
    assert!(root.children[0].node.props.contains("uscale"));
    let e = load(&v06(r#"<texture type="bitmap">
<float name="uscale" value="0"/></texture>"#))
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("test.xml:3:") && e.contains("zero"), "{e}");
    let e = load(&v06(
        r#"<texture type="bitmap"><float name="uscale" value="2"/>
<transform name="toUV"><scale value="2"/></transform></texture>"#,
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("'to_uv'") && e.contains("twice"), "{e}");
}
