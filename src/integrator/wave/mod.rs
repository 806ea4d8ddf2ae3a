//! The wavefront integrator: the paths of a tile advanced together, one vertex at a time, rays
//! traced in batches and the common vertices shaded in SIMD lanes.
//!
//! # How the data flows
//!
//! A tile's pass is a list of jobs, one per (pixel, sample index), in the order the scalar
//! loop takes them (each pixel its own range of sample indices, which differ from pixel to
//! pixel in an adaptive render). A [`pool::Pool`] of at most [`POOL`] live paths, stored as one array per
//! field, is kept full from that list; each round
//!
//! 1. **refills** the pool: new jobs draw their wavelengths, filter offset and lens sample
//!    and get their camera ray, exactly as [`crate::render`]'s scalar loop does;
//! 2. **traces** every live path's ray in one batch, handed over as the pool's columns
//!    ([`crate::accel::Bvh::intersect_raw_columns`], sixteen rays to a SIMD packet);
//!    where the scene has no infinite light, paths whose ray escaped end here (they are
//!    retired and removed, as in step 5), and the others are **grouped** by what they hit
//!    (`group.rs`), so that a chunk of lanes mostly runs one material's code;
//! 3. **shades** the pool in chunks of lanes ([`vertex::shade_chunk`]): hits that
//!    [`program::Program`] marks (the materials and lights the lanes implement) run the vertex
//!    in lanes, the rest run the scalar estimator ([`PathState::escape`] /
//!    [`PathState::scatter`]) path by path; both hand back shadow rays instead of tracing them;
//! 4. **traces the shadow rays** in one batch (kept as columns too) and adds the contributions
//!    of unoccluded ones;
//! 5. **retires** the paths that ended, writing their XYZ value to their job's slot, and
//!    fills each hole with the last live path.
//!
//! A stopwatch ([`stages`]) charges each step's time to it, for `ophis render --stats`.
//!
//! The lanes compute what the scalar code computes, operation for operation (see
//! [`crate::simd`]), every path draws from its own sampler state in the scalar order, and each
//! pixel's samples are summed in sample order at the end: a tile is bit-identical to the
//! scalar loop's, which `tests/wavefront.rs` checks on every scene.
//!
//! Lanes are sixteen wide on CPUs with AVX-512, eight with AVX2 (chosen at run time like the
//! accelerator's traversal) and one elsewhere.

/// `[e(0), e(1), e(2), e(3)]` for an expression `e` of `k`. Not a closure: a closure is
/// compiled as a function of its own, without the caller's instruction set, and unless it
/// is inlined every lane operation inside it becomes a call.
macro_rules! spec {
    ($k:ident => $e:expr) => {
        [
            {
                let $k = 0;
                $e
            },
            {
                let $k = 1;
                $e
            },
            {
                let $k = 2;
                $e
            },
            {
                let $k = 3;
                $e
            },
        ]
    };
}

mod bsdf;
mod ends;
mod group;
mod lookup;
mod nee;
mod pool;
pub mod program;
pub mod stages;
mod surface;
mod vertex;

pub use pool::POOL;
pub use program::Program as WaveProgram;

use super::path::{PathConfig, PathStrategy};
use crate::accel::{Isa, RayColumns};
use crate::math::Ray;
use crate::render::TileSums;
use crate::scene::Scene;
use crate::simd::Float;
use crate::spectrum::SampledSpectrum;
use pool::Pool;
use program::Program;
use stages::Stage;
use vertex::Ctx;

/// Whether the wavefront integrator can render `scene` (the `path` integrator, without AOVs).
pub fn supports(scene: &Scene) -> bool {
    scene.integrator.aov.is_none()
        && matches!(scene.integrator.kind, crate::scene::IntegratorKind::Path)
}

/// The shadow rays of a round: the path each belongs to, the ray (as columns, which the
/// packets load straight into lanes), and the radiance it adds when unoccluded. A round has
/// at most one shadow ray per path, so each column holds [`POOL`].
pub(super) struct Shadows {
    n: usize,
    slot: Box<[u32; POOL]>,
    o: [Box<[f32; POOL]>; 3],
    d: [Box<[f32; POOL]>; 3],
    t_max: Box<[f32; POOL]>,
    contribution: Box<[SampledSpectrum; POOL]>,
    blocked: Vec<bool>,
}

impl Shadows {
    fn new() -> Shadows {
        let col = || Box::new([0.0; POOL]);
        Shadows {
            n: 0,
            slot: Box::new([0; POOL]),
            o: [col(), col(), col()],
            d: [col(), col(), col()],
            t_max: col(),
            contribution: Box::new([SampledSpectrum::splat(0.0); POOL]),
            blocked: Vec::with_capacity(POOL),
        }
    }

    #[inline(always)]
    pub(super) fn push(&mut self, slot: u32, ray: Ray, c: SampledSpectrum) {
        let k = self.n;
        assert!(k < POOL, "more shadow rays than paths in a round");
        self.slot[k] = slot;
        self.o[0][k] = ray.o.x;
        self.o[1][k] = ray.o.y;
        self.o[2][k] = ray.o.z;
        self.d[0][k] = ray.d.x;
        self.d[1][k] = ray.d.y;
        self.d[2][k] = ray.d.z;
        self.t_max[k] = ray.t_max;
        self.contribution[k] = c;
        self.n = k + 1;
    }

    fn len(&self) -> usize {
        self.n
    }

    fn clear(&mut self) {
        self.n = 0;
    }

    /// Sets `blocked` for every ray.
    fn trace(&mut self, scene: &Scene) {
        let n = self.n;
        let columns = RayColumns {
            o: [&self.o[0][..], &self.o[1][..], &self.o[2][..]],
            d: [&self.d[0][..], &self.d[1][..], &self.d[2][..]],
            t_max: &self.t_max[..],
            n,
        };
        self.blocked.clear();
        self.blocked.resize(n, false);
        scene
            .bvh
            .occluded_columns(&scene.shapes, &columns, &mut self.blocked);
    }
}

/// A thread's path pool and shadow-ray columns, kept from one tile to the next of the same
/// render (the program `id`): made anew for every tile, their 250 kB were returned to the
/// system at each tile's end and their pages faulted in and cleared again at the next (the
/// Cornell box at 128 spp: 13,300 page faults, 2,600 with the buffers kept; 1.023× as fast on
/// two threads, standard error 0.008). Not kept across renders: what a pool
/// holds beyond its live paths is left over from earlier paths, which the code never reads
/// as such, but which need not be valid for another scene.
struct Buffers {
    id: u64,
    pool: Pool,
    shadows: Shadows,
}

thread_local! {
    static BUFFERS: std::cell::Cell<Option<Box<Buffers>>> = const { std::cell::Cell::new(None) };
}

impl Buffers {
    /// This thread's buffers if the last tile it rendered was `prog`'s, emptied; else new ones.
    fn take(prog: &Program) -> Box<Buffers> {
        match BUFFERS.with(|b| b.take()) {
            Some(mut b) if b.id == prog.id => {
                b.pool.n = 0;
                b.shadows.clear();
                b
            }
            _ => Box::new(Buffers {
                id: prog.id,
                pool: Pool::new(),
                shadows: Shadows::new(),
            }),
        }
    }

    /// Keeps `pool` and `shadows` for this thread's next tile of `prog`.
    fn keep(prog: &Program, pool: Pool, shadows: Shadows) {
        let b = Buffers {
            id: prog.id,
            pool,
            shadows,
        };
        BUFFERS.with(|c| c.set(Some(Box::new(b))));
    }
}

/// Sets `out` to the indices below `n` for which `pick` holds, in order. Without branches:
/// which paths escaped or ended is as good as random, and a filter's mispredicted branch per
/// path cost more than writing every index and advancing over the picked ones.
#[inline(always)]
fn select(out: &mut Vec<u32>, n: usize, pick: impl Fn(usize) -> bool) {
    out.clear();
    out.resize(n, 0);
    let mut k = 0;
    for i in 0..n {
        out[k] = i as u32;
        k += pick(i) as usize;
    }
    out.truncate(k);
}

/// Renders the samples `ranges` (a range of sample indices per pixel, row-major) of the tile
/// with corner (x0, y0) and far corner (x1, y1) (exclusive); returns per-pixel sums (X, Y, Z,
/// count, Y²), row-major.
pub fn render_tile(
    scene: &Scene,
    prog: &Program,
    corner: (u32, u32),
    far: (u32, u32),
    ranges: &[(u32, u32)],
    strategy: PathStrategy,
) -> Vec<TileSums> {
    #[cfg(target_arch = "x86_64")]
    {
        // `run` with lanes `$lanes`, compiled for the instruction set `$features`.
        macro_rules! entry {
            ($name:ident, $lanes:ty, $features:literal) => {
                #[target_feature(enable = $features)]
                fn $name(
                    s: &Scene,
                    p: &Program,
                    c: (u32, u32),
                    f: (u32, u32),
                    n: &[(u32, u32)],
                    st: PathStrategy,
                ) -> Vec<TileSums> {
                    run::<$lanes>(s, p, c, f, n, st)
                }
            };
        }
        entry!(avx2, crate::simd::F8, "avx2,fma,bmi1,bmi2,lzcnt,popcnt");
        entry!(
            avx512,
            crate::simd::F16,
            "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi1,bmi2,lzcnt,popcnt"
        );
        match scene.bvh.isa() {
            // SAFETY: the BVH only holds an instruction set the CPU supports (`Isa::best`,
            // `Bvh::set_isa`).
            Isa::Avx512 => return unsafe { avx512(scene, prog, corner, far, ranges, strategy) },
            Isa::Avx2 => return unsafe { avx2(scene, prog, corner, far, ranges, strategy) },
            Isa::Baseline => {}
        }
    }
    run::<f32>(scene, prog, corner, far, ranges, strategy)
}

/// The rounds of [`render_tile`] with lanes of type `F`.
#[inline(always)]
fn run<F: Float>(
    scene: &Scene,
    prog: &Program,
    (x0, y0): (u32, u32),
    (x1, y1): (u32, u32),
    ranges: &[(u32, u32)],
    strategy: PathStrategy,
) -> Vec<TileSums> {
    let ctx = Ctx {
        scene,
        prog,
        cfg: PathConfig::new(scene, strategy),
        kind: scene.sampler.kind,
    };
    debug_assert_eq!(ranges.len() as u32, (x1 - x0) * (y1 - y0));
    let mut jobs = ends::Jobs::new(x0, y0, x1 - x0, ranges);
    let mut results = vec![[0.0f32; 3]; jobs.count as usize];
    let Buffers {
        mut pool,
        mut shadows,
        ..
    } = *Buffers::take(prog);
    let mut dead: Vec<u32> = Vec::with_capacity(POOL);
    let mut scratch = vertex::Scratch::new();
    let mut clock = stages::Clock::new();

    loop {
        // 1. Refill.
        while ends::start::<F>(scene, ctx.kind, &mut pool, &mut jobs) > 0 {}
        if pool.n == 0 {
            break;
        }
        let n = pool.n;
        let traced = n;
        clock.lap(Stage::Refill);

        // 2. Trace (and group the paths by what they hit).
        let columns = RayColumns {
            o: [&pool.o[0][..], &pool.o[1][..], &pool.o[2][..]],
            d: [&pool.d[0][..], &pool.d[1][..], &pool.d[2][..]],
            t_max: &pool.t_max[..],
            n,
        };
        scene
            .bvh
            .intersect_raw_columns(&scene.shapes, &columns, &mut pool.hit[..n]);
        if prog.big_meshes {
            surface::prefetch_meshes(&scene.shapes, &pool.hit[..n], false);
        }
        // With nothing beyond the scene an escaped path ends with what it has: it leaves now,
        // so that the chunks shaded next hold only paths with work to do.
        if scene.infinite_lights.is_empty() {
            select(&mut dead, n, |i| pool.hit[i].is_none());
            for chunk in dead.chunks(F::LANES) {
                ends::retire::<F>(&pool, chunk, &mut results);
            }
            if !dead.is_empty() {
                pool.remove_escaped(&dead);
            }
        }
        let n = pool.n;
        clock.lap(Stage::Trace);
        pool.group(&prog.shape_class);
        pool.spread_hits();
        if prog.big_meshes {
            surface::prefetch_meshes(&scene.shapes, &pool.hit[..n], true);
        }
        clock.lap(Stage::Group);

        // 3. Shade.
        shadows.clear();
        for base in (0..n).step_by(F::LANES) {
            vertex::shade_chunk::<F>(&ctx, &mut pool, base, &mut shadows, &mut scratch);
        }
        clock.lap(Stage::Shade);

        // 4. Shadow rays.
        shadows.trace(scene);
        let m = shadows.len();
        for ((&i, c), &b) in shadows.slot[..m]
            .iter()
            .zip(&shadows.contribution[..m])
            .zip(&shadows.blocked)
        {
            if !b {
                for k in 0..4 {
                    pool.l[k][i as usize] += c[k];
                }
            }
        }

        clock.lap(Stage::Shadow);
        clock.count(traced, shadows.len());

        // 5. Retire and compact.
        select(&mut dead, n, |i| pool.alive[i] == 0);
        for chunk in dead.chunks(F::LANES) {
            ends::retire::<F>(&pool, chunk, &mut results);
        }
        pool.compact(&dead);
        clock.lap(Stage::Retire);
    }

    Buffers::keep(prog, pool, shadows);
    // Per-pixel sums in sample order, as the scalar loop adds them.
    jobs.first_job
        .windows(2)
        .map(|j| {
            let mut acc = [0.0f64; 5];
            for xyz in &results[j[0] as usize..j[1] as usize] {
                acc[0] += xyz[0] as f64;
                acc[1] += xyz[1] as f64;
                acc[2] += xyz[2] as f64;
                acc[3] += 1.0;
                acc[4] += xyz[1] as f64 * xyz[1] as f64;
            }
            acc
        })
        .collect()
}
