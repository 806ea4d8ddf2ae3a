//! The wavefront integrator against the scalar one: every scene of `scenes/` (each `-D` variant)
//! renders to the same pixels, bit for bit, with either engine. The wavefront integrator is
//! meant to compute exactly what the scalar loop computes, path by path, only in another order
//! (batched rays, lanes), so any difference at all is a defect.

use ophis::accel::Isa;
use ophis::film::Film;
use ophis::integrator::PathStrategy;
use ophis::render::{render, Engine, NoProgress, RenderOptions};
use ophis::scene::build::{load_scene, LoadOptions};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

mod common;
use common::scenes::{scene_files, tiny_mesh, variants};

fn render_with(scene: &ophis::scene::Scene, engine: Engine, spp: u32) -> Film {
    let mut film = Film::new(scene.width, scene.height);
    let opts = RenderOptions {
        spp,
        time_limit: None,
        strategy: PathStrategy::Mis,
        engine,
    };
    render(
        scene,
        &mut film,
        0,
        &opts,
        &AtomicBool::new(false),
        &NoProgress,
    );
    film
}

#[test]
fn every_scene_renders_identically_with_both_engines() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut checked = 0;
    let mut differ = Vec::new();
    for rel in scene_files() {
        let text = std::fs::read_to_string(root.join(&rel)).unwrap();
        if !text.contains("<sensor") && !text.contains("<include") {
            continue;
        }
        for mut defines in variants(&text) {
            if text.contains("<default name=\"mesh\"") {
                defines.push(("mesh".into(), tiny_mesh().display().to_string()));
            }
            let opts = LoadOptions {
                defines: defines.clone(),
                spp: Some(2),
                seed: Some(7),
                // Wider than a tile and taller than a pool: tiles at the edge are partial and
                // the pool refills.
                resolution: Some((40, 36)),
            };
            let (mut scene, _) =
                load_scene(&root.join(&rel), &opts).unwrap_or_else(|e| panic!("{rel}: {e}"));
            let a = render_with(&scene, Engine::Scalar, 2);
            // Every instruction-set variant of the lanes this CPU runs (eight lanes with AVX2
            // or AVX-512, one lane on the baseline).
            for isa in Isa::ALL {
                if !scene.bvh.set_isa(isa) {
                    continue;
                }
                let b = render_with(&scene, Engine::Auto, 2);
                checked += 1;
                if a.pixels != b.pixels {
                    let n = a
                        .pixels
                        .iter()
                        .zip(&b.pixels)
                        .filter(|(x, y)| x != y)
                        .count();
                    differ.push(format!("{rel} {defines:?} {isa:?}: {n} pixels differ"));
                }
            }
        }
    }
    assert!(checked > 20, "only {checked} scene variants");
    assert!(differ.is_empty(), "{differ:#?}");
}
