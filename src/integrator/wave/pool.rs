//! The paths in flight, structure of arrays: one array per field, so that lanes load and store
//! consecutive paths at once. Every array is [`CAP`] long (the pool plus a chunk of padding, so
//! that a chunk starting at any live path stays in bounds); the first `n` entries are live,
//! in no particular order.

use crate::accel::RawHit;
use crate::integrator::path::PathState;
use crate::light::LightSampleContext;
use crate::math::{Ray, Vec3};
use crate::sampler::SamplerState;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Most paths in flight per tile. Fewer rounds of larger batches: against 1024
/// (`bench/ab.py --threads 2 --pairs 8 --spp 64`, images bit for bit the same, CPU time) the
/// Cornell box 1.035× (standard error 0.005), the 1M-triangle mesh 1.010× (0.003), the
/// smooth-film sphere 1.034× (0.011), the plastic-coated sphere and the flagship level (1.005×,
/// 1.001×); 4096 level with 2048 on the box, 512 2.8 % slower on the mesh. About 0.5 MB of
/// columns per thread.
pub const POOL: usize = 2048;
/// Array length: the pool and a chunk of the widest lanes.
pub(super) const CAP: usize = POOL + 16;

/// Hit shape index of a ray that escaped.
pub(super) const MISS: u32 = u32::MAX;

/// One field of every path: an array of constant length, so that an index checked once
/// against [`CAP`] needs no further bounds checks.
pub(super) type Col<T> = Box<[T; CAP]>;

/// Four arrays, one per wavelength.
pub(super) type Spectra = [Col<f32>; 4];

fn col<T: Copy>(v: T) -> Col<T> {
    Box::new([v; CAP])
}

fn spectra() -> Spectra {
    std::array::from_fn(|_| col(0.0))
}

/// Applies the macro `$op` to every per-path column of the pool `$p` but the hit and `alive`:
/// the one list that moving ([`Pool::move_path`]) and exchanging paths (`group.rs`) go by, so
/// that neither can miss a field.
macro_rules! path_columns {
    ($p:expr, $op:ident) => {{
        for a in 0..3 {
            $op!($p.o[a]);
            $op!($p.d[a]);
            $op!($p.prev_p[a]);
            $op!($p.prev_n[a]);
        }
        for k in 0..4 {
            $op!($p.l[k]);
            $op!($p.beta[k]);
            $op!($p.lambda[k]);
            $op!($p.wl_pdf[k]);
            $op!($p.d65[k]);
        }
        $op!($p.t_max);
        $op!($p.eta_scale);
        $op!($p.prev_pdf);
        $op!($p.env_by_bsdf);
        $op!($p.path_length);
        $op!($p.specular);
        $op!($p.depth);
        $op!($p.null_crossings);
        $op!($p.rng_state);
        $op!($p.rng_inc);
        $op!($p.pixel_seed);
        $op!($p.sample_index);
        $op!($p.dim);
        $op!($p.job);
    }};
}
pub(super) use path_columns;

/// The live paths; see the module header.
pub(super) struct Pool {
    /// Number of live paths.
    pub n: usize,
    pub o: [Col<f32>; 3],
    pub d: [Col<f32>; 3],
    pub t_max: Col<f32>,
    pub l: Spectra,
    pub beta: Spectra,
    pub lambda: Spectra,
    pub wl_pdf: Spectra,
    /// D65 at the path's wavelengths (for RGB emission), looked up once per path.
    pub d65: Spectra,
    pub eta_scale: Col<f32>,
    pub prev_pdf: Col<f32>,
    /// [`PathState::env_by_bsdf`] (1: true).
    pub env_by_bsdf: Col<u32>,
    pub path_length: Col<f32>,
    pub specular: Col<u32>,
    pub depth: Col<u32>,
    pub null_crossings: Col<u32>,
    pub prev_p: [Col<f32>; 3],
    pub prev_n: [Col<f32>; 3],
    /// Each path's sampler state ([`SamplerState::parts`]), field by field.
    pub rng_state: Col<u64>,
    pub rng_inc: Col<u64>,
    pub pixel_seed: Col<u32>,
    pub sample_index: Col<u32>,
    pub dim: Col<u32>,
    /// Index of the job (pixel sample) in the tile's pass.
    pub job: Col<u32>,
    /// Whether the path goes on after this round (1) or ends (0).
    pub alive: Col<u32>,
    /// This round's closest hit, as the traversal returned it.
    pub hit: Col<Option<RawHit>>,
    /// The hit's shape ([`MISS`] for an escaped ray), primitive, parameter and coordinates.
    pub h_shape: Col<u32>,
    pub h_prim: Col<u32>,
    pub h_t: Col<f32>,
    pub h_u: Col<f32>,
    pub h_v: Col<f32>,
    pub h_block: Col<u32>,
    pub h_lane: Col<u32>,
}

fn v3() -> [Col<f32>; 3] {
    std::array::from_fn(|_| col(0.0))
}

impl Pool {
    pub fn new() -> Pool {
        Pool {
            n: 0,
            o: v3(),
            d: v3(),
            t_max: col(0.0),
            l: spectra(),
            beta: spectra(),
            lambda: spectra(),
            wl_pdf: spectra(),
            d65: spectra(),
            eta_scale: col(0.0),
            prev_pdf: col(0.0),
            env_by_bsdf: col(0),
            path_length: col(0.0),
            specular: col(0),
            depth: col(0),
            null_crossings: col(0),
            prev_p: v3(),
            prev_n: v3(),
            rng_state: col(0),
            rng_inc: col(0),
            pixel_seed: col(0),
            sample_index: col(0),
            dim: col(0),
            job: col(0),
            alive: col(0),
            hit: col(None),
            h_shape: col(MISS),
            h_prim: col(0),
            h_t: col(0.0),
            h_u: col(0.0),
            h_v: col(0.0),
            h_block: col(0),
            h_lane: col(0),
        }
    }

    /// Path `i`'s ray.
    #[inline]
    pub fn ray(&self, i: usize) -> Ray {
        Ray {
            o: Vec3::new(self.o[0][i], self.o[1][i], self.o[2][i]),
            d: Vec3::new(self.d[0][i], self.d[1][i], self.d[2][i]),
            t_max: self.t_max[i],
        }
    }

    /// Copies the fields of the live paths' hits (in `hit`) to their own arrays.
    pub fn spread_hits(&mut self) {
        let n = self.n;
        let hits = &self.hit[..n];
        let (shape, prim) = (&mut self.h_shape[..n], &mut self.h_prim[..n]);
        let (t, u, v) = (&mut self.h_t[..n], &mut self.h_u[..n], &mut self.h_v[..n]);
        let (block, lane) = (&mut self.h_block[..n], &mut self.h_lane[..n]);
        for i in 0..n {
            match &hits[i] {
                None => shape[i] = MISS,
                Some(h) => {
                    shape[i] = h.hit.shape;
                    prim[i] = h.hit.prim;
                    t[i] = h.hit.t;
                    u[i] = h.hit.uv.x;
                    v[i] = h.hit.uv.y;
                    block[i] = h.block;
                    lane[i] = h.lane;
                }
            }
        }
    }

    /// Path `i`'s wavelengths.
    #[inline]
    pub fn wavelengths(&self, i: usize) -> SampledWavelengths {
        // The D65 values computed in lanes at the camera (the same operations as `cie::d65`).
        SampledWavelengths {
            lambda: std::array::from_fn(|k| self.lambda[k][i]),
            pdf: std::array::from_fn(|k| self.wl_pdf[k][i]),
            d65: std::array::from_fn(|k| self.d65[k][i]),
        }
    }

    /// Path `i`'s sampler state.
    #[inline]
    pub fn sampler_state(&self, i: usize) -> SamplerState {
        SamplerState::from_parts((
            self.rng_state[i],
            self.rng_inc[i],
            self.pixel_seed[i],
            self.sample_index[i],
            self.dim[i],
        ))
    }

    /// Sets path `i`'s sampler state.
    #[inline]
    pub fn set_sampler_state(&mut self, i: usize, st: &SamplerState) {
        (
            self.rng_state[i],
            self.rng_inc[i],
            self.pixel_seed[i],
            self.sample_index[i],
            self.dim[i],
        ) = st.parts();
    }

    /// Path `i` as the scalar estimator's state.
    pub fn load_path(&self, i: usize) -> PathState {
        let spec = |a: &Spectra| SampledSpectrum(std::array::from_fn(|k| a[k][i]));
        let v = |a: &[Col<f32>; 3]| Vec3::new(a[0][i], a[1][i], a[2][i]);
        PathState {
            ray: self.ray(i),
            l: spec(&self.l),
            beta: spec(&self.beta),
            eta_scale: self.eta_scale[i],
            specular_bounce: self.specular[i] != 0,
            prev_pdf: self.prev_pdf[i],
            env_by_bsdf: self.env_by_bsdf[i] != 0,
            prev_ctx: LightSampleContext {
                p: v(&self.prev_p),
                n: v(&self.prev_n),
            },
            depth: self.depth[i],
            null_crossings: self.null_crossings[i],
            path_length: self.path_length[i],
        }
    }

    /// Writes the scalar estimator's state back as path `i`.
    pub fn store_path(&mut self, i: usize, p: &PathState) {
        for a in 0..3 {
            self.o[a][i] = p.ray.o[a];
            self.d[a][i] = p.ray.d[a];
            self.prev_p[a][i] = p.prev_ctx.p[a];
            self.prev_n[a][i] = p.prev_ctx.n[a];
        }
        self.t_max[i] = p.ray.t_max;
        for k in 0..4 {
            self.l[k][i] = p.l[k];
            self.beta[k][i] = p.beta[k];
        }
        self.eta_scale[i] = p.eta_scale;
        self.specular[i] = p.specular_bounce as u32;
        self.prev_pdf[i] = p.prev_pdf;
        self.env_by_bsdf[i] = p.env_by_bsdf as u32;
        self.depth[i] = p.depth;
        self.null_crossings[i] = p.null_crossings;
        self.path_length[i] = p.path_length;
    }

    /// Copies every per-path field of `from` to `to` (compaction; hits are not kept).
    fn move_path(&mut self, from: usize, to: usize) {
        // Checked once: every column has length CAP.
        assert!(from < CAP && to < CAP);
        macro_rules! mv {
            ($a:expr) => {
                $a[to] = $a[from]
            };
        }
        path_columns!(self, mv);
    }

    /// Removes the paths at the indices `gone` (ascending), filling each hole with the last
    /// live path (only removed paths cost a move, and no removed path is moved); `also` copies
    /// what [`Pool::move_path`] does not and the next step needs. The caller has the list
    /// already (it retired those paths): walking it instead of testing every path spares a
    /// branch per path that goes either way at random.
    fn remove(&mut self, gone: &[u32], also: impl Fn(&mut Pool, usize, usize)) {
        debug_assert!(gone.windows(2).all(|w| w[0] < w[1]));
        debug_assert!(gone.last().is_none_or(|&g| (g as usize) < self.n));
        let (mut lo, mut hi) = (0, gone.len());
        // Invariant: gone[lo..hi] are the removed paths still below `n`.
        while lo < hi {
            let last = self.n - 1;
            self.n = last;
            if gone[hi - 1] as usize == last {
                hi -= 1;
            } else {
                let hole = gone[lo] as usize;
                self.move_path(last, hole);
                also(self, last, hole);
                lo += 1;
            }
        }
    }

    /// Removes the paths whose ray escaped, `gone` (after tracing, before shading), their
    /// hits kept.
    pub fn remove_escaped(&mut self, gone: &[u32]) {
        self.remove(gone, |p, from, to| p.hit[to] = p.hit[from]);
    }

    /// Removes the paths that ended, `gone` (after shading).
    pub fn compact(&mut self, gone: &[u32]) {
        self.remove(gone, |p, from, to| p.alive[to] = p.alive[from]);
    }
}
