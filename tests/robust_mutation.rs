//! Property test: mutated valid scenes (bytes, tags, attribute names and values) and mutated
//! mesh files give an error or an image, never a panic. Seeded and bounded (CASES per seed
//! scene), so a failure reproduces; the offending input is printed.

use ophis::film::Film;
use ophis::integrator::PathStrategy;
use ophis::math::Pcg32;
use ophis::render::{render, NoProgress, RenderOptions};
use ophis::scene::build::{load_scene, load_scene_str, LoadOptions};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// Mutants per seed scene.
const CASES: usize = 250;

const TAGS: &[&str] = &[
    "scene",
    "shape",
    "bsdf",
    "emitter",
    "sensor",
    "film",
    "sampler",
    "integrator",
    "texture",
    "float",
    "integer",
    "boolean",
    "string",
    "rgb",
    "spectrum",
    "point",
    "vector",
    "transform",
    "translate",
    "scale",
    "rotate",
    "lookat",
    "matrix",
    "ref",
    "include",
    "default",
    "alias",
    "rfilter",
    "blackbody",
    "frobnicate",
];
const ATTRS: &[&str] = &[
    "type",
    "name",
    "value",
    "id",
    "filename",
    "x",
    "y",
    "z",
    "angle",
    "origin",
    "target",
    "up",
    "version",
    "temperature",
    "as",
    "foo",
];
const VALUES: &[&str] = &[
    "",
    "0",
    "-0",
    "1",
    "-1",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e39",
    "1e-45",
    "99999999999999999999",
    "1000000",
    "0.5, 0.5",
    "1,2,3,4",
    "#zzzzzz",
    "$undefined",
    "$spp",
    "a",
    "sphere",
    "obj",
    "ply",
    "envmap",
    "dielectric",
    "layered",
    "../",
    "/",
    "nope.xml",
    "m.obj",
    "m.ply",
    "3.0.0",
    "0.6.0",
    "9.9.9",
    "400:nan",
    "300K",
    "Au",
    "\u{1F40D}",
];

fn pick<'a>(rng: &mut Pcg32, v: &[&'a str]) -> &'a str {
    v[rng.next_u32() as usize % v.len()]
}

/// Byte offsets of every occurrence of `pat`.
fn find_all(s: &[u8], pat: &[u8]) -> Vec<usize> {
    (0..s.len().saturating_sub(pat.len()))
        .filter(|&i| &s[i..i + pat.len()] == pat)
        .collect()
}

/// One to three random edits of the text.
fn mutate(src: &[u8], rng: &mut Pcg32) -> Vec<u8> {
    let mut s = src.to_vec();
    for _ in 0..1 + rng.next_u32() % 3 {
        let n = s.len().max(1);
        let at = rng.next_u32() as usize % n;
        match rng.next_u32() % 8 {
            // Bytes: flip, delete a run, duplicate a run, truncate.
            0 => {
                if let Some(b) = s.get_mut(at) {
                    *b ^= 1 << (rng.next_u32() % 8);
                }
            }
            1 => {
                let len = (rng.next_u32() % 40) as usize;
                s.drain(at.min(s.len())..(at + len).min(s.len()));
            }
            2 => {
                let len = (rng.next_u32() % 200) as usize;
                let run = s[at.min(s.len())..(at + len).min(s.len())].to_vec();
                let to = rng.next_u32() as usize % n;
                s.splice(to.min(s.len())..to.min(s.len()), run);
            }
            3 => s.truncate(at),
            // Tags: rename an element (opening or closing).
            4 => {
                let hits = find_all(&s, b"<");
                if let Some(&i) = hits.get(rng.next_u32() as usize % hits.len().max(1)) {
                    let j = i + 1 + (s.get(i + 1) == Some(&b'/')) as usize;
                    let end = (j..s.len())
                        .find(|&k| !s[k].is_ascii_alphanumeric() && s[k] != b'_')
                        .unwrap_or(s.len());
                    s.splice(j..end, pick(rng, TAGS).bytes());
                }
            }
            // Attributes: replace a value, rename an attribute, or add one.
            5 | 6 => {
                let hits = find_all(&s, b"=\"");
                if let Some(&i) = hits.get(rng.next_u32() as usize % hits.len().max(1)) {
                    let start = i + 2;
                    let end = (start..s.len()).find(|&k| s[k] == b'"').unwrap_or(s.len());
                    if rng.next_u32().is_multiple_of(3) {
                        let k0 = (0..i).rev().find(|&k| s[k] == b' ').map_or(i, |k| k + 1);
                        s.splice(k0..i, pick(rng, ATTRS).bytes());
                    } else {
                        s.splice(start..end, pick(rng, VALUES).bytes());
                    }
                }
            }
            _ => {
                let hits = find_all(&s, b"/>");
                if let Some(&i) = hits.get(rng.next_u32() as usize % hits.len().max(1)) {
                    let attr = format!(" {}=\"{}\"", pick(rng, ATTRS), pick(rng, VALUES));
                    s.splice(i..i, attr.bytes());
                }
            }
        }
    }
    s
}

/// Loads the mutant and, if it loads, renders 4 × 4 pixels at 1 spp. Returns whether it
/// rendered, or the panic message.
fn exercise(bytes: &[u8], scene_file: &Path) -> Result<bool, String> {
    let r = catch_unwind(AssertUnwindSafe(|| {
        let opts = LoadOptions::default();
        let loaded = match std::str::from_utf8(bytes) {
            Ok(text) => load_scene_str(text, scene_file, &opts),
            Err(_) => {
                let p = scene_file.with_file_name("mutant-bytes.xml");
                std::fs::write(&p, bytes).unwrap();
                load_scene(&p, &opts)
            }
        };
        if let Ok((mut scene, _)) = loaded {
            // The camera maps the unit square to the view, so a 4 × 4 film samples the
            // whole image coarsely whatever resolution the mutant asked for.
            scene.width = 4;
            scene.height = 4;
            let mut film = Film::new(4, 4);
            let opts = RenderOptions {
                spp: 1,
                time_limit: Some(std::time::Duration::from_secs(20)),
                strategy: PathStrategy::Mis,
                engine: ophis::render::Engine::Auto,
            };
            render(
                &scene,
                &mut film,
                0,
                &opts,
                &AtomicBool::new(false),
                &NoProgress,
            );
            assert!(film.to_linear_srgb().len() == 16);
            return true;
        }
        false
    }));
    r.map_err(|e| {
        e.downcast_ref::<String>()
            .cloned()
            .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default()
    })
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ophis-mut-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run_seed(name: &str, text: &[u8], dir: &Path, seed: u64) {
    let scene_file = dir.join(name);
    let mut rng = Pcg32::new(seed, 0);
    let mut failures = Vec::new();
    let mut rendered = 0;
    for case in 0..CASES {
        let m = mutate(text, &mut rng);
        match exercise(&m, &scene_file) {
            Ok(r) => rendered += r as usize,
            Err(msg) => failures.push(format!(
                "case {case} of {name} panicked: {msg}\n--- input ---\n{}\n---",
                String::from_utf8_lossy(&m)
            )),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // Both outcomes must be exercised, or the mutations are too mild or too wild.
    assert!(
        rendered > CASES / 10 && rendered < CASES * 9 / 10,
        "{name}: {rendered} of {CASES} mutants rendered"
    );
}

#[test]
fn mutated_scenes_error_or_render_never_panic() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = temp("scenes");
    for (i, f) in ["tests/data/reference.xml", "scenes/cornell-box.xml"]
        .iter()
        .enumerate()
    {
        let text = std::fs::read(root.join(f)).unwrap();
        // Small films and few samples: only the absence of panics is under test.
        let text = String::from_utf8(text)
            .unwrap()
            .replace("value=\"256\"", "value=\"8\"")
            .replace("value=\"64\"", "value=\"8\"")
            .replace("value=\"48\"", "value=\"6\"");
        run_seed(
            &format!("seed{i}.xml"),
            text.as_bytes(),
            &dir,
            1000 + i as u64,
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn mutated_meshes_error_or_render_never_panic() {
    let dir = temp("meshes");
    let obj = b"# tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1\nf 1 2 4\nf 1 3 4\nf 2 3 4\n";
    let ply = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n4 0 1 2 3\n";
    let scene =
        "<scene version=\"3.0.0\"><sensor type=\"perspective\"><transform name=\"to_world\">\
        <lookat origin=\"0,0,4\" target=\"0,0,0\" up=\"0,1,0\"/></transform></sensor>\
        <emitter type=\"constant\"/>\
        <shape type=\"obj\"><string name=\"filename\" value=\"m.obj\"/></shape>\
        <shape type=\"ply\"><string name=\"filename\" value=\"m.ply\"/></shape></scene>";
    let scene_file = dir.join("mesh.xml");
    let mut rng = Pcg32::new(77, 0);
    let mut failures = Vec::new();
    let mut rendered = 0;
    for case in 0..CASES {
        let (mo, mp) = (mutate(obj, &mut rng), mutate(ply, &mut rng));
        std::fs::write(dir.join("m.obj"), &mo).unwrap();
        std::fs::write(dir.join("m.ply"), &mp).unwrap();
        let r = exercise(scene.as_bytes(), &scene_file);
        rendered += matches!(r, Ok(true)) as usize;
        if let Err(msg) = r {
            failures.push(format!(
                "case {case} panicked: {msg}\n--- m.obj ---\n{}\n--- m.ply ---\n{}",
                String::from_utf8_lossy(&mo),
                String::from_utf8_lossy(&mp)
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        rendered > CASES / 20,
        "only {rendered} of {CASES} mutated meshes rendered"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
