//! Where paths start and end, in lanes: new jobs get their sampler state, wavelengths, filter
//! offset and camera ray ([`start`]); finished paths turn into XYZ ([`retire`]). Both follow
//! the scalar loop of [`crate::render`] operation for operation.

use super::pool::{Pool, POOL};
use super::vertex::{lanes, load_v3};
use crate::camera::Camera;
use crate::film::spectrum_to_xyz_lanes;
use crate::math::Vec2;
use crate::sampler::{SamplerKind, SamplerState};
use crate::scene::Scene;
use crate::simd::{Float, Int, Mask};
use crate::spectrum::cie::d65_lanes;
use crate::spectrum::SampledWavelengths;

/// The jobs of a tile's pass: each pixel of the tile (row-major) with its range of sample
/// indices, in that order.
pub(super) struct Jobs<'a> {
    x0: u32,
    y0: u32,
    width: u32,
    /// Per pixel, the sample indices of this pass.
    ranges: &'a [(u32, u32)],
    /// Per pixel, the index of its first job, and the job count at the end.
    pub first_job: Vec<u32>,
    /// The pixel of job `next` (jobs are started in order).
    pixel: usize,
    pub count: u32,
    pub next: u32,
}

impl<'a> Jobs<'a> {
    /// The jobs of the tile whose corner is (x0, y0) and rows `width` pixels wide.
    pub fn new(x0: u32, y0: u32, width: u32, ranges: &'a [(u32, u32)]) -> Jobs<'a> {
        let mut first_job = Vec::with_capacity(ranges.len() + 1);
        let mut count = 0u32;
        for &(a, b) in ranges {
            first_job.push(count);
            count += b - a;
        }
        first_job.push(count);
        Jobs {
            x0,
            y0,
            width,
            ranges,
            first_job,
            pixel: 0,
            count,
            next: 0,
        }
    }

    /// The pixel (within the tile) and sample index of job `job`, the next to start.
    #[inline]
    fn locate(&mut self, job: u32) -> (u32, u32) {
        while job >= self.first_job[self.pixel + 1] {
            self.pixel += 1;
        }
        let p = self.pixel;
        (p as u32, self.ranges[p].0 + job - self.first_job[p])
    }
}

/// Starts up to `F::LANES` new jobs at the end of the pool (fewer when the pool or the jobs
/// run out); returns how many.
#[inline(always)]
pub(super) fn start<F: Float>(
    scene: &Scene,
    kind: SamplerKind,
    pool: &mut Pool,
    jobs: &mut Jobs,
) -> usize {
    let k = F::LANES
        .min(POOL - pool.n)
        .min((jobs.count - jobs.next) as usize);
    if k == 0 {
        return 0;
    }
    let base = pool.n;
    let mut u = [[0.0f32; 16]; 5];
    let mut px = [[0.0f32; 16]; 2];
    let lens = scene.camera.needs_aperture_sample();
    for i in 0..k {
        let job = jobs.next + i as u32;
        let (pixel, sample) = jobs.locate(job);
        let (x, y) = (jobs.x0 + pixel % jobs.width, jobs.y0 + pixel / jobs.width);
        let mut st = SamplerState::start(scene.sampler.seed, x, y, sample);
        // As `render::render_tile`: filter offset and lens point (rows 0–3), then the
        // wavelengths (row 4), from the next set if there is a lens.
        for row in u.iter_mut().take(if lens { 4 } else { 2 }) {
            row[i] = st.next_1d(kind);
        }
        if lens {
            st.start_set();
        }
        u[4][i] = st.next_1d(kind);
        st.end_camera();
        pool.set_sampler_state(base + i, &st);
        pool.job[base + i] = job;
        px[0][i] = x as f32 + 0.5;
        px[1][i] = y as f32 + 0.5;
    }
    jobs.next += k as u32;
    let (lambda, pdf) = SampledWavelengths::sample_visible_lanes(F::load(&u[4]));
    for j in 0..4 {
        lambda[j].store_at(&mut pool.lambda[j][..], base);
        pdf[j].store_at(&mut pool.wl_pdf[j][..], base);
        d65_lanes(lambda[j]).store_at(&mut pool.d65[j][..], base);
    }
    let ox = scene.filter.sample_1d_lanes(F::load(&u[0]));
    let oy = scene.filter.sample_1d_lanes(F::load(&u[1]));
    let fx = (F::load(&px[0]) + ox) * F::splat(1.0 / scene.width as f32);
    let fy = (F::load(&px[1]) + oy) * F::splat(1.0 / scene.height as f32);
    let (o, d, t_max) = match &scene.camera {
        Camera::Perspective(c) => c.generate_ray_lanes(fx, fy),
        cam => {
            // Other cameras, lane by lane.
            let mut r = [[0.0f32; 16]; 7];
            for i in 0..k {
                let lens = if lens {
                    Vec2::new(u[2][i], u[3][i])
                } else {
                    Vec2::splat(0.5)
                };
                let ray = cam.generate_ray(Vec2::new(fx.lane(i), fy.lane(i)), lens);
                for a in 0..3 {
                    r[a][i] = ray.o[a];
                    r[3 + a][i] = ray.d[a];
                }
                r[6][i] = ray.t_max;
            }
            (load_v3(&r, 0), load_v3(&r, 3), F::load(&r[6]))
        }
    };
    // A new path ([`crate::integrator::path::PathState::new`]).
    let (zero, one) = (F::splat(0.0), F::splat(1.0));
    for a in 0..3 {
        let (oa, da) = match a {
            0 => (o.x, d.x),
            1 => (o.y, d.y),
            _ => (o.z, d.z),
        };
        oa.store_at(&mut pool.o[a][..], base);
        da.store_at(&mut pool.d[a][..], base);
        oa.store_at(&mut pool.prev_p[a][..], base);
        zero.store_at(&mut pool.prev_n[a][..], base);
    }
    t_max.store_at(&mut pool.t_max[..], base);
    for j in 0..4 {
        zero.store_at(&mut pool.l[j][..], base);
        one.store_at(&mut pool.beta[j][..], base);
    }
    one.store_at(&mut pool.eta_scale[..], base);
    zero.store_at(&mut pool.prev_pdf[..], base);
    zero.store_at(&mut pool.path_length[..], base);
    F::I::splat(1).store_at(&mut pool.specular[..], base);
    F::I::splat(0).store_at(&mut pool.depth[..], base);
    F::I::splat(0).store_at(&mut pool.null_crossings[..], base);
    pool.n += k;
    k
}

/// Writes the XYZ value of the finished paths `dead` (pool indices, at most `F::LANES`) to
/// their jobs' slots in `results`.
#[inline(always)]
pub(super) fn retire<F: Float>(pool: &Pool, dead: &[u32], results: &mut [[f32; 3]]) {
    let mut idx = [0u32; 16];
    idx[..dead.len()].copy_from_slice(dead);
    let idx = F::I::load(&idx);
    let l: [F; 4] = spec!(k => F::gather(&pool.l[k][..], idx));
    let lambda: [F; 4] = spec!(k => F::gather(&pool.lambda[k][..], idx));
    let pdf: [F; 4] = spec!(k => F::gather(&pool.wl_pdf[k][..], idx));
    // NaN and infinities never reach the film.
    let finite = l[0].is_finite() & l[1].is_finite() & l[2].is_finite() & l[3].is_finite();
    let zero = F::splat(0.0);
    let l = spec!(k => F::select(finite, l[k], zero));
    let xyz = spectrum_to_xyz_lanes(&l, &lambda, &pdf);
    for i in lanes(F::M::from_bits((1u32 << dead.len()) - 1).bits()) {
        let job = pool.job[dead[i] as usize] as usize;
        results[job] = [xyz[0].lane(i), xyz[1].lane(i), xyz[2].lane(i)];
    }
}
