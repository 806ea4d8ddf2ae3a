//! Sample generators: independent uniform (PCG32) and Owen-scrambled Sobol (Burley 2020,
//! "Practical Hash-based Owen Scrambling", JCGT 9(4), via the `sobol_burley` crate).
//!
//! Every pixel sample starts from a state derived only from (seed, pixel, sample index), so an
//! image is bit-identical whatever the number of threads or the order of tiles.

use crate::math::rng::mix64;
use crate::math::{Pcg32, Vec2};

/// Which sequence to draw from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    /// Mitsuba's `independent`.
    Independent,
    /// Owen-scrambled Sobol (accepted for Mitsuba's `stratified`, `multijitter`, `ldsampler`,
    /// `orthogonal` and `sobol`-like names: they all ask for a low-discrepancy sequence).
    Sobol,
}

// sobol_burley supports 256 dimensions and 2^16 samples per seed.
const SOBOL_DIMS: u32 = 256;
const SOBOL_MAX_INDEX: u32 = 1 << 16;

/// What a sampler carries from one draw to the next within a pixel sample: the PCG stream,
/// the pixel's seed, the sample index and the next dimension. The wavefront integrator keeps
/// one per path and draws from it directly.
///
/// Sobol values are computed four dimensions at a time (`sobol_burley::sample_4d`, the same
/// numbers as four calls of `sample` for about the cost of one); the set last computed is kept
/// here, so consecutive draws from one state share it. It is a cache only: [`SamplerState::parts`]
/// leaves it out and [`SamplerState::from_parts`] starts without it, and equality ignores it.
#[derive(Clone, Copy, Debug)]
pub struct SamplerState {
    rng: Pcg32,
    pixel_seed: u32,
    index: u32,
    dim: u32,
    /// Which four dimensions `sobol` holds (`dim / 4`), or [`NO_SET`].
    sobol_set: u32,
    sobol: [f32; 4],
}

/// `SamplerState::sobol_set` when no Sobol values are cached.
const NO_SET: u32 = u32::MAX;

impl PartialEq for SamplerState {
    fn eq(&self, o: &SamplerState) -> bool {
        self.parts() == o.parts()
    }
}

impl Eq for SamplerState {}

impl SamplerState {
    /// The state of sample `index` of pixel (x, y) under the global `seed`.
    #[inline]
    pub fn start(seed: u64, x: u32, y: u32, index: u32) -> SamplerState {
        let pix = mix64(seed ^ mix64(((y as u64) << 32) | x as u64));
        SamplerState {
            rng: Pcg32::new(pix, index as u64),
            pixel_seed: pix as u32,
            index,
            dim: 0,
            sobol_set: NO_SET,
            sobol: [0.0; 4],
        }
    }

    /// The state as (PCG state, PCG increment, pixel seed, sample index, dimension), the form
    /// the wavefront integrator stores per path.
    #[inline]
    pub(crate) fn parts(&self) -> (u64, u64, u32, u32, u32) {
        let (state, inc) = self.rng.raw();
        (state, inc, self.pixel_seed, self.index, self.dim)
    }

    /// The state from [`SamplerState::parts`].
    #[inline]
    pub(crate) fn from_parts(
        (state, inc, pixel_seed, index, dim): (u64, u64, u32, u32, u32),
    ) -> SamplerState {
        SamplerState {
            rng: Pcg32::from_raw(state, inc),
            pixel_seed,
            index,
            dim,
            sobol_set: NO_SET,
            sobol: [0.0; 4],
        }
    }

    /// Next 1D sample in [0, 1) of the sequence `kind`.
    #[inline]
    pub fn next_1d(&mut self, kind: SamplerKind) -> f32 {
        match kind {
            SamplerKind::Sobol if self.dim < SOBOL_DIMS && self.index < SOBOL_MAX_INDEX => {
                let set = self.dim / 4;
                if set != self.sobol_set {
                    self.sobol = sobol_burley::sample_4d(self.index, set, self.pixel_seed);
                    self.sobol_set = set;
                }
                let v = self.sobol[(self.dim % 4) as usize];
                self.dim += 1;
                v.min(crate::math::ONE_MINUS_EPSILON)
            }
            _ => {
                self.dim += 1;
                self.rng.next_f32()
            }
        }
    }

    /// A seed for the stochastic BSDFs at the current path vertex: a hash of the pixel
    /// sample and the dimensions drawn so far, so it differs from vertex to vertex without
    /// consuming any of the sampler's numbers.
    #[inline]
    pub fn vertex_seed(&self) -> u64 {
        mix64(((self.pixel_seed as u64) << 32 | self.index as u64) ^ mix64(self.dim as u64 + 1))
    }
}

/// A per-thread sampler.
#[derive(Clone, Debug)]
pub struct Sampler {
    kind: SamplerKind,
    seed: u64,
    st: SamplerState,
}

impl Sampler {
    /// A sampler of the given kind with a global `seed`.
    pub fn new(kind: SamplerKind, seed: u64) -> Sampler {
        Sampler {
            kind,
            seed,
            st: SamplerState {
                rng: Pcg32::new(seed, 0),
                pixel_seed: 0,
                index: 0,
                dim: 0,
                sobol_set: NO_SET,
                sobol: [0.0; 4],
            },
        }
    }

    /// A sampler continuing the pixel sample whose state is `st`.
    #[inline]
    pub fn resume(kind: SamplerKind, seed: u64, st: SamplerState) -> Sampler {
        Sampler { kind, seed, st }
    }

    /// The sequence this sampler draws from.
    #[inline]
    pub fn kind(&self) -> SamplerKind {
        self.kind
    }

    /// The current pixel sample's state.
    #[inline]
    pub fn state(&self) -> SamplerState {
        self.st
    }

    /// Continues a pixel sample from its state (see [`Sampler::state`]).
    #[inline]
    pub fn set_state(&mut self, s: SamplerState) {
        self.st = s;
    }

    /// Prepares sample `index` of pixel (x, y).
    #[inline]
    pub fn start_pixel_sample(&mut self, x: u32, y: u32, index: u32) {
        self.st = SamplerState::start(self.seed, x, y, index);
    }

    /// A seed for the stochastic BSDFs at the current path vertex (see
    /// [`SamplerState::vertex_seed`]).
    #[inline]
    pub fn vertex_seed(&self) -> u64 {
        self.st.vertex_seed()
    }

    /// Next 1D sample in [0, 1).
    #[inline]
    pub fn get_1d(&mut self) -> f32 {
        self.st.next_1d(self.kind)
    }

    /// Next 2D sample in [0, 1)².
    #[inline]
    pub fn get_2d(&mut self) -> Vec2 {
        let a = self.get_1d();
        Vec2::new(a, self.get_1d())
    }
}

// The plugins: each sampler's manual, declaration and loader (the sequences are above).
pub(crate) mod independent;
pub(crate) mod sobol;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_pixel_sample_gives_same_numbers() {
        for kind in [SamplerKind::Independent, SamplerKind::Sobol] {
            let mut a = Sampler::new(kind, 9);
            let mut b = Sampler::new(kind, 9);
            a.start_pixel_sample(3, 4, 17);
            let _ = a.get_2d();
            b.start_pixel_sample(1, 1, 0);
            let _ = b.get_1d();
            b.start_pixel_sample(3, 4, 17);
            a.start_pixel_sample(3, 4, 17);
            for _ in 0..10 {
                assert_eq!(a.get_1d(), b.get_1d());
            }
        }
    }

    #[test]
    fn sobol_four_at_a_time_are_the_single_dimension_values() {
        // The cached set of four must give what sobol_burley::sample gives dimension by
        // dimension, also for a state rebuilt from its parts in the middle of a set (as the
        // wavefront pool does between draws).
        let mut st = SamplerState::start(5, 7, 3, 11);
        let (_, _, seed, index, _) = st.parts();
        for d in 0..40 {
            if d % 3 == 1 {
                st = SamplerState::from_parts(st.parts());
            }
            let v = st.next_1d(SamplerKind::Sobol);
            let want = sobol_burley::sample(index, d, seed).min(crate::math::ONE_MINUS_EPSILON);
            assert_eq!(v.to_bits(), want.to_bits(), "dimension {d}");
        }
    }

    #[test]
    fn sobol_first_dimension_is_stratified() {
        // 64 consecutive Sobol points fall one per 1/64 stratum.
        let mut s = Sampler::new(SamplerKind::Sobol, 1);
        let mut seen = [false; 64];
        for i in 0..64 {
            s.start_pixel_sample(5, 6, i);
            seen[(s.get_1d() * 64.0) as usize] = true;
        }
        assert!(seen.iter().all(|&b| b));
    }
}
