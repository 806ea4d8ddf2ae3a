//! Quick renders for tools and tests: a scene file at a given size and sample count, as an
//! image in memory.

use crate::image_io::RgbImage;
use crate::render::{render, NoProgress, RenderOptions};
use crate::scene::build::{load_scene, LoadOptions};
use crate::scene::mitsuba::SceneError;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// Renders a scene file with `-D` values at `res` × `res` pixels, `spp` samples and seed 0.
/// Warnings are returned beside the image.
pub fn render_file(
    path: &Path,
    defines: &[(String, String)],
    resolution: (u32, u32),
    spp: u32,
) -> Result<(RgbImage, Vec<String>), SceneError> {
    let opts = LoadOptions {
        defines: defines.to_vec(),
        spp: Some(spp),
        seed: Some(0),
        resolution: Some(resolution),
    };
    let (scene, warnings) = load_scene(path, &opts)?;
    let mut film = crate::film::Film::new(scene.width, scene.height);
    let ropts = RenderOptions {
        spp: scene.sampler.spp,
        time_limit: None,
        strategy: crate::integrator::PathStrategy::Mis,
        engine: crate::render::Engine::Auto,
    };
    render(
        &scene,
        &mut film,
        0,
        &ropts,
        &AtomicBool::new(false),
        &NoProgress,
    );
    let image = RgbImage {
        width: film.width as usize,
        height: film.height as usize,
        data: film.to_linear_srgb(),
    };
    Ok((image, warnings.iter().map(|w| w.to_string()).collect()))
}
