//! The bad-input sweep: every kind of broken scene, mesh, image and command line named in
//! issue 7 gives an error naming where (file:line:column, or the file) and what, never a
//! panic or a hang; through the library, and through the binary with a non-zero exit.

use ophis::scene::build::{load_scene, LoadOptions};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::Command;

fn temp(name: &str) -> PathBuf {
    // The test's own name too: tests run in parallel threads and reuse case names.
    let test = std::thread::current()
        .name()
        .unwrap_or("main")
        .replace("::", "-");
    let d = std::env::temp_dir().join(format!("ophis-bad-{}-{test}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A scene whose `BODY` is replaced by the case's elements.
const FRAME: &str = "<scene version=\"3.0.0\">\n\
    <sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/>\
    <integer name=\"height\" value=\"8\"/></film></sensor>\nBODY\n</scene>\n";

fn frame(body: &str) -> String {
    FRAME.replace("BODY", body)
}

/// Loads `scene.xml` (written from `xml`) beside `files`; returns the error message, failing
/// the test if the load succeeds or panics.
fn load_error(case: &str, xml: &str, files: &[(&str, &[u8])]) -> String {
    let dir = temp(case);
    for (name, bytes) in files {
        if name.ends_with('/') {
            std::fs::create_dir_all(dir.join(name)).unwrap();
        } else {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
    }
    let scene = dir.join("scene.xml");
    std::fs::write(&scene, xml).unwrap();
    let r = catch_unwind(AssertUnwindSafe(|| {
        load_scene(&scene, &LoadOptions::default()).map(|_| ())
    }));
    let _ = std::fs::remove_dir_all(&dir);
    match r {
        Err(_) => panic!("{case}: the loader panicked on:\n{xml}"),
        Ok(Ok(())) => panic!("{case}: loaded without error:\n{xml}"),
        Ok(Err(e)) => e.to_string(),
    }
}

/// Asserts that the message contains every `want` (case-insensitive).
fn says(case: &str, msg: &str, want: &[&str]) {
    for w in want {
        assert!(
            msg.to_lowercase().contains(&w.to_lowercase()),
            "{case}: message lacks '{w}': {msg}"
        );
    }
}

fn reference_xml() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/reference.xml"))
        .unwrap()
}

#[test]
fn truncated_and_malformed_xml() {
    let xml = reference_xml();
    for cut in [10, xml.len() / 3, xml.len() / 2, xml.len() - 3] {
        let mut end = cut;
        while !xml.is_char_boundary(end) {
            end -= 1;
        }
        let msg = load_error("truncated", &xml[..end], &[]);
        says("truncated", &msg, &["scene.xml:"]);
    }
    let cases = [
        (
            "unclosed",
            "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n</scene>",
            "scene.xml:3:",
        ),
        ("empty", "", "scene.xml"),
        ("not xml", "\u{0}\u{1}garbage", "scene.xml:1:"),
        ("wrong root", "<shape type=\"sphere\"/>", "scene"),
        (
            "bad attribute",
            "<scene version=\"3.0.0\">\n<shape type=sphere/>\n</scene>",
            "scene.xml:2:",
        ),
    ];
    for (case, xml, want) in cases {
        let msg = load_error(case, xml, &[]);
        says(case, &msg, &[want]);
    }
}

#[test]
fn unknown_and_cyclic_references_and_includes() {
    let msg = load_error(
        "unknown ref",
        &frame("<shape type=\"sphere\">\n<ref id=\"nope\"/></shape>"),
        &[],
    );
    says("unknown ref", &msg, &["scene.xml:4:", "nope"]);
    let msg = load_error(
        "self ref",
        &frame("<bsdf type=\"twosided\" id=\"a\">\n<ref id=\"a\"/></bsdf>\n<shape type=\"sphere\"><ref id=\"a\"/></shape>"),
        &[],
    );
    says("self ref", &msg, &["scene.xml:4:", "'a'"]);
    let msg = load_error(
        "unknown include",
        &frame("<include filename=\"nope.xml\"/>"),
        &[],
    );
    says("unknown include", &msg, &["scene.xml:3:", "nope.xml"]);
    let msg = load_error(
        "cyclic include",
        &frame("<include filename=\"a.xml\"/>"),
        &[
            (
                "a.xml",
                b"<scene version=\"3.0.0\">\n<include filename=\"b.xml\"/>\n</scene>",
            ),
            (
                "b.xml",
                b"<scene version=\"3.0.0\">\n<include filename=\"a.xml\"/>\n</scene>",
            ),
        ],
    );
    says("cyclic include", &msg, &["b.xml:2:", "a.xml"]);
    let msg = load_error(
        "self include",
        &frame("<include filename=\"scene.xml\"/>"),
        &[],
    );
    says("self include", &msg, &["scene.xml:3:"]);
    let msg = load_error(
        "include dir",
        &frame("<include filename=\"d/\"/>"),
        &[("d/", b"")],
    );
    says("include dir", &msg, &["scene.xml:3:", "d"]);
}

const CUBE_OBJ: &[u8] = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n";
const TRI_PLY: &[u8] = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

#[test]
fn broken_meshes() {
    let obj_trunc = &CUBE_OBJ[..CUBE_OBJ.len() - 4];
    let ply_trunc = &TRI_PLY[..TRI_PLY.len() - 8];
    let ply_huge = String::from_utf8_lossy(TRI_PLY).replace("vertex 3", "vertex 1000000000000");
    let garbage: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    for ext in ["obj", "ply"] {
        let trunc = if ext == "obj" { obj_trunc } else { ply_trunc };
        let cases: Vec<(&str, Option<&[u8]>)> = vec![
            ("missing", None),
            ("empty", Some(b"")),
            ("truncated", Some(trunc)),
            ("garbage", Some(&garbage)),
            ("directory", Some(b"/")),
        ];
        for (case, content) in cases {
            let name = format!("m.{ext}");
            let files: Vec<(String, &[u8])> = match content {
                None => vec![],
                Some(b"/") => vec![(format!("{name}/"), &b""[..])],
                Some(c) => vec![(name.clone(), c)],
            };
            let files: Vec<(&str, &[u8])> = files.iter().map(|(n, c)| (n.as_str(), *c)).collect();
            let xml = frame(&format!(
                "<shape type=\"{ext}\">\n<string name=\"filename\" value=\"{name}\"/></shape>"
            ));
            let msg = load_error(case, &xml, &files);
            says(&format!("{ext} {case}"), &msg, &["scene.xml:4:", &name]);
        }
    }
    let xml = frame("<shape type=\"ply\">\n<string name=\"filename\" value=\"h.ply\"/></shape>");
    let msg = load_error("huge ply", &xml, &[("h.ply", ply_huge.as_bytes())]);
    says("huge ply", &msg, &["h.ply"]);
}

/// Files to create beside a scene: name (a trailing `/` makes a directory) and contents.
type Files<'a> = Vec<(&'a str, &'a [u8])>;

#[test]
fn broken_environment_images() {
    let garbage: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2246822519) >> 11) as u8)
        .collect();
    let hdr_trunc: &[u8] = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n\x01\x02";
    let exr_trunc: &[u8] = &[0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0, b'c', b'h'];
    for ext in ["exr", "hdr"] {
        let trunc = if ext == "exr" { exr_trunc } else { hdr_trunc };
        let name = format!("e.{ext}");
        let dir_name = format!("{name}/");
        let cases: Vec<(&str, Files)> = vec![
            ("missing", vec![]),
            ("empty", vec![(name.as_str(), b"")]),
            ("truncated", vec![(name.as_str(), trunc)]),
            ("garbage", vec![(name.as_str(), &garbage)]),
            ("directory", vec![(dir_name.as_str(), b"")]),
        ];
        for (case, files) in cases {
            let xml = frame(&format!(
                "<emitter type=\"envmap\">\n<string name=\"filename\" value=\"{name}\"/></emitter>"
            ));
            let msg = load_error(case, &xml, &files);
            says(&format!("{ext} {case}"), &msg, &["scene.xml:4:", &name]);
        }
    }
}

/// A case name, its scene and what the message must contain.
type Case<'a> = (&'a str, String, &'a [&'a str]);

#[test]
fn nan_inf_negative_and_absurd_numbers() {
    let cases: &[Case] = &[
        ("radius nan", frame("<shape type=\"sphere\">\n<float name=\"radius\" value=\"nan\"/></shape>"), &["scene.xml:4:", "radius"]),
        ("radius inf", frame("<shape type=\"sphere\">\n<float name=\"radius\" value=\"inf\"/></shape>"), &["scene.xml:4:", "radius"]),
        ("radius negative", frame("<shape type=\"sphere\">\n<float name=\"radius\" value=\"-2\"/></shape>"), &["scene.xml:4:", "radius"]),
        ("radius huge", frame("<shape type=\"sphere\">\n<float name=\"radius\" value=\"1e39\"/></shape>"), &["scene.xml:4:", "radius"]),
        ("ior nan", frame("<shape type=\"sphere\"><bsdf type=\"dielectric\">\n<float name=\"int_ior\" value=\"nan\"/></bsdf></shape>"), &["scene.xml:4:", "int_ior"]),
        ("ior negative", frame("<shape type=\"sphere\"><bsdf type=\"dielectric\">\n<float name=\"int_ior\" value=\"-1.5\"/></bsdf></shape>"), &["scene.xml:4:", "int_ior"]),
        ("ior inf", frame("<shape type=\"sphere\"><bsdf type=\"dielectric\">\n<float name=\"ext_ior\" value=\"inf\"/></bsdf></shape>"), &["scene.xml:4:", "ext_ior"]),
        ("alpha nan", frame("<shape type=\"sphere\"><bsdf type=\"roughconductor\">\n<float name=\"alpha\" value=\"nan\"/></bsdf></shape>"), &["scene.xml:4:", "alpha"]),
        ("width 0", "<scene version=\"3.0.0\"><sensor type=\"perspective\"><film type=\"hdrfilm\">\n<integer name=\"width\" value=\"0\"/></film></sensor></scene>".into(), &["scene.xml:2:", "width"]),
        ("height 10^6", "<scene version=\"3.0.0\"><sensor type=\"perspective\"><film type=\"hdrfilm\">\n<integer name=\"height\" value=\"1000000\"/></film></sensor></scene>".into(), &["scene.xml:2:", "height"]),
        ("width huge", "<scene version=\"3.0.0\"><sensor type=\"perspective\"><film type=\"hdrfilm\">\n<integer name=\"width\" value=\"99999999999999999999\"/></film></sensor></scene>".into(), &["scene.xml:2:", "width"]),
        ("spp 0", "<scene version=\"3.0.0\"><sensor type=\"perspective\"><sampler type=\"independent\">\n<integer name=\"sample_count\" value=\"0\"/></sampler></sensor></scene>".into(), &["scene.xml:2:", "sample_count"]),
        ("fov nan", "<scene version=\"3.0.0\"><sensor type=\"perspective\">\n<float name=\"fov\" value=\"nan\"/></sensor></scene>".into(), &["scene.xml:2:", "fov"]),
        ("scale 0", frame("<shape type=\"sphere\"><transform name=\"to_world\">\n<scale value=\"0\"/></transform></shape>"), &["scene.xml:4:"]),
        ("rgb nan", frame("<shape type=\"sphere\"><bsdf type=\"diffuse\">\n<rgb name=\"reflectance\" value=\"nan, 0, 0\"/></bsdf></shape>"), &["scene.xml:4:", "reflectance"]),
        ("radiance inf", frame("<emitter type=\"constant\">\n<rgb name=\"radiance\" value=\"inf\"/></emitter>"), &["scene.xml:4:", "radiance"]),
    ];
    for (case, xml, want) in cases {
        let msg = load_error(case, xml, &[]);
        says(case, &msg, want);
    }
}

#[test]
fn a_directory_or_nothing_where_the_scene_file_should_be() {
    let dir = temp("scene-dir");
    for p in [dir.clone(), dir.join("absent.xml")] {
        let r = catch_unwind(|| load_scene(&p, &LoadOptions::default()).map(|_| ()));
        let msg = r.expect("no panic").expect_err("an error").to_string();
        says("scene path", &msg, &[&p.display().to_string()]);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// ---- through the binary ----

fn ophis(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_ophis"))
        .args(args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!err.contains("panicked"), "ophis {args:?} panicked: {err}");
    (out.status.code().unwrap_or(-1), err)
}

#[test]
fn command_line_errors_exit_non_zero_with_a_message() {
    let dir = temp("cli");
    let d = |p: &str| dir.join(p).display().to_string();
    let scene = d("scene.xml");
    std::fs::write(
        &scene,
        frame("<shape type=\"sphere\">\n<float name=\"radius\" value=\"-1\"/></shape>"),
    )
    .unwrap();
    let good = d("good.xml");
    std::fs::write(&good, frame("<shape type=\"sphere\"/>")).unwrap();
    std::fs::write(d("file"), b"x").unwrap();
    std::fs::create_dir_all(d("out.exr")).unwrap();
    let garbage_state = d("g.ophis-state");
    std::fs::write(&garbage_state, b"OPHISST\0 garbage").unwrap();
    let cases: Vec<(Vec<String>, Vec<String>)> = vec![
        (
            vec!["render".into(), scene.clone(), "-q".into()],
            vec![format!("{scene}:4:"), "radius".into()],
        ),
        (
            vec!["render".into(), d("absent.xml")],
            vec![d("absent.xml")],
        ),
        (
            vec!["render".into(), dir.display().to_string()],
            vec!["directory".into()],
        ),
        (
            vec!["render".into(), good.clone(), "--spp".into(), "0".into()],
            vec!["--spp".into()],
        ),
        (
            vec!["render".into(), good.clone(), "--time=-1".into()],
            vec!["--time".into()],
        ),
        (
            vec![
                "render".into(),
                good.clone(),
                "--checkpoint".into(),
                "nan".into(),
            ],
            vec!["--checkpoint".into()],
        ),
        (
            vec!["render".into(), good.clone(), "-D".into(), "novalue".into()],
            vec!["NAME=VALUE".into()],
        ),
        (
            vec!["render".into(), good.clone(), "-o".into(), d("nodir/x.exr")],
            vec!["nodir".into(), "does not exist".into()],
        ),
        (
            vec!["render".into(), good.clone(), "-o".into(), d("file/x.exr")],
            vec![d("file")],
        ),
        (
            vec!["render".into(), good.clone(), "-o".into(), d("out.exr")],
            vec!["out.exr".into(), "directory".into()],
        ),
        (
            vec!["render".into(), "--resume".into(), garbage_state.clone()],
            vec![garbage_state.clone()],
        ),
        (
            vec!["render".into(), "--resume".into(), d("nostate")],
            vec![d("nostate")],
        ),
        (
            vec![
                "render".into(),
                good.clone(),
                "--threads".into(),
                "0".into(),
            ],
            vec!["--threads".into()],
        ),
        (
            vec!["merge".into(), d("m.exr"), d("absent.exr")],
            vec![d("absent.exr")],
        ),
    ];
    for (args, want) in cases {
        let a: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
        let (code, err) = ophis(&a);
        assert_ne!(code, 0, "ophis {a:?} succeeded: {err}");
        assert_ne!(code, -1, "ophis {a:?} died of a signal: {err}");
        let w: Vec<&str> = want.iter().map(|s| s.as_str()).collect();
        says(&format!("{a:?}"), &err, &w);
    }
    // The unwritable output is found before rendering: no time is spent on the scene.
    let t = std::time::Instant::now();
    let (code, _) = ophis(&["render", &good, "--spp", "100000000", "-o", &d("nodir/x")]);
    assert!(code != 0 && t.elapsed().as_secs() < 10);
    let _ = std::fs::remove_dir_all(&dir);
}
