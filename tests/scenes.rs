//! Every scene in `scenes/` (all subfolders; `scenes/parts/` holds include-only fragments)
//! loads without warnings and renders at a tiny resolution to a finite image; one test per
//! file, so a broken scene names itself. Figure scenes driven by `-Dshape` (and `-Dstage`) are
//! rendered with every value. A last test checks that the list below is the directory listing,
//! so that a new scene cannot be forgotten.

use ophis::tools::preview::render_file;
use std::path::{Path, PathBuf};

/// Pixels per side and samples per pixel of the smoke renders.
const RES: u32 = 12;
const SPP: u32 = 2;

fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// A one-triangle PLY for scenes that expect a generated mesh (cornell-mesh.xml).
fn tiny_mesh() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ophis-scenes-test-{}", std::process::id()));
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

/// The `-D` variants a scene is rendered with: each value of the parameters it declares.
fn variants(text: &str) -> Vec<Vec<(String, String)>> {
    let mut out = vec![vec![]];
    let mut expand = |name: &str, values: &[&str]| {
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
    };
    expand("shape", &["sphere", "torus", "snake"]);
    expand("stage", &["diffuse", "bump", "film-bump", "skin-bump"]);
    out
}

fn check_scene(rel: &str) {
    let path = scenes_dir().join(rel);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{rel}: {e}"));
    for mut defines in variants(&text) {
        if text.contains("<default name=\"mesh\"") {
            defines.push(("mesh".into(), tiny_mesh().display().to_string()));
        }
        let (img, warnings) = render_file(&path, &defines, (RES, RES), SPP)
            .unwrap_or_else(|e| panic!("{rel} {defines:?}: {e}"));
        // A file without a sensor is a BSDF collection for `ophis bsdf` (layered-skin.xml):
        // it has no lights by design, and every parameter of its BSDFs (nested phases
        // included) must be read even though no shape uses them.
        let unexpected: Vec<_> = warnings
            .iter()
            .filter(|w| text.contains("<sensor") || !w.to_string().contains("no emitters"))
            .collect();
        assert!(unexpected.is_empty(), "{rel} {defines:?}: {unexpected:#?}");
        assert_eq!((img.width, img.height), (RES as usize, RES as usize));
        assert!(
            img.data.iter().flatten().all(|v| v.is_finite()),
            "{rel} {defines:?}: non-finite pixels"
        );
        // A lit scene must show something: a black image means the lights or camera broke.
        if text.contains("<emitter") || rel == "xenopeltis.xml" || text.contains("stage-") {
            let mean: f32 = img.data.iter().flatten().sum::<f32>() / (3 * img.data.len()) as f32;
            assert!(mean > 1e-3, "{rel} {defines:?}: black image (mean {mean})");
        }
    }
}

macro_rules! scene_tests {
    ($($name:ident => $path:expr),* $(,)?) => {
        $(
            #[test]
            fn $name() {
                check_scene($path);
            }
        )*
        /// The scenes the tests above cover.
        const LISTED: &[&str] = &[$($path),*];
    };
}

scene_tests! {
    ceig2023_fig5_range => "ceig2023/fig5-range.xml",
    ceig2023_fig6_ablation => "ceig2023/fig6-ablation.xml",
    cornell_box => "cornell-box.xml",
    cornell_mesh => "cornell-mesh.xml",
    daylight => "daylight.xml",
    filmstack_compare => "filmstack-compare.xml",
    layered_skin => "layered-skin.xml",
    scales_snake_thinfilm => "scales-snake-thinfilm.xml",
    scales_snake => "scales-snake.xml",
    scales_sphere => "scales-sphere.xml",
    scales_torus => "scales-torus.xml",
    snake_head => "snake-head.xml",
    snake_poses => "snake-poses.xml",
    snake_shape => "snake-shape.xml",
    thesis_fig4_1_diffuse => "thesis/fig4-1-diffuse.xml",
    thesis_fig4_2_bump => "thesis/fig4-2-bump.xml",
    thesis_fig4_3_film => "thesis/fig4-3-film.xml",
    thesis_fig4_4_film_bump => "thesis/fig4-4-film-bump.xml",
    thesis_fig4_5_absorption => "thesis/fig4-5-absorption.xml",
    thesis_fig4_6_skin => "thesis/fig4-6-skin.xml",
    thesis_fig4_7_skin_bump => "thesis/fig4-7-skin-bump.xml",
    thinfilm_bubble => "thinfilm-bubble.xml",
    thinfilm_compare => "thinfilm-compare.xml",
    thinfilm_sphere => "thinfilm-sphere.xml",
    xenopeltis => "xenopeltis.xml",
}

fn collect(dir: &Path, root: &Path, out: &mut Vec<String>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            // Include-only fragments, rendered through the scenes that include them.
            if p.file_name().is_some_and(|n| n == "parts") {
                continue;
            }
            collect(&p, root, out);
        } else if p.extension().is_some_and(|x| x == "xml") {
            let rel = p.strip_prefix(root).unwrap();
            out.push(rel.to_string_lossy().replace('\\', "/"));
        }
    }
}

#[test]
fn every_scene_file_is_tested() {
    let root = scenes_dir();
    let mut found = Vec::new();
    collect(&root, &root, &mut found);
    found.sort();
    let mut listed: Vec<String> = LISTED.iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(
        found, listed,
        "tests/scenes.rs must list every scene in scenes/ (add new ones to scene_tests!)"
    );
}

#[test]
fn builtin_flagship_is_the_scene_file() {
    let file = std::fs::read_to_string(scenes_dir().join("xenopeltis.xml")).unwrap();
    assert_eq!(file, ophis::scene::builtin::XENOPELTIS_XML);
    // It must not depend on files beside it: it is loaded from the binary.
    for attr in ["filename=", "<include"] {
        assert!(
            !file.contains(attr),
            "xenopeltis.xml refers to a file ({attr})"
        );
    }
}
