//! The wavefront integrator: many paths of a tile advanced together, one vertex at a time, so
//! that rays are traced in batches.
//!
//! # How the data flows
//!
//! A tile's pass is a list of jobs, one per (pixel, sample index), in the order the scalar
//! loop takes them. A pool of at most [`POOL`] live paths is kept full from that list; each
//! round of the loop
//!
//! 1. **refills** the pool: new jobs draw their wavelengths, filter offset and lens sample
//!    and get their camera ray, exactly as [`crate::render`]'s scalar loop does;
//! 2. **traces** every live path's ray in one batch ([`crate::accel::Bvh`]);
//! 3. **shades** each path with the estimator of [`super::path`] ([`PathState::escape`] or
//!    [`PathState::scatter`]), which hands back its shadow ray instead of tracing it;
//! 4. **traces the shadow rays** in one batch and adds the contributions of the unoccluded ones;
//! 5. **retires** the paths that ended, writing their XYZ value to their job's slot, and
//!    compacts the pool, keeping its order (new camera rays stay together at its end).
//!
//! Every path draws from its own sampler state and follows the same operations as in
//! [`super::path::radiance`], and each pixel's samples are summed in sample order at the end,
//! so the tile is bit-identical to the scalar loop's.

use super::path::{PathConfig, PathState, PathStrategy};
use crate::film::spectrum_to_xyz;
use crate::math::{Ray, Vec2};
use crate::sampler::Sampler;
use crate::scene::Scene;
use crate::shape::SurfaceInteraction;
use crate::spectrum::SampledWavelengths;

/// Most paths in flight per tile.
pub const POOL: usize = 1024;

/// Whether the wavefront integrator can render `scene` with `strategy` (the `path` integrator,
/// without AOVs).
pub fn supports(scene: &Scene) -> bool {
    scene.integrator.aov.is_none()
        && matches!(scene.integrator.kind, crate::scene::IntegratorKind::Path)
}

/// One live path.
struct Slot {
    path: PathState,
    sampler: Sampler,
    wl: SampledWavelengths,
    /// Index of the job (pixel and sample) in the tile's pass.
    job: u32,
}

/// Renders samples [s0, s1) of every pixel of the tile whose corner is (x0, y0) and extent
/// (x1, y1); returns per-pixel sums (X, Y, Z, count), row-major.
pub fn render_tile(
    scene: &Scene,
    (x0, y0): (u32, u32),
    (x1, y1): (u32, u32),
    (s0, s1): (u32, u32),
    strategy: PathStrategy,
) -> Vec<[f64; 4]> {
    let cfg = PathConfig::new(scene, strategy);
    let (tw, th) = (x1 - x0, y1 - y0);
    let spp = s1 - s0;
    let jobs = tw * th * spp;
    let mut results = vec![[0.0f32; 3]; jobs as usize];
    let inv = Vec2::new(1.0 / scene.width as f32, 1.0 / scene.height as f32);
    let mut sampler = Sampler::new(scene.sampler.kind, scene.sampler.seed);

    let mut pool: Vec<Slot> = Vec::with_capacity(POOL);
    let mut rays: Vec<Ray> = Vec::with_capacity(POOL);
    let mut hits: Vec<Option<SurfaceInteraction>> = Vec::with_capacity(POOL);
    let mut alive: Vec<bool> = Vec::with_capacity(POOL);
    let mut shadow_rays: Vec<Ray> = Vec::with_capacity(POOL);
    let mut shadow_of: Vec<(u32, crate::spectrum::SampledSpectrum)> = Vec::with_capacity(POOL);
    let mut blocked: Vec<bool> = Vec::with_capacity(POOL);
    let mut next = 0u32;

    loop {
        // 1. Refill.
        while pool.len() < POOL && next < jobs {
            let job = next;
            next += 1;
            let pixel = job / spp;
            let (x, y) = (x0 + pixel % tw, y0 + pixel / tw);
            let s = s0 + job % spp;
            sampler.start_pixel_sample(x, y, s);
            let wl = SampledWavelengths::sample_visible(sampler.get_1d());
            let offset = scene.filter.sample(sampler.get_2d());
            let film_p = (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset) * inv;
            let lens = if scene.camera.needs_aperture_sample() {
                sampler.get_2d()
            } else {
                Vec2::splat(0.5)
            };
            let ray = scene.camera.generate_ray(film_p, lens);
            pool.push(Slot {
                path: PathState::new(ray),
                sampler: sampler.clone(),
                wl,
                job,
            });
        }
        if pool.is_empty() {
            break;
        }

        // 2. Trace.
        rays.clear();
        rays.extend(pool.iter().map(|s| s.path.ray));
        hits.clear();
        hits.resize(pool.len(), None);
        scene
            .bvh
            .intersect_interaction_n(&scene.shapes, &rays, &mut hits);

        // 3. Shade.
        alive.clear();
        shadow_rays.clear();
        shadow_of.clear();
        for (i, (slot, hit)) in pool.iter_mut().zip(&hits).enumerate() {
            let Some(si) = hit else {
                slot.path.escape(scene, &cfg, &slot.wl);
                alive.push(false);
                continue;
            };
            let (go_on, shadow) = slot
                .path
                .scatter(scene, &cfg, &slot.wl, si, &mut slot.sampler);
            if let Some(s) = shadow {
                shadow_rays.push(s.ray);
                shadow_of.push((i as u32, s.contribution));
            }
            alive.push(go_on);
        }

        // 4. Shadow rays.
        blocked.clear();
        blocked.resize(shadow_rays.len(), false);
        scene
            .bvh
            .occluded_n(&scene.shapes, &shadow_rays, &mut blocked);
        for (&(i, c), &b) in shadow_of.iter().zip(&blocked) {
            if !b {
                pool[i as usize].path.l += c;
            }
        }

        // 5. Retire and compact.
        let mut k = 0;
        pool.retain(|slot| {
            let keep = alive[k];
            k += 1;
            if !keep {
                results[slot.job as usize] = spectrum_to_xyz(&slot.path.radiance(), &slot.wl);
            }
            keep
        });
    }

    // Per-pixel sums in sample order, as the scalar loop adds them.
    results
        .chunks(spp as usize)
        .map(|samples| {
            let mut acc = [0.0f64; 4];
            for xyz in samples {
                acc[0] += xyz[0] as f64;
                acc[1] += xyz[1] as f64;
                acc[2] += xyz[2] as f64;
                acc[3] += 1.0;
            }
            acc
        })
        .collect()
}
