//! The scenes of `scenes/`: their files and the `-D` variants the tests render.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A one-triangle PLY for scenes that expect a generated mesh (cornell-mesh.xml).
pub fn tiny_mesh() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ophis-baseline-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("tri.ply");
    std::fs::write(
        &path,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         -0.5 0 0\n0.5 0 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    path
}

/// Scene files below `scenes/` (not the include-only `parts/`), sorted.
pub fn scene_files() -> Vec<String> {
    fn walk(dir: &Path, base: &Path, out: &mut Vec<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                if p.file_name().is_some_and(|n| n != "parts") {
                    walk(&p, base, out);
                }
            } else if p.extension().is_some_and(|x| x == "xml") {
                out.push(p.strip_prefix(base).unwrap().to_string_lossy().into());
            }
        }
    }
    let base = root().join("scenes");
    let mut v = Vec::new();
    walk(&base, &base, &mut v);
    v.sort();
    v
}

/// The `-D` variants of a scene: every value of the `shape` and `stage` it declares.
pub fn variants(text: &str) -> Vec<Vec<(String, String)>> {
    let mut out = vec![vec![]];
    for (name, values) in [
        ("shape", &["sphere", "torus", "snake"][..]),
        ("stage", &["diffuse", "bump", "film-bump", "skin-bump"][..]),
    ] {
        if text.contains(&format!("<default name=\"{name}\"")) {
            out = out
                .iter()
                .flat_map(|d| {
                    values.iter().map(move |v| {
                        let mut d = d.clone();
                        d.push((name.to_string(), v.to_string()));
                        d
                    })
                })
                .collect();
        }
    }
    out
}
