//! The Mitsuba-style scenes of `tests/data/mitsuba/` (written for ophis, in the 0.4, 0.5,
//! 0.6, 2.0 and 3.x dialects; `tools/compare_mitsuba.py` renders them against Mitsuba 3) load
//! with exactly the warnings they should, and what they exercise arrives in the scene: meshes
//! from serialized files, PLY and OBJ texture coordinates, instances, cylinders, the direct and
//! moment integrators, UTF-16 text. Plus the hostile inputs of the same issue.

use ophis::image_io::read_image;
use ophis::math::{Ray, Vec2, Vec3};
use ophis::scene::build::{load_scene, load_scene_str, LoadOptions};
use ophis::scene::{IntegratorKind, Scene};
use ophis::shape::Shape;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mitsuba")
        .join(name)
}

/// Loads a scene; returns it and its warnings' messages.
fn load(name: &str) -> (Scene, Vec<String>) {
    let (s, w) =
        load_scene(&data(name), &LoadOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
    (s, w.into_iter().map(|w| w.to_string()).collect())
}

fn meshes(s: &Scene) -> Vec<&ophis::shape::TriangleMesh> {
    s.shapes
        .iter()
        .filter_map(|s| match s {
            Shape::Mesh(m) => Some(m),
            _ => None,
        })
        .collect()
}

#[test]
fn every_scene_loads_with_only_its_expected_warnings() {
    let expected: &[(&str, &[&str])] = &[
        ("cbox_v06.xml", &[]),
        ("envmap_v3.xml", &[]),
        (
            "instances_v04.xml",
            &["have zero area; the shape is skipped"],
        ),
        ("serialized_v05.xml", &[]),
        ("textures_v2.xml", &[]),
        ("utf16_spheres_v3.xml", &[]),
        ("utf8_spheres_v3.xml", &[]),
        ("veach_mis_v3.xml", &["integrator 'moment'"]),
    ];
    let mut files: Vec<String> = std::fs::read_dir(data(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".xml"))
        .collect();
    files.sort();
    let listed: Vec<String> = expected.iter().map(|(n, _)| n.to_string()).collect();
    assert_eq!(
        files, listed,
        "a scene without expectations, or one missing"
    );
    for (name, want) in expected {
        let (_, w) = load(name);
        assert_eq!(w.len(), want.len(), "{name}: {w:#?}");
        for (got, want) in w.iter().zip(want.iter()) {
            assert!(got.contains(want), "{name}: {got}");
        }
    }
}

#[test]
fn cornell_box_in_the_06_dialect() {
    let (s, _) = load("cbox_v06.xml");
    // Five walls and the light (rectangles), the box and the ball from one serialized file.
    let m = meshes(&s);
    assert_eq!(m.len(), 8);
    let (boxm, ball) = (m[6], m[7]);
    assert_eq!(boxm.triangle_count(), 12);
    assert_eq!(ball.triangle_count(), 320);
    // The ball's file has no normals: Mitsuba shades it smoothly, so does ophis.
    assert!(ball.has_vertex_normals() && ball.has_uvs());
    assert_eq!(s.lights.len(), 1);
    assert_eq!(s.integrator.max_depth, Some(6));
    assert_eq!((s.width, s.height, s.sampler.spp), (80, 60, 64));
}

#[test]
fn ply_uvs_are_used_as_stored_and_obj_uvs_flipped() {
    let (s, _) = load("textures_v2.xml");
    let uv_at = |x: f32, y: f32| {
        let (_, si) = s
            .intersect(&Ray::new(Vec3::new(x, y, 5.0), -Vec3::Z))
            .expect("the ray meets a quad");
        si.uv
    };
    // The PLY quad (left, centre x = −1.1) stores uv (0, 0) at its lower-left corner; the OBJ
    // quad (right) stores 1 − v, which Mitsuba's flip turns back: both read the same uv.
    for (dx, dy) in [(0.5, -0.5), (-0.8, 0.7), (0.0, 0.0), (0.9, 0.9)] {
        let want = Vec2::new((dx + 1.0) / 2.0, (dy + 1.0) / 2.0);
        let ply = uv_at(-1.1 + dx, dy);
        let obj = uv_at(1.1 + dx, dy);
        assert!((ply - want).length() < 1e-5, "ply {ply} vs {want}");
        assert!((obj - want).length() < 1e-5, "obj {obj} vs {want}");
    }
    assert_eq!(s.infinite_lights.len(), 1);
}

#[test]
fn instances_cylinders_and_a_referenced_area_emitter() {
    let (s, _) = load("instances_v04.xml");
    let cylinders = s
        .shapes
        .iter()
        .filter(|s| matches!(s, Shape::Cylinder(_)))
        .count();
    let spheres = s
        .shapes
        .iter()
        .filter(|s| matches!(s, Shape::Sphere(_)))
        .count();
    // Three instances of (cylinder, sphere), the tube light, the glowing sphere, two walls.
    assert_eq!((cylinders, spheres, s.shapes.len()), (4, 4, 10));
    assert_eq!(s.lights.len(), 2);
    assert_eq!(
        s.integrator.kind,
        IntegratorKind::Direct {
            emitter_samples: 2,
            bsdf_samples: 1
        }
    );
    // The second instance scales by 1.3: its post is a radius 0.13 cylinder.
    let Shape::Cylinder(c) = &s.shapes[2] else {
        panic!("{:?}", s.shapes[2])
    };
    assert!((c.radius - 0.13).abs() < 1e-5 && (c.length - 1.3).abs() < 1e-5);
}

#[test]
fn serialized_meshes_in_the_05_dialect() {
    let (s, _) = load("serialized_v05.xml");
    let m = meshes(&s);
    assert_eq!(m.len(), 4);
    assert_eq!((m[0].triangle_count(), m[1].triangle_count()), (80, 80));
    assert!(m[0].has_vertex_normals(), "smooth: computed normals");
    assert!(!m[1].has_vertex_normals(), "face_normals");
    assert_eq!(m[2].triangle_count(), 12);
    // `-D index=2` picks the file's third mesh, a single triangle.
    let opts = LoadOptions {
        defines: vec![("index".into(), "2".into())],
        ..Default::default()
    };
    let (s, _) = load_scene(&data("serialized_v05.xml"), &opts).unwrap();
    assert_eq!(meshes(&s)[0].triangle_count(), 1);
    let opts = LoadOptions {
        defines: vec![("index".into(), "3".into())],
        ..Default::default()
    };
    let e = load_scene(&data("serialized_v05.xml"), &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("serialized_v05.xml:27:") && e.contains("shape_index 3"),
        "{e}"
    );
}

#[test]
fn utf16_and_utf8_copies_give_the_same_scene() {
    let (a, _) = load("utf8_spheres_v3.xml");
    let (b, _) = load("utf16_spheres_v3.xml");
    assert_eq!(a.shapes.len(), b.shapes.len());
    assert_eq!(a.materials.len(), b.materials.len());
    assert_eq!((a.width, a.height), (b.width, b.height));
    assert_eq!(a.shape_material, b.shape_material);
    // The alias and the forward reference name one material for two spheres.
    assert_eq!(a.shape_material[0], a.shape_material[2]);
}

#[test]
fn moment_keeps_the_nested_depth() {
    let (s, _) = load("veach_mis_v3.xml");
    assert_eq!(s.integrator.kind, IntegratorKind::Path);
    assert_eq!(s.integrator.max_depth, Some(4));
    assert_eq!(s.lights.len(), 5);
}

#[test]
fn jpeg_blocks_decode_to_their_colours() {
    let srgb = |v: f32| {
        let v = v.clamp(0.0, 1.0);
        255.0
            * if v <= 0.0031308 {
                12.92 * v
            } else {
                1.055 * v.powf(1.0 / 2.4) - 0.055
            }
    };
    let colours = [[200, 40, 30], [30, 180, 60], [20, 50, 210], [250, 250, 250]];
    for name in ["blocks.jpg", "blocks_progressive.jpg"] {
        let img = read_image(data(&format!("textures/{name}"))).unwrap();
        assert_eq!((img.width, img.height), (16, 16));
        for (k, c) in colours.iter().enumerate() {
            let p = img.get(8 * (k % 2) + 3, 8 * (k / 2) + 4);
            for ch in 0..3 {
                // Quality 100 without chroma subsampling: within 2 codes of what was stored.
                let got = srgb(p[ch]);
                assert!((got - c[ch] as f32).abs() <= 2.0, "{name} block {k}: {p:?}");
            }
        }
    }
    let grey = read_image(data("textures/blocks_grey.jpg")).unwrap();
    for (k, v) in [10, 90, 170, 250].iter().enumerate() {
        let p = grey.get(8 * (k % 2) + 4, 8 * (k / 2) + 3);
        assert!(p[0] == p[1] && p[1] == p[2]);
        assert!((srgb(p[0]) - *v as f32).abs() <= 2.0, "{p:?}");
    }
}

#[test]
fn truncated_or_corrupt_jpegs_are_errors_not_panics() {
    let bytes = std::fs::read(data("textures/chart.jpg")).unwrap();
    let dir = std::env::temp_dir().join(format!("ophis-jpeg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("cut.jpg");
    for cut in (0..bytes.len()).step_by(97) {
        std::fs::write(&p, &bytes[..cut]).unwrap();
        let _ = read_image(&p);
    }
    let mut bad = bytes.clone();
    for i in (20..bad.len()).step_by(13) {
        bad[i] ^= 0x5A;
    }
    std::fs::write(&p, &bad).unwrap();
    let _ = read_image(&p);
    std::fs::write(&p, &bytes[..3]).unwrap();
    let e = read_image(&p).unwrap_err().to_string();
    assert!(e.contains("cut.jpg") && e.contains("JPEG"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 3.0 scene with `body`, body from line 2.
fn xml(body: &str) -> String {
    format!("<scene version=\"3.0.0\">\n{body}\n</scene>")
}

fn err(body: &str) -> String {
    load_scene_str(&xml(body), Path::new("h.xml"), &LoadOptions::default())
        .map(|_| ())
        .unwrap_err()
        .to_string()
}

fn warnings(body: &str) -> Vec<String> {
    let (_, w) = load_scene_str(&xml(body), Path::new("h.xml"), &LoadOptions::default()).unwrap();
    w.into_iter().map(|w| w.message).collect()
}

#[test]
fn out_of_range_rgb_reflectances_are_refused_as_in_mitsuba() {
    let e = err("<shape type=\"sphere\"><bsdf type=\"diffuse\">\n  <rgb name=\"reflectance\" value=\"-1, 0.5, 0.5\"/></bsdf></shape>");
    assert!(
        e.starts_with("h.xml:3:3") && e.contains("-1, 0.5, 0.5") && e.contains("[0, 1]"),
        "{e}"
    );
    let e = err("<shape type=\"sphere\"><bsdf type=\"diffuse\">\n<rgb name=\"reflectance\" value=\"0.2, 1.5, 0.5\"/></bsdf></shape>");
    assert!(e.contains("1.5"), "{e}");
    let e = err("<shape type=\"sphere\"><emitter type=\"area\">\n<rgb name=\"radiance\" value=\"1, -2, 1\"/></emitter></shape>");
    assert!(e.contains("non-negative"), "{e}");
    // Emission above 1 is fine.
    warnings("<shape type=\"sphere\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"10, 2, 1\"/></emitter></shape>");
}

#[test]
fn top_level_area_emitters_and_shapegroups() {
    let w = warnings(
        "<emitter type=\"area\" id=\"e\"><rgb name=\"radiance\" value=\"2\"/></emitter>\n\
         <shape type=\"sphere\"><ref id=\"e\"/></shape><shape type=\"cube\"><ref id=\"e\"/></shape>",
    );
    assert!(w.is_empty(), "{w:?}");
    let w = warnings("<emitter type=\"area\" id=\"lonely\"/><emitter type=\"constant\"/>");
    assert!(
        w.iter().any(|m| m.contains("attached to no shape")),
        "{w:?}"
    );
    let e = err("<emitter type=\"area\"/>");
    assert!(e.contains("inside a shape"), "{e}");
    let w = warnings("<shape type=\"shapegroup\" id=\"g\"><shape type=\"sphere\"/></shape><emitter type=\"constant\"/>");
    assert!(w.iter().any(|m| m.contains("never instanced")), "{w:?}");
    let e = err(
        "<shape type=\"shapegroup\" id=\"g\"><shape type=\"sphere\"/></shape>\n\
         <shape type=\"shapegroup\" id=\"h\">\n<shape type=\"instance\"><ref id=\"g\"/></shape></shape>\n\
         <shape type=\"instance\"><ref id=\"h\"/></shape>",
    );
    assert!(
        e.starts_with("h.xml:4:") && e.contains("nested instancing"),
        "{e}"
    );
    let e = err("<shape type=\"instance\">\n</shape>");
    assert!(e.contains("0 shapegroups"), "{e}");
}

#[test]
fn cylinder_parameters_are_checked() {
    let e = err("<shape type=\"cylinder\">\n<float name=\"radius\" value=\"-1\"/></shape>");
    assert!(e.contains("radius"), "{e}");
    let e = err("<shape type=\"cylinder\"><transform name=\"to_world\"><scale x=\"1\" y=\"3\" z=\"1\"/></transform></shape>");
    assert!(e.contains("cylinder") && e.contains("similarity"), "{e}");
    let e = err("<shape type=\"cylinder\"><point name=\"p0\" value=\"1, 1, 1\"/><point name=\"p1\" value=\"1, 1, 1\"/></shape>");
    assert!(e.contains("cylinder"), "{e}");
}

#[test]
fn an_emitter_without_a_bsdf_is_black_as_in_mitsuba() {
    use ophis::bsdf::Material;
    use ophis::spectrum::Spectrum;
    use ophis::texture::SpectrumTexture;
    let (s, _) = load_scene_str(
        &xml("<shape type=\"sphere\"><emitter type=\"area\"/></shape>\n<shape type=\"cube\"/>"),
        Path::new("h.xml"),
        &LoadOptions::default(),
    )
    .unwrap();
    let reflectance = |i: usize| match &s.materials[s.shape_material[i] as usize] {
        Material::Diffuse {
            reflectance: SpectrumTexture::Constant(Spectrum::Constant(v)),
        } => *v,
        other => panic!("{other:?}"),
    };
    assert_eq!((reflectance(0), reflectance(1)), (0.0, 0.5));
}

/// Runs the `ophis` binary; returns (exit code, stdout, stderr).
fn ophis(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ophis"))
        .args(args)
        .output()
        .unwrap();
    let s = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (
        out.status.code().unwrap_or(-1),
        s(&out.stdout),
        s(&out.stderr),
    )
}

#[test]
fn check_prints_every_warning_and_renders_nothing() {
    let scene = data("instances_v04.xml");
    let (code, out, err) = ophis(&["check", scene.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("loads: 10 shapes") && out.contains("1 warning"),
        "{out}"
    );
    assert!(
        err.contains("instances_v04.xml:") && err.contains("zero area"),
        "{err}"
    );
    let (code, _, err) = ophis(&["check", "--strict", scene.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
}

#[test]
fn warnings_leading_up_to_an_error_are_printed_before_it() {
    let dir = std::env::temp_dir().join(format!("ophis-warn-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("bad.xml");
    // A misspelt attribute (a warning), then an unknown id (the error).
    std::fs::write(
        &p,
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\" colour=\"red\"/>\n<shape type=\"sphere\"><ref id=\"nowhere\"/></shape>\n</scene>\n",
    )
    .unwrap();
    for cmd in ["check", "render"] {
        let out = dir.join("out.exr");
        let (code, _, err) = ophis(
            &[cmd, p.to_str().unwrap(), "-o", out.to_str().unwrap()]
                [..if cmd == "check" { 2 } else { 4 }],
        );
        assert_eq!(code, 1, "{cmd}: {err}");
        let warn = err.find("colour").unwrap_or_else(|| panic!("{cmd}: {err}"));
        let error = err
            .find("unknown id 'nowhere'")
            .unwrap_or_else(|| panic!("{cmd}: {err}"));
        assert!(warn < error, "{cmd}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
