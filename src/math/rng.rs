//! PCG32 random number generator (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
//! Statistically Good Algorithms for Random Number Generation").

use glam::Vec2;

const MULT: u64 = 0x5851_f42d_4c95_7f2d;

/// A small, fast, seedable generator with independent streams.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// A generator for sequence index `seq` started from `seed`.
    pub fn new(seed: u64, seq: u64) -> Pcg32 {
        let mut r = Pcg32 {
            state: 0,
            inc: (seq << 1) | 1,
        };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }

    /// The generator with this raw state and increment (as [`Pcg32::raw`] returns them).
    #[inline]
    pub(crate) fn from_raw(state: u64, inc: u64) -> Pcg32 {
        Pcg32 { state, inc }
    }

    /// The raw state and increment.
    #[inline]
    pub(crate) fn raw(&self) -> (u64, u64) {
        (self.state, self.inc)
    }

    /// Next 32 random bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform float in [0, 1).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        // 24 high-quality bits give an exactly representable value below 1.
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Two uniform floats in [0, 1).
    #[inline]
    pub fn next_vec2(&mut self) -> Vec2 {
        let a = self.next_f32();
        Vec2::new(a, self.next_f32())
    }
}

/// Mixes 64 bits into a well-distributed hash (splitmix64 finaliser).
#[inline]
pub fn mix64(mut x: u64) -> u64 {
    x ^= x >> 30;
    x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x ^= x >> 27;
    x = x.wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

#[cfg(test)]
/// Uniform f64s in [0, 1) with 53 random bits each, from a [`mix64`] chain started at `seed`:
/// a stream for tests that need more precision than [`Pcg32::next_f32`].
pub(crate) fn uniform_f64s(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed = mix64(seed);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_mean_and_range() {
        let mut r = Pcg32::new(42, 54);
        let n = 100_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let x = r.next_f32();
            assert!((0.0..1.0).contains(&x));
            sum += x as f64;
        }
        // Mean of U(0,1) has σ = sqrt(1/12/n); allow 4σ.
        let sigma = (1.0 / 12.0 / n as f64).sqrt();
        assert!((sum / n as f64 - 0.5).abs() < 4.0 * sigma);
    }

    #[test]
    fn streams_differ() {
        let mut a = Pcg32::new(1, 1);
        let mut b = Pcg32::new(1, 2);
        let same = (0..64).filter(|_| a.next_u32() == b.next_u32()).count();
        assert!(same < 4);
    }
}
