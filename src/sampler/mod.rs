//! Sample generators: independent uniform (PCG32) and Owen-scrambled Sobol (Burley 2020,
//! "Practical Hash-based Owen Scrambling", JCGT 9(4): the `sobol_burley` crate's values, four
//! dimensions at a time from tables in `sets.rs`).
//!
//! Every pixel sample starts from a state derived only from (seed, pixel, sample index), so an
//! image is bit-identical whatever the number of threads or the order of tiles.
//!
//! ## Dimensions come in sets of four
//!
//! A pixel sample's dimensions are grouped in sets of four, and the integrators draw so that
//! each 2D sample takes the first two dimensions of a set ([`SamplerState::start_set`] skips to
//! the next one). The layout: set 0 the camera's filter offset and lens point (a pinhole's
//! wavelengths in the lens's place), set 1 a lens camera's wavelengths, then two sets per path
//! vertex — the light sample (its 2D point, then the light choice) and the BSDF sample (2D
//! point, lobe choice, Russian roulette).
//!
//! The first four sets — the camera and the first vertex, whose decisions matter most and
//! whose integrand over pixel, lens, wavelength and first bounce together is smooth — are
//! dimensions of one Owen-scrambled Sobol sequence, so they are stratified jointly. Which
//! Sobol dimensions they take is chosen by the 2D projections' t-values (a (t, m, 2)-net for
//! 2^m points puts 2^t points in each elementary interval of area 2^(t−m); t = 0 is perfect
//! stratification): dimensions taken in order would give the first BSDF sample dimensions 7
//! and 8, whose 16 points have t = 3 — on the thin-film benchmark sphere the noise per
//! sample was higher at 16 spp than at 8 (relVar × spp 0.0089 vs 0.0076). The pairs chosen
//! have t ≤ 1 up to 32 points and ≤ 3 up to 128, but for the lens point, which takes Sobol
//! dimensions 2–3 beside the filter offset for their joint stratification (t = 2 at 8 points)
//! (`FIRST_SETS`; the test `first_sets_pairs_are_well_stratified` checks it).
//!
//! Later sets are *padded* (Kollig & Keller 2002, "Efficient multidimensional sampling";
//! Burley 2020, §4): each is the sequence's first four dimensions with the sample index
//! shuffled and the points scrambled by a hash of the pixel and the set, so every set has the
//! sequence's best projections — its first two dimensions a (0, 2)-sequence — and sets are
//! independent of one another, to any path depth (the crate's 256 dimensions do not limit
//! it). Measured on the thin-film benchmark sphere (`bench/noise.py`, 96², relVar × spp,
//! before → after): plastic coat 0.0088 → 0.0036 at 16 spp, 0.0023 → 0.0024 at 64, 0.0018 →
//! 0.00095 at 256; random walk 0.019 → 0.0095 at 16, 0.0050 → 0.0044 at 256; smooth coat
//! equal; the flagship 0.239 → 0.220 at 16 spp, level at 64. Padding every set instead lost
//! the joint stratification: 1.15–1.27× the noise at 256 spp for the walk and the smooth
//! coat; a lens point away from the filter offset cost the flagship 4–9 % at 64 spp.

mod sets;

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

// sobol_burley supports 2^16 samples per seed.
const SOBOL_MAX_INDEX: u32 = 1 << 16;

/// The Sobol dimensions of the first sets' dimensions (see the module notes). The camera's
/// set: filter offset (0, 1), then the lens point (2, 3) — the sequence's first four
/// dimensions, stratified jointly as in Cycles' tabulated sets — or, for a pinhole, the
/// wavelengths (2; stratified jointly with the filter offset: placing them elsewhere cost the
/// smooth film coat 1.5× the noise at 64 spp). A lens camera's wavelengths 9, from the second
/// set. The first vertex: light point (8, 11) and choice 10; BSDF point (4, 6), lobe 5,
/// roulette 7. The rest (12–15) are drawn by no integrator today. A permutation of 0–15, so
/// the sequence's first four sets of four hold them, and each of the first vertex's sets lies
/// in one of those (one `sample_4d` each: a path computes three sets for its camera and first
/// vertex, as many as the dimensions taken in order did).
const FIRST_SETS: [u32; 16] = [0, 1, 2, 3, 9, 12, 13, 14, 8, 11, 10, 15, 4, 6, 5, 7];

/// The dimension a path's first vertex starts at: the camera takes the first two sets.
pub(crate) const CAMERA_DIMS: u32 = 8;

/// What a sampler carries from one draw to the next within a pixel sample: the PCG stream,
/// the pixel's seed, the sample index and the next dimension. The wavefront integrator keeps
/// one per path and draws from it directly.
///
/// Sobol values are computed a set of four dimensions at a time (`sets::sample_4d`, the
/// values of `sobol_burley::sample_4d` from tables);
/// the set last computed is kept here, so consecutive draws from one state share it. It is a cache only: [`SamplerState::parts`]
/// leaves it out and [`SamplerState::from_parts`] starts without it, and equality ignores it.
#[derive(Clone, Copy, Debug)]
pub struct SamplerState {
    rng: Pcg32,
    pixel_seed: u32,
    index: u32,
    dim: u32,
    /// Which four dimensions `sobol` holds (see [`SamplerState::next_1d`]), or [`NO_SET`].
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
            SamplerKind::Sobol if self.index < SOBOL_MAX_INDEX => {
                // Which four Sobol dimensions hold this one, under which seed; `key` names
                // them for the cache (the first sets' are the sequence's sets 0–3, FIRST_SETS
                // being a permutation of dimensions 0–15; padded sets are numbered from 4).
                let (key, sobol_set, comp, seed) = match FIRST_SETS.get(self.dim as usize) {
                    Some(&d) => (d / 4, d / 4, d % 4, self.pixel_seed),
                    None => {
                        let set = self.dim / 4;
                        (set, 0, self.dim % 4, self.set_seed(set))
                    }
                };
                if key != self.sobol_set {
                    self.sobol = sets::sample_4d(self.index, sobol_set, seed);
                    self.sobol_set = key;
                }
                let v = self.sobol[comp as usize];
                self.dim += 1;
                v.min(crate::math::ONE_MINUS_EPSILON)
            }
            _ => {
                self.dim += 1;
                self.rng.next_f32()
            }
        }
    }

    /// The scrambling seed of the pixel's set of dimensions `set`: the index shuffle and the
    /// Owen scramble of that set (see the module notes).
    #[inline]
    fn set_seed(&self, set: u32) -> u32 {
        mix64((self.pixel_seed as u64) << 32 | set as u64) as u32
    }

    /// Skips to the first dimension of the next set of four (nothing if the current dimension
    /// starts one), so that the next 2D sample is a set's best-stratified pair.
    #[inline]
    pub fn start_set(&mut self) {
        self.dim = self.dim.next_multiple_of(4);
    }

    /// Skips the rest of the camera's sets: the first vertex starts at [`CAMERA_DIMS`].
    #[inline]
    pub fn end_camera(&mut self) {
        self.dim = self.dim.max(CAMERA_DIMS);
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

    /// Skips to the next set of four dimensions (see [`SamplerState::start_set`]).
    #[inline]
    pub fn start_set(&mut self) {
        self.st.start_set();
    }

    /// Skips the rest of the camera's sets (see [`SamplerState::end_camera`]).
    #[inline]
    pub fn end_camera(&mut self) {
        self.st.end_camera();
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
    fn sobol_values_are_the_sequences_by_the_layout() {
        // The first sets are the listed dimensions of the pixel's sequence, later sets
        // sobol_burley's first four dimensions under the set's own seed (a cached set also for a
        // state rebuilt from its parts in the middle of a set, as the wavefront pool does
        // between draws); padded sets differ from one another.
        let mut st = SamplerState::start(5, 7, 3, 11);
        let (_, _, seed, index, _) = st.parts();
        let mut firsts = Vec::new();
        for d in 0..56 {
            if d % 3 == 1 {
                st = SamplerState::from_parts(st.parts());
            }
            let want = if d < 16 {
                sobol_burley::sample(index, FIRST_SETS[d as usize], seed)
            } else {
                sobol_burley::sample(index, d % 4, st.set_seed(d / 4))
            };
            let v = st.next_1d(SamplerKind::Sobol);
            let want = want.min(crate::math::ONE_MINUS_EPSILON);
            assert_eq!(v.to_bits(), want.to_bits(), "dimension {d}");
            if d >= 16 && d % 4 == 0 {
                firsts.push(v.to_bits());
            }
        }
        firsts.sort_unstable();
        firsts.dedup();
        assert_eq!(firsts.len(), 10, "padded sets gave repeated values");
    }

    /// The smallest t for which the points are a (t, m, 2)-net: every elementary interval of
    /// area 2^(t − m) holds 2^t of the 2^m points.
    fn t_value(pts: &[(f32, f32)]) -> u32 {
        let m = pts.len().trailing_zeros();
        (0..=m)
            .find(|&t| {
                (0..=m - t).all(|a| {
                    let (nx, ny) = (1u32 << a, 1u32 << (m - t - a));
                    let mut count = vec![0u32; (nx * ny) as usize];
                    for &(x, y) in pts {
                        count[((x * nx as f32) as u32 * ny + (y * ny as f32) as u32) as usize] += 1;
                    }
                    count.iter().all(|&c| c == 1 << t)
                })
            })
            .unwrap()
    }

    /// The first 2^m samples of pixel (10, 20) at dimensions `d` and `d + 1`.
    fn pair(d: u32, m: u32) -> Vec<(f32, f32)> {
        (0..1u32 << m)
            .map(|i| {
                let mut st = SamplerState::start(3, 10, 20, i);
                st.dim = d;
                (
                    st.next_1d(SamplerKind::Sobol),
                    st.next_1d(SamplerKind::Sobol),
                )
            })
            .collect()
    }

    #[test]
    fn first_sets_pairs_are_well_stratified() {
        // Filter offset, lens, light point, BSDF point: t ≤ 1 up to 32 samples, ≤ 3 up to 128
        // (the unpadded order gave the BSDF point t = 3 at 16). The filter offset is perfect.
        for d in [0u32, 2, 8, 12] {
            for m in 1..=7u32 {
                let t = t_value(&pair(d, m));
                // The lens point (2, 3) has t = 2 at 8 points: it is chosen for its joint
                // stratification with the filter offset (the first four dimensions together).
                let limit = match (d, m) {
                    (0, _) => 0,
                    (2, 3) => 2,
                    (_, 1..=5) => 1,
                    _ => 3,
                };
                assert!(
                    t <= limit,
                    "dimensions {d}–{}: t = {t} for {} points",
                    d + 1,
                    1 << m
                );
            }
        }
        // The old order's BSDF point (dimensions 7–8 taken in order) for contrast: the test
        // can fail.
        let old: Vec<(f32, f32)> = (0..16)
            .map(|i| (sobol_burley::sample(i, 7, 9), sobol_burley::sample(i, 8, 9)))
            .collect();
        assert_eq!(t_value(&old), 3);
    }

    #[test]
    fn padded_sets_pairs_are_perfectly_stratified() {
        // The first two dimensions of any padded set, over the first 2^m samples of a pixel,
        // form a (0, m, 2)-net, also deep in a path.
        for set in [4u32, 5, 40, 300] {
            for m in 1..=7u32 {
                assert_eq!(
                    t_value(&pair(4 * set, m)),
                    0,
                    "set {set}, {} points",
                    1 << m
                );
            }
        }
    }

    #[test]
    fn start_set_skips_to_the_next_multiple_of_four() {
        let mut st = SamplerState::start(1, 2, 3, 4);
        st.start_set();
        assert_eq!(st.parts().4, 0);
        st.next_1d(SamplerKind::Sobol);
        st.start_set();
        assert_eq!(st.parts().4, 4);
        for _ in 0..4 {
            st.next_1d(SamplerKind::Independent);
        }
        st.start_set();
        assert_eq!(st.parts().4, 8);
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
