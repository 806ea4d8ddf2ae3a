//! The render loop: passes of samples over tiles on a rayon pool, with progress reporting, a
//! time budget and cancellation.
//!
//! Determinism: every pixel sample draws from a sampler state fixed by (seed, pixel, sample
//! index), each pixel belongs to exactly one tile, and the pass schedule depends only on the
//! sample count, so the film's sums are bit-identical whatever the number of threads.

use crate::film::{spectrum_to_xyz, Film};
use crate::integrator::{radiance, PathStrategy};
use crate::math::Vec2;
use crate::sampler::Sampler;
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Tile edge in pixels.
pub const TILE: u32 = 32;

/// What to render and when to stop.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Target samples per pixel.
    pub spp: u32,
    /// Stop starting new tiles after this long; the image is normalised per pixel.
    pub time_limit: Option<Duration>,
    /// Estimator combination (MIS by default).
    pub strategy: PathStrategy,
}

/// Progress events for a user interface.
pub trait Progress: Sync {
    /// `done` of `total` samples are finished.
    fn update(&self, done: u64, total: u64);
}

/// No progress output.
pub struct NoProgress;
impl Progress for NoProgress {
    fn update(&self, _: u64, _: u64) {}
}

/// How a render ended.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderStats {
    /// Samples per pixel completed by every pixel.
    pub spp_complete: u32,
    /// Total samples taken.
    pub samples: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Whether the render stopped before the target (time budget or cancellation).
    pub stopped_early: bool,
}

/// The pass schedule: sample-index ranges, growing so that early passes give quick feedback and
/// later ones amortise scheduling. A function of `spp` alone, for determinism.
pub fn pass_schedule(start: u32, spp: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let mut s = 0u32;
    let mut size = 1u32;
    while s < spp {
        let e = (s + size).min(spp);
        if e > start {
            out.push((s.max(start), e));
        }
        s = e;
        size = (size * 2).min(16);
    }
    out
}

/// Renders into `film` (which may already hold `start_spp` samples per pixel, e.g. when
/// resuming), until `opts.spp`, the time limit, or `cancel` is set.
pub fn render(
    scene: &Scene,
    film: &mut Film,
    start_spp: u32,
    opts: &RenderOptions,
    cancel: &AtomicBool,
    progress: &dyn Progress,
) -> RenderStats {
    let t0 = Instant::now();
    let (w, h) = (scene.width, scene.height);
    let tiles: Vec<(u32, u32)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..w.div_ceil(TILE)).map(move |tx| (tx * TILE, ty * TILE)))
        .collect();
    let total = w as u64 * h as u64 * opts.spp.saturating_sub(start_spp) as u64;
    let done = AtomicU64::new(0);
    let stop = AtomicBool::new(false);
    let mut spp_complete = start_spp;
    let mut stopped_early = false;

    for (s0, s1) in pass_schedule(start_spp, opts.spp) {
        let results: Vec<Option<((u32, u32), Vec<[f64; 4]>)>> = tiles
            .par_iter()
            .map(|&(x0, y0)| {
                if cancel.load(Ordering::Relaxed) || stop.load(Ordering::Relaxed) {
                    return None;
                }
                if let Some(limit) = opts.time_limit {
                    if t0.elapsed() >= limit {
                        stop.store(true, Ordering::Relaxed);
                        return None;
                    }
                }
                let acc = render_tile(scene, x0, y0, s0, s1, opts.strategy);
                let n = acc.len() as u64 * (s1 - s0) as u64;
                let d = done.fetch_add(n, Ordering::Relaxed) + n;
                progress.update(d, total);
                Some(((x0, y0), acc))
            })
            .collect();
        let mut complete = true;
        for r in results {
            match r {
                Some(((x0, y0), acc)) => add_tile(film, x0, y0, &acc),
                None => complete = false,
            }
        }
        if complete {
            spp_complete = s1;
        } else {
            stopped_early = true;
            break;
        }
    }
    RenderStats {
        spp_complete,
        samples: done.load(Ordering::Relaxed),
        seconds: t0.elapsed().as_secs_f64(),
        stopped_early,
    }
}

fn tile_extent(scene: &Scene, x0: u32, y0: u32) -> (u32, u32) {
    ((x0 + TILE).min(scene.width), (y0 + TILE).min(scene.height))
}

/// Renders samples [s0, s1) of every pixel in a tile; returns per-pixel sums (X, Y, Z, count).
fn render_tile(
    scene: &Scene,
    x0: u32,
    y0: u32,
    s0: u32,
    s1: u32,
    strategy: PathStrategy,
) -> Vec<[f64; 4]> {
    let (x1, y1) = tile_extent(scene, x0, y0);
    let mut sampler = Sampler::new(scene.sampler.kind, scene.sampler.seed);
    let inv = Vec2::new(1.0 / scene.width as f32, 1.0 / scene.height as f32);
    let mut out = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
    for y in y0..y1 {
        for x in x0..x1 {
            let mut acc = [0.0f64; 4];
            for s in s0..s1 {
                sampler.start_pixel_sample(x, y, s);
                let wl = SampledWavelengths::sample_visible(sampler.get_1d());
                let offset = scene.filter.sample(sampler.get_2d());
                let film_p = (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset) * inv;
                let ray = scene.camera.generate_ray(film_p);
                let l = radiance(scene, ray, &wl, &mut sampler, strategy);
                let xyz = spectrum_to_xyz(&l, &wl);
                acc[0] += xyz[0] as f64;
                acc[1] += xyz[1] as f64;
                acc[2] += xyz[2] as f64;
                acc[3] += 1.0;
            }
            out.push(acc);
        }
    }
    out
}

fn add_tile(film: &mut Film, x0: u32, y0: u32, acc: &[[f64; 4]]) {
    let x1 = (x0 + TILE).min(film.width);
    let y1 = (y0 + TILE).min(film.height);
    let mut i = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            let p = &mut film.pixels[(y * film.width + x) as usize];
            for c in 0..4 {
                p[c] += acc[i][c];
            }
            i += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedule_covers_range_without_gaps() {
        for (start, spp) in [(0, 1), (0, 100), (7, 64), (64, 64), (3, 5)] {
            let sched = pass_schedule(start, spp);
            let mut s = start.min(spp);
            for (a, b) in &sched {
                assert_eq!(*a, s);
                assert!(b > a);
                s = *b;
            }
            assert_eq!(s, spp.max(start.min(spp)));
        }
    }

    #[test]
    fn resumed_schedule_is_a_suffix_of_the_full_one() {
        let full = pass_schedule(0, 200);
        let cut = full[4].0;
        assert_eq!(pass_schedule(cut, 200), full[4..].to_vec());
    }
}
