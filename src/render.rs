//! The render loop: passes of samples over tiles on a rayon pool, with progress reporting, a
//! time budget and cancellation.
//!
//! Determinism: every pixel sample draws from a sampler state fixed by (seed, pixel, sample
//! index), each pixel belongs to exactly one tile, and the pass schedule depends only on the
//! sample count, so the film's sums are bit-identical whatever the number of threads. An
//! adaptive render ([`adaptive`]) keeps this: its per-pixel counts are fixed once, from the
//! pilot's sums, and each pass takes a fixed range of every pixel's samples.
//!
//! Small images (fewer than [`SPLIT_BELOW`] tiles) render each tile's pass in quarters, so
//! that every thread has work until the pass ends; the first quarter of a tile to start
//! decides for all four whether the tile's pass runs (a cancelled render still finishes the
//! tiles it began), and checkpoints wait until no tile is half added, so a stopped film's
//! tiles each hold whole passes, as resuming and `ophis merge` expect.

pub mod adaptive;
mod units;

use crate::film::{spectrum_to_xyz, Film};
use crate::integrator::{aov, radiance, wave, PathStrategy};
use crate::math::Vec2;
use crate::sampler::Sampler;
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;
use adaptive::Adaptive;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use units::{work_units, Book, SPLIT_BELOW};

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
    /// Which implementation of the integrator runs.
    pub engine: Engine,
}

/// The implementation that renders a scene's paths. Both give the same image, bit for bit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Engine {
    /// The wavefront integrator ([`crate::integrator::wave`]) wherever it supports the scene,
    /// the scalar loop elsewhere.
    #[default]
    Auto,
    /// One path at a time ([`crate::integrator::path::radiance`]).
    Scalar,
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
    /// CPU seconds of the whole process over the render, all threads together (on a shared
    /// machine a steadier measure of the work than wall time; NaN where it cannot be read).
    pub cpu_seconds: f64,
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

/// The order in which tiles are handed to the workers. It changes which tiles are finished
/// first (and so what an interrupted render holds), never the sums of a completed pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TileOrder {
    /// Row by row from the top left.
    #[default]
    RowMajor,
    /// Row by row from the bottom right.
    Reversed,
    /// A pseudo-random permutation fixed by the seed.
    Shuffled(u64),
}

/// A checkpoint writer: called with the film between tiles.
pub type CheckpointFn<'a> = &'a (dyn Fn(&Film) + Sync);

/// Everything about a render that is not the image: stopping, progress, checkpoints.
pub struct RenderControl<'a> {
    /// Set (e.g. by a signal handler) to stop starting tiles; tiles in flight finish.
    pub cancel: &'a AtomicBool,
    /// Progress reporting.
    pub progress: &'a dyn Progress,
    /// Called with the film at most once per interval, between tiles, while no tile is being
    /// added: every tile then holds a whole number of passes, so the film is a valid state to
    /// resume from.
    pub checkpoint: Option<(Duration, CheckpointFn<'a>)>,
    /// Tile order.
    pub tile_order: TileOrder,
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
    let ctl = RenderControl {
        cancel,
        progress,
        checkpoint: None,
        tile_order: TileOrder::RowMajor,
    };
    render_with(scene, film, start_spp, opts, &ctl)
}

/// Tile origins in the requested order.
fn tiles(w: u32, h: u32, order: TileOrder) -> Vec<(u32, u32)> {
    let mut t: Vec<(u32, u32)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..w.div_ceil(TILE)).map(move |tx| (tx * TILE, ty * TILE)))
        .collect();
    match order {
        TileOrder::RowMajor => {}
        TileOrder::Reversed => t.reverse(),
        TileOrder::Shuffled(seed) => {
            let mut rng = crate::math::Pcg32::new(seed, 0);
            for i in (1..t.len()).rev() {
                let j = (rng.next_u32() as usize) % (i + 1);
                t.swap(i, j);
            }
        }
    }
    t
}

/// Samples per pixel a tile has finished (all pixels of a tile always finish the same passes):
/// its pixels' count, or in an adaptive render the nominal sample index its passes reached.
pub fn tile_spp(film: &Film, x0: u32, y0: u32) -> u32 {
    let i = (y0 * film.width + x0) as usize;
    match &film.adaptive {
        Some(a) => a.done[i],
        None => film.pixels[i][3] as u32,
    }
}

/// [`pass_schedule`] with the pass that holds the end of an adaptive render's pilot split
/// there, so that every pass lies wholly in the pilot or wholly after it.
fn schedule(start: u32, spp: u32, pilot: Option<u32>) -> Vec<(u32, u32)> {
    let mut passes = pass_schedule(start, spp);
    if let Some(p) = pilot {
        if let Some(k) = passes.iter().position(|&(a, b)| a < p && p < b) {
            let (a, b) = passes[k];
            passes[k] = (a, p);
            passes.insert(k + 1, (p, b));
        }
    }
    passes
}

/// Gives an empty film the adaptive state its scene asks for. A film that already holds
/// samples keeps what it has: a resumed render continues the way it started.
fn prepare_adaptive(scene: &Scene, film: &mut Film, spp: u32) {
    if scene.sampler.adaptive && film.adaptive.is_none() && film.total_weight() == 0.0 {
        film.adaptive = Adaptive::new(spp, film.pixels.len());
    }
}

/// Like [`render`], with checkpoints and a tile order. Each tile resumes from the samples the
/// film already holds for it, so an interrupted film (where some tiles finished a pass that
/// others had not started) continues exactly where it stopped: the same sample indices are
/// grouped into the same passes, and the sums are bit-identical to an uninterrupted render.
pub fn render_with(
    scene: &Scene,
    film: &mut Film,
    start_spp: u32,
    opts: &RenderOptions,
    ctl: &RenderControl,
) -> RenderStats {
    assert!(
        film.width == scene.width && film.height == scene.height,
        "film and scene resolutions differ"
    );
    prepare_aovs(scene, film);
    prepare_adaptive(scene, film, opts.spp);
    // An adaptive film's counts were planned for its own target.
    let spp = film.adaptive.as_ref().map_or(opts.spp, |a| a.spp);
    let pilot = film.adaptive.as_ref().map(|a| a.pilot);
    let t0 = Instant::now();
    let cpu0 = cpu_seconds(CpuClock::Process);
    let program = (opts.engine == Engine::Auto && wave::supports(scene))
        .then(|| wave::WaveProgram::new(scene));
    let (w, h) = (scene.width, scene.height);
    let tiles = tiles(w, h, ctl.tile_order);
    // The samples still to take (for progress): each pixel's target (spp until an adaptive
    // render's targets are known) less what it holds.
    let total: u64 = film
        .pixels
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let target = match &film.adaptive {
                Some(a) if !a.targets.is_empty() => a.targets[i],
                _ => spp,
            };
            (target as u64).saturating_sub((p[3] as u64).max(start_spp as u64))
        })
        .sum();
    let done = AtomicU64::new(0);
    let stop = AtomicBool::new(false);
    let mut stopped_early = false;
    // The film, when the last checkpoint was written, how many tiles are half added, and
    // whether a checkpoint fell due while some were.
    let shared = Mutex::new((film, Instant::now(), 0usize, false));
    // Small images: a tile's pass in quarters, so that each thread has several to take.
    let split = tiles.len() < SPLIT_BELOW;

    for (s0, s1) in schedule(start_spp, spp, pilot) {
        let (todo, plan): (Vec<((u32, u32), u32)>, _) = {
            let mut g = shared.lock().unwrap_or_else(|e| e.into_inner());
            let film = &mut *g.0;
            if let Some(a) = &film.adaptive {
                if s0 >= a.pilot && a.targets.is_empty() {
                    // Every pixel holds exactly the pilot now (no tile passes it before the
                    // targets exist).
                    let targets = adaptive::targets(film, a);
                    if let Some(a) = &mut film.adaptive {
                        a.targets = targets;
                    }
                }
            }
            let todo = tiles
                .iter()
                .map(|&t| (t, tile_spp(film, t.0, t.1).max(s0)))
                .filter(|&(_, from)| from < s1)
                .collect();
            (todo, film.adaptive.as_ref().map(Adaptive::plan))
        };
        let in_pilot = pilot.is_some_and(|p| s1 <= p);
        let missed = AtomicBool::new(false);
        let units = work_units(scene, &todo, split);
        let book = Book::new(todo.len(), &units);
        units.par_iter().for_each(|u| {
            let mut quit = ctl.cancel.load(Ordering::Relaxed) || stop.load(Ordering::Relaxed);
            if let Some(limit) = opts.time_limit {
                if !quit && t0.elapsed() >= limit {
                    stop.store(true, Ordering::Relaxed);
                    quit = true;
                }
            }
            if !book.start(u.tile, quit) {
                missed.store(true, Ordering::Relaxed);
                return;
            }
            let ((x0, y0), (x1, y1)) = (u.corner, u.far);
            let from = u.from;
            let ranges: Vec<(u32, u32)> = (y0..y1)
                .flat_map(|y| (x0..x1).map(move |x| (y * w + x) as usize))
                .map(|i| match &plan {
                    Some(a) => (a.samples_at(i, from), a.samples_at(i, s1)),
                    None => (from, s1),
                })
                .collect();
            let (acc, aov) = if let Some(prog) = &program {
                let acc =
                    wave::render_tile(scene, prog, (x0, y0), (x1, y1), &ranges, opts.strategy);
                (acc, Vec::new())
            } else {
                render_tile(scene, (x0, y0), (x1, y1), &ranges, opts.strategy)
            };
            let n: u64 = ranges.iter().map(|&(a, b)| (b - a) as u64).sum();
            let d = done.fetch_add(n, Ordering::Relaxed) + n;
            ctl.progress.update(d, total);
            let mut g = shared.lock().unwrap_or_else(|e| e.into_inner());
            add_tile(g.0, u.corner, u.far, &acc, s1, in_pilot);
            add_aov_tile(g.0, u.corner, u.far, &aov);
            // Under the lock: the count of tiles with some but not all units added.
            g.2 = g.2.wrapping_add_signed(book.added(u.tile));
            // A checkpoint only while no tile is half added (a resumed render takes up each
            // tile where all its pixels stand).
            if let Some((every, write)) = ctl.checkpoint {
                if g.1.elapsed() >= every {
                    if g.2 == 0 {
                        write(g.0);
                        g.1 = Instant::now();
                        g.3 = false;
                    } else {
                        g.3 = true;
                    }
                }
            }
        });
        // Between passes no tile is half added: write the checkpoint that fell due while some
        // were.
        if let Some((_, write)) = ctl.checkpoint {
            let mut g = shared.lock().unwrap_or_else(|e| e.into_inner());
            if g.3 {
                write(g.0);
                g.1 = Instant::now();
                g.3 = false;
            }
        }
        if missed.load(Ordering::Relaxed) {
            stopped_early = true;
            break;
        }
    }
    let film = shared.into_inner().unwrap_or_else(|e| e.into_inner()).0;
    let spp_complete = tiles
        .iter()
        .map(|&(x, y)| tile_spp(film, x, y))
        .min()
        .unwrap_or(0);
    RenderStats {
        spp_complete,
        samples: done.load(Ordering::Relaxed),
        seconds: t0.elapsed().as_secs_f64(),
        cpu_seconds: cpu_seconds(CpuClock::Process) - cpu0,
        stopped_early,
    }
}

/// Whose CPU time [`cpu_seconds`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CpuClock {
    /// All the threads of this process together.
    Process,
    /// The calling thread alone.
    Thread,
}

/// CPU seconds used so far by this process or thread (Linux 64-bit, via `clock_gettime`);
/// NaN elsewhere.
pub fn cpu_seconds(clock: CpuClock) -> f64 {
    #[cfg(all(target_os = "linux", target_pointer_width = "64"))]
    {
        #[repr(C)]
        struct Timespec {
            sec: i64,
            nsec: i64,
        }
        extern "C" {
            fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
        }
        // CLOCK_PROCESS_CPUTIME_ID and CLOCK_THREAD_CPUTIME_ID.
        let id = match clock {
            CpuClock::Process => 2,
            CpuClock::Thread => 3,
        };
        let mut ts = Timespec { sec: 0, nsec: 0 };
        // SAFETY: clock_gettime writes one timespec, which `ts` is.
        if unsafe { clock_gettime(id, &mut ts) } == 0 {
            return ts.sec as f64 + ts.nsec as f64 * 1e-9;
        }
    }
    let _ = clock;
    f64::NAN
}

/// Renders the samples `ranges` (one range of sample indices per pixel, row-major) of the
/// tile from corner (x0, y0) to far corner (x1, y1) (exclusive); returns per-pixel sums
/// [`TileSums`] and, with the `aov` integrator, the AOV channel sums.
fn render_tile(
    scene: &Scene,
    (x0, y0): (u32, u32),
    (x1, y1): (u32, u32),
    ranges: &[(u32, u32)],
    strategy: PathStrategy,
) -> (Vec<TileSums>, Vec<f64>) {
    let aov = scene.integrator.aov.as_ref();
    let n_aov = aov.map_or(0, |a| a.channels());
    let with_image = aov.is_none_or(|a| a.has_image);
    let mut aov_sums = vec![0.0f64; n_aov * ((x1 - x0) * (y1 - y0)) as usize];
    let mut sampler = Sampler::new(scene.sampler.kind, scene.sampler.seed);
    let inv = Vec2::new(1.0 / scene.width as f32, 1.0 / scene.height as f32);
    let mut out = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
    for y in y0..y1 {
        for x in x0..x1 {
            let mut acc = [0.0f64; 5];
            let (s0, s1) = ranges[out.len()];
            for s in s0..s1 {
                sampler.start_pixel_sample(x, y, s);
                // The camera's sets of dimensions: the filter offset, then the lens point
                // (drawn only by cameras with a lens) and the wavelengths from the next set,
                // or a pinhole's wavelengths in the lens's place.
                let offset = scene.filter.sample(sampler.get_2d());
                let lens = if scene.camera.needs_aperture_sample() {
                    let lens = sampler.get_2d();
                    sampler.start_set();
                    lens
                } else {
                    Vec2::splat(0.5)
                };
                let wl = SampledWavelengths::sample_visible(sampler.get_1d());
                sampler.end_camera();
                let film_p = (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset) * inv;
                let ray = scene.camera.generate_ray(film_p, lens);
                if let Some(a) = aov {
                    let px = out.len() * n_aov;
                    let key = aov::sample_key(scene.sampler.seed, x, y, s);
                    a.accumulate(scene, &ray, key, &mut aov_sums[px..px + n_aov]);
                }
                let l = if with_image {
                    radiance(scene, ray, &wl, &mut sampler, strategy)
                } else {
                    crate::spectrum::SampledSpectrum::ZERO
                };
                let xyz = spectrum_to_xyz(&l, &wl);
                acc[0] += xyz[0] as f64;
                acc[1] += xyz[1] as f64;
                acc[2] += xyz[2] as f64;
                acc[3] += 1.0;
                acc[4] += xyz[1] as f64 * xyz[1] as f64;
            }
            out.push(acc);
        }
    }
    (out, aov_sums)
}

/// Gives an empty film the scene's AOV channels; a film that already holds samples must have
/// them (callers that resume check this first).
fn prepare_aovs(scene: &Scene, film: &mut Film) {
    let names = scene
        .integrator
        .aov
        .as_ref()
        .map_or(Vec::new(), |a| a.channel_names());
    if film.aov_names != names {
        assert!(
            film.total_weight() == 0.0,
            "the film's AOV channels differ from the scene's"
        );
        *film = Film::with_aovs(film.width, film.height, names);
    }
}

/// Adds the AOV sums (see [`render_tile`]) of the pixels from `(x0, y0)` to `(x1, y1)`
/// (exclusive).
fn add_aov_tile(film: &mut Film, (x0, y0): (u32, u32), (x1, y1): (u32, u32), sums: &[f64]) {
    let n = film.aov_names.len();
    if n == 0 {
        return;
    }
    let row = ((x1 - x0) as usize) * n;
    for (k, y) in (y0..y1).enumerate() {
        let at = ((y * film.width + x0) as usize) * n;
        for (a, b) in film.aov[at..at + row].iter_mut().zip(&sums[k * row..]) {
            *a += b;
        }
    }
}

/// A pixel's sums over a tile's pass: X, Y, Z, the sample count, and Y² (which an adaptive
/// render's pilot keeps).
pub type TileSums = [f64; 5];

/// Adds the sums of the pixels from `(x0, y0)` to `(x1, y1)` (exclusive: a tile or a piece
/// of one) for the pass ending at (nominal) sample `s1`; `in_pilot` says the pass is part of
/// an adaptive render's pilot.
fn add_tile(
    film: &mut Film,
    (x0, y0): (u32, u32),
    (x1, y1): (u32, u32),
    acc: &[TileSums],
    s1: u32,
    in_pilot: bool,
) {
    let mut sums = acc.iter();
    for y in y0..y1 {
        for x in x0..x1 {
            let i = (y * film.width + x) as usize;
            let a = sums.next().expect("one sum per pixel of the tile");
            for (p, v) in film.pixels[i].iter_mut().zip(a) {
                *p += v;
            }
            if let Some(ad) = &mut film.adaptive {
                ad.done[i] = s1;
                if in_pilot {
                    ad.sq[i] += a[4];
                }
            }
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
