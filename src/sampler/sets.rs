//! Owen-scrambled Sobol points four dimensions at a time, the values of
//! `sobol_burley::sample_4d` (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4))
//! with the Sobol matrix product done by table instead of bit by bit.
//!
//! A Sobol point is the XOR of the direction vectors of the index's set bits. Burley's
//! construction shuffles the index first (a hash-based Owen scramble of its reversed bits), so
//! the index that reaches the product has ~8 of its 16 significant bits set, and the crate's
//! loop over them (one `lzcnt`, shift and XOR per bit, each waiting for the last) showed as
//! ~6 % of a render of the thin-film benchmark sphere. Here the 16 bits are read as four
//! nibbles, and a table holds, for each nibble position and value, the XOR of its direction
//! vectors for the four dimensions of a set: four loads and three XORs. The tables cover the
//! sequence's first four sets (dimensions 0–15, the only ones the sampler draws: see the
//! module notes of [`super`]) and take 4 KiB, built once from the crate's own direction
//! vectors (`sobol_burley::parts::sobol_rev` at single-bit indices). The index shuffle and the
//! output scramble are Burley's hash-based Owen scramble with the crate's constants, so the
//! values are the crate's bit for bit (tested); they are computed here on four lanes in an
//! AVX2 build where the CPU has it (the crate's SIMD type emulates the 32-bit lane multiply
//! unless the whole program is built for SSE4.1). Measured on the thin-film benchmark sphere
//! (plastic coat, 96², 256 spp, 8 interleaved pairs): 1.02× the samples per second (0.90–1.16,
//! the machine's spread), the sampler's share of the profile 6.3 % → 5.7 %.

use std::sync::LazyLock;

/// Dimension sets with tables: the sequence's first four (dimensions 0–15).
pub(crate) const TABLE_SETS: u32 = 4;

/// `[set][nibble position][nibble value]` → the XOR of the direction vectors of the nibble's
/// set bits, for the set's four dimensions. Position 0 holds the reversed index's top four
/// bits (bits 31–28: direction vectors 0–3), position 3 bits 19–16 (vectors 12–15).
type Tables = [[[[u32; 4]; 16]; 4]; TABLE_SETS as usize];

static TABLES: LazyLock<Box<Tables>> = LazyLock::new(|| {
    let mut t: Box<Tables> = Box::new([[[[0; 4]; 16]; 4]; TABLE_SETS as usize]);
    for (set, per_set) in t.iter_mut().enumerate() {
        for (pos, per_pos) in per_set.iter_mut().enumerate() {
            for (value, entry) in per_pos.iter_mut().enumerate() {
                for (d, out) in entry.iter_mut().enumerate() {
                    let dim = 4 * set as u32 + d as u32;
                    // Bit b of the nibble (b = 0 its highest) is bit 31 − (4 pos + b) of the
                    // reversed index, i.e. direction vector 4 pos + b.
                    *out = (0..4)
                        .filter(|b| value & (8 >> b) != 0)
                        .map(|b| sobol_burley::parts::sobol_rev(1 << (31 - (4 * pos + b)), dim))
                        .fold(0, |a, v| a ^ v);
                }
            }
        }
    }
    t
});

/// Sobol dimensions 4 `set` … 4 `set` + 3 of point `index` (< 2¹⁶) under `seed`, Owen-scrambled:
/// `sobol_burley::sample_4d(index, set, seed)`, for `set` < [`TABLE_SETS`].
#[inline]
pub(crate) fn sample_4d(index: u32, set: u32, seed: u32) -> [f32; 4] {
    let t = &TABLES[set as usize];
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above), the only requirement.
        return unsafe { sample_4d_avx2(t, index, set, seed) };
    }
    sample_4d_lanes(t, index, set, seed)
}

/// [`sample_4d`] compiled for AVX2, whose 32-bit lane multiply (`vpmulld`) the scrambles'
/// ten multiplies per lane use; the baseline build emulates it (the crate's `Int4` too, which
/// chooses at compile time).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sample_4d_avx2(t: &[[[u32; 4]; 16]; 4], index: u32, set: u32, seed: u32) -> [f32; 4] {
    sample_4d_lanes(t, index, set, seed)
}

/// Burley's hash of a seed (his §3 "hash" with the crate's first xor, so that 0 does not map
/// to 0).
#[inline(always)]
fn hash(mut n: u32) -> u32 {
    n ^= 0xe6fe_3beb;
    n ^= n >> 16;
    n = n.wrapping_mul(0x7feb_352d);
    n ^= n >> 15;
    n = n.wrapping_mul(0x846c_a68b);
    n ^ (n >> 16)
}

/// Burley's nested uniform scramble of a bit-reversed integer: each bit flipped by a hash of
/// the bits below it (in the reversed order: above it in the original), so the permutation is
/// an Owen scramble (his Listing 2, "laine_karras_permutation", with his improved constants).
#[inline(always)]
fn owen_rev(mut n: u32, scramble: u32) -> u32 {
    n ^= n.wrapping_mul(0x3d20_adea);
    n = n.wrapping_add(scramble);
    n = n.wrapping_mul((scramble >> 16) | 1);
    n ^= n.wrapping_mul(0x0552_6c56);
    n ^ n.wrapping_mul(0x53a2_2864)
}

/// The four lanes, written as loops over arrays that the compiler keeps in one register.
#[inline(always)]
fn sample_4d_lanes(t: &[[[u32; 4]; 16]; 4], index: u32, set: u32, seed: u32) -> [f32; 4] {
    // The index shuffle: an Owen scramble of the index under the point's seed.
    let r = owen_rev(index.reverse_bits(), hash(seed ^ 0x79c6_8e4a));
    let (a, b, c, d) = (
        &t[0][(r >> 28) as usize],
        &t[1][((r >> 24) & 15) as usize],
        &t[2][((r >> 20) & 15) as usize],
        &t[3][((r >> 16) & 15) as usize],
    );
    // The output scramble: a seed per dimension from the point's seed and the set.
    const DIM_SALT: [u32; 4] = [0x912f_69ba, 0x174f_18ab, 0x691e_72ca, 0xb40c_c1b8];
    let s = seed.wrapping_mul(0x9c8f_2d3b) ^ set;
    let mut out = [0.0f32; 4];
    for i in 0..4 {
        let sobol = a[i] ^ b[i] ^ c[i] ^ d[i];
        let v = owen_rev(sobol, hash(s ^ DIM_SALT[i])).reverse_bits();
        // The top 23 bits as a float in [0, 1).
        out[i] = f32::from_bits((v >> 9) | 0x3f80_0000) - 1.0;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_the_crates_bit_for_bit() {
        let mut rng = crate::math::Pcg32::new(7, 3);
        for set in 0..TABLE_SETS {
            for k in 0..4000u32 {
                // Small indices (every one up to 1024) and random ones up to 2^16.
                let index = if k < 1024 { k } else { rng.next_u32() >> 16 };
                let seed = rng.next_u32();
                let ours = sample_4d(index, set, seed).map(f32::to_bits);
                let theirs = sobol_burley::sample_4d(index, set, seed).map(f32::to_bits);
                assert_eq!(ours, theirs, "index {index}, set {set}, seed {seed:#x}");
            }
        }
    }
}
