//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod scenes;

use ophis::film::Film;
use ophis::integrator::PathStrategy;
use ophis::render::{render, NoProgress, RenderOptions};
use ophis::scene::build::{load_scene_str, LoadOptions};
use ophis::scene::Scene;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// Builds a scene from XML text; panics with the loader's message on error.
pub fn scene(xml: &str) -> Scene {
    match load_scene_str(xml, Path::new("test.xml"), &LoadOptions::default()) {
        Ok((s, _)) => s,
        Err(e) => panic!("scene failed to load: {e}"),
    }
}

/// Renders a scene with the given strategy; returns linear sRGB pixels.
pub fn render_rgb(scene: &Scene, spp: u32, strategy: PathStrategy) -> Vec<[f32; 3]> {
    let mut film = Film::new(scene.width, scene.height);
    let opts = RenderOptions {
        spp,
        time_limit: None,
        strategy,
        engine: ophis::render::Engine::Auto,
    };
    render(
        scene,
        &mut film,
        0,
        &opts,
        &AtomicBool::new(false),
        &NoProgress,
    );
    film.to_linear_srgb()
}

/// Mean and standard error of a list of values (standard error from the sample variance).
pub fn mean_stderr(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}
