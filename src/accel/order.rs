//! The order in which a single-ray walk visits a node's children: nearest first, the others
//! pushed far to near ([`Vec8::far_first`]), and for occlusion the first child hit with the
//! others pushed in lane order ([`Vec8::first_and_rest`]).
//!
//! The trait's own versions (`simd.rs`) insert each child hit into a sorted list, branching on
//! the data at every child; whether a ray enters a child is as good as random, so those
//! branches mispredict. With AVX-512 ([`Avx8k`]) the eight keys (entry distance's bits above
//! the child reference; a child missed is zero) are sorted in one register by the optimal
//! 8-input network of 19 comparators in 6 layers (Knuth, *The Art of Computer Programming*
//! vol. 3, §5.3.4), each layer a permutation, a minimum, a maximum and a blend, and stored to
//! the stack at once; the nearest child comes from a masked minimum, off the sort's path. The
//! occlusion walk's children are compressed into place by one instruction. Same order, same
//! stack, bit for bit (`tests` below against a plain sort).
#![cfg(target_arch = "x86_64")]

use super::simd::{Avx8, Vec8};
use std::arch::x86_64::*;
use std::mem::MaybeUninit;

/// `fn $f(self, o: Self) -> Self` of [`Avx8k`] as [`Avx8`]'s.
macro_rules! delegate_binary {
    ($($f:ident),*) => {
        $(
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                Avx8k(self.0.$f(o.0))
            }
        )*
    };
}

/// [`Avx8`] on a CPU with AVX-512, which orders a node's children with a sorting network in
/// one register instead of branches.
#[derive(Clone, Copy, Debug)]
pub struct Avx8k(Avx8);

// SAFETY (whole block): only instantiated inside `#[target_feature(enable = "avx512f", ...)]`
// functions, which run only after `Isa::supported` confirmed AVX-512.
impl Vec8 for Avx8k {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        Avx8k(Avx8::splat(x))
    }
    #[inline(always)]
    fn load(a: &[f32; 8]) -> Self {
        Avx8k(Avx8::load(a))
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        self.0.to_array()
    }
    // The lane arithmetic is `Avx8`'s.
    delegate_binary!(sub, mul, min, max);
    #[inline(always)]
    fn le_bits(self, o: Self) -> u32 {
        self.0.le_bits(o.0)
    }
    #[inline(always)]
    fn used_bits(a: &[u32; 8]) -> u32 {
        Avx8::used_bits(a)
    }
    #[inline(always)]
    fn far_first(self, child: &[u32; 8], mask: u32, out: &mut [MaybeUninit<u64>; 8]) -> u64 {
        unsafe {
            let near = _mm512_cvtepu32_epi64(_mm256_castps_si256((self.0).0));
            let ch = _mm512_cvtepu32_epi64(_mm256_loadu_si256(child.as_ptr().cast()));
            let k = mask as __mmask8;
            let keys =
                _mm512_maskz_mov_epi64(k, _mm512_or_si512(_mm512_slli_epi64::<32>(near), ch));
            let nearest = _mm512_mask_reduce_min_epu64(k, keys);
            // Optimal 8-input network (19 comparators, 6 layers), descending.
            macro_rules! layer {
                ($x:ident, $p:expr, $lower:expr) => {{
                    let y = _mm512_permutexvar_epi64($p, $x);
                    let (mn, mx) = (_mm512_min_epu64($x, y), _mm512_max_epu64($x, y));
                    _mm512_mask_blend_epi64($lower, mn, mx)
                }};
            }
            let x = keys;
            let x = layer!(x, _mm512_setr_epi64(2, 3, 0, 1, 6, 7, 4, 5), 0x33);
            let x = layer!(x, _mm512_setr_epi64(4, 5, 6, 7, 0, 1, 2, 3), 0x0f);
            let x = layer!(x, _mm512_setr_epi64(1, 0, 3, 2, 5, 4, 7, 6), 0x55);
            let x = layer!(x, _mm512_setr_epi64(0, 1, 4, 5, 2, 3, 6, 7), 0x0c);
            let x = layer!(x, _mm512_setr_epi64(0, 4, 2, 6, 1, 5, 3, 7), 0x0a);
            let x = layer!(x, _mm512_setr_epi64(0, 2, 1, 4, 3, 6, 5, 7), 0x2a);
            _mm512_storeu_si512(out.as_mut_ptr().cast(), x);
            nearest
        }
    }
    #[inline(always)]
    fn first_and_rest(child: &[u32; 8], mask: u32, out: &mut [MaybeUninit<u32>; 8]) -> u32 {
        let first = child[mask.trailing_zeros() as usize];
        unsafe {
            let c = _mm256_loadu_si256(child.as_ptr().cast());
            let rest = _mm256_maskz_compress_epi32((mask & (mask - 1)) as __mmask8, c);
            _mm256_storeu_si256(out.as_mut_ptr().cast(), rest);
        }
        first
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::simd::Pair8;

    /// `far_first` and `first_and_rest` against a plain sort, for every mask of hit children
    /// and entry distances with ties (broken by the child reference) and zeros.
    fn check_order<V: Vec8>() {
        let mut rng = crate::math::Pcg32::new(7, 1);
        for round in 0..64 {
            let near: [f32; 8] = std::array::from_fn(|_| match rng.next_u32() % 4 {
                0 => 0.0,
                1 => 1.5,
                _ => rng.next_f32() * 10.0,
            });
            // Odd rounds: small references, so that equal distances tie on them.
            let child: [u32; 8] = std::array::from_fn(|i| {
                if round & 1 == 0 {
                    rng.next_u32()
                } else {
                    i as u32 + 1
                }
            });
            for mask in 1u32..256 {
                let mut keys: Vec<u64> = (0..8)
                    .filter(|&l| mask >> l & 1 != 0)
                    .map(|l| ((near[l].to_bits() as u64) << 32) | child[l] as u64)
                    .collect();
                keys.sort_unstable_by(|a, b| b.cmp(a));
                let n = keys.len();
                let mut out = [MaybeUninit::new(0u64); 8];
                let nearest = V::load(&near).far_first(&child, mask, &mut out);
                assert_eq!(nearest, keys[n - 1], "mask {mask:#b}");
                // SAFETY: initialised above.
                let out = out.map(|o| unsafe { o.assume_init() });
                assert_eq!(out[..n - 1], keys[..n - 1], "mask {mask:#b}");
                let lanes: Vec<u32> = (0..8)
                    .filter(|&l| mask >> l & 1 != 0)
                    .map(|l| child[l])
                    .collect();
                let mut rest = [MaybeUninit::new(0u32); 8];
                assert_eq!(V::first_and_rest(&child, mask, &mut rest), lanes[0]);
                // SAFETY: initialised above.
                let rest = rest.map(|o| unsafe { o.assume_init() });
                assert_eq!(rest[..n - 1], lanes[1..], "mask {mask:#b}");
            }
        }
    }

    #[test]
    fn children_come_in_the_order_of_a_plain_sort() {
        check_order::<Pair8>();
        if is_x86_feature_detected!("avx2") {
            check_order::<Avx8>();
        }
        if is_x86_feature_detected!("avx512f") && is_x86_feature_detected!("avx512vl") {
            check_order::<Avx8k>();
        }
    }
}
