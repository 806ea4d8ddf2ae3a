//! Sanity limits: scenes whose estimated memory exceeds the machine's are refused before
//! anything large is allocated, with a message that says what is too big.

use ophis::limits::{check, estimate};
use ophis::scene::mitsuba::load_str;
use std::path::Path;
use std::process::Command;

fn film(w: u64, h: u64) -> String {
    format!(
        "<scene version=\"3.0.0\"><sensor type=\"perspective\"><film type=\"hdrfilm\">\
         <integer name=\"width\" value=\"{w}\"/><integer name=\"height\" value=\"{h}\"/>\
         </film></sensor></scene>"
    )
}

#[test]
fn film_and_mesh_estimates_decide_the_refusal() {
    let (root, _) = load_str(&film(1280, 720), Path::new("s.xml"), &[]).unwrap();
    let e = estimate(&root);
    assert_eq!((e.width, e.height), (1280, 720));
    assert_eq!(e.film, 1280 * 720 * 48);
    assert!(check(&root, Some(1 << 30)).is_ok());
    let msg = check(&root, Some(1 << 20)).unwrap_err().to_string();
    assert!(
        msg.starts_with("s.xml:1:") && msg.contains("1280 × 720") && msg.contains("1.0 MiB"),
        "{msg}"
    );
    assert!(check(&root, None).is_ok(), "no known limit: no refusal");

    // A PLY header declaring a billion triangles is counted before it is read.
    let dir = std::env::temp_dir().join(format!("ophis-limits-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("big.ply"),
        "ply\nformat binary_little_endian 1.0\nelement vertex 500000000\nproperty float x\n\
         element face 1000000000\nproperty list uchar int vertex_indices\nend_header\n",
    )
    .unwrap();
    let xml = "<scene version=\"3.0.0\"><shape type=\"ply\">\
               <string name=\"filename\" value=\"big.ply\"/></shape></scene>";
    let (root, _) = load_str(xml, &dir.join("s.xml"), &[]).unwrap();
    let e = estimate(&root);
    assert!(e.meshes > 200 << 30, "{e:?}");
    let msg = check(&root, Some(64 << 30)).unwrap_err().to_string();
    assert!(
        msg.contains("meshes: 2") && msg.contains("big.ply"),
        "{msg}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_binary_refuses_before_rendering_and_exits_non_zero() {
    let dir = std::env::temp_dir().join(format!("ophis-limits-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("big.xml");
    // The largest film the loader accepts: 32768² pixels, about 48 GiB.
    std::fs::write(&scene, film(32768, 32768)).unwrap();
    for limit in [Some("8G"), None] {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_ophis"));
        cmd.arg("render")
            .arg(&scene)
            .arg("-q")
            .arg("-o")
            .arg(dir.join("x"));
        match limit {
            Some(l) => cmd.env("OPHIS_MEMORY_LIMIT", l),
            None => cmd.env_remove("OPHIS_MEMORY_LIMIT"),
        };
        let machine = ophis::limits::machine_memory();
        if limit.is_none() && machine.is_none_or(|m| m >= 48 << 30) {
            continue; // a machine this large would render it
        }
        let out = cmd.output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(
            err.contains("big.xml:1:") && err.contains("48.0 GiB") && err.contains("32768 × 32768"),
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
