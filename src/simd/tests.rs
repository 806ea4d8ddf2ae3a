//! Every lane type against one lane: each operation, on random values and on the special ones
//! (±0, ±∞, NaN, subnormals), gives in every lane the bits `f32`/`i32` give.

// Lanes and arrays are indexed together.
#![allow(clippy::needless_range_loop)]

use super::{Float, Int, Mask};
use crate::math::Pcg32;
use std::panic::AssertUnwindSafe;

/// Values that exercise the corners of IEEE arithmetic, then random ones of all magnitudes.
fn values(rng: &mut Pcg32, n: usize) -> Vec<f32> {
    let mut v = vec![
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        f32::MIN_POSITIVE,
        1e-40,
        -1e-40,
        f32::MAX,
        3.5,
        -2.5,
        1e18,
        -1e20,
    ];
    while v.len() < n {
        let e = (rng.next_u32() % 60) as i32 - 30;
        let s = if rng.next_u32() & 1 == 0 { 1.0 } else { -1.0 };
        v.push(s * rng.next_f32() * 2f32.powi(e));
    }
    v
}

/// Checks lane type `F` against `f32` on chunks of `values`.
fn check<F: Float>(rng: &mut Pcg32) {
    let n = F::LANES;
    let a = values(rng, 4096);
    let mut b = a.clone();
    b.rotate_left(7);
    let bits = |x: f32| x.to_bits();
    let pairs = |f: &dyn Fn(F, F) -> F, g: &dyn Fn(f32, f32) -> f32, name: &str| {
        for (ca, cb) in a.chunks_exact(n).zip(b.chunks_exact(n)) {
            let r = f(F::load(ca), F::load(cb));
            for i in 0..n {
                let want = g(ca[i], cb[i]);
                // Any NaN stands for NaN (payloads are not specified).
                if want.is_nan() {
                    assert!(r.lane(i).is_nan(), "{name}({}, {})", ca[i], cb[i]);
                } else {
                    assert_eq!(bits(r.lane(i)), bits(want), "{name}({}, {})", ca[i], cb[i]);
                }
            }
        }
    };
    pairs(&|x, y| x + y, &|x, y| x + y, "add");
    pairs(&|x, y| x - y, &|x, y| x - y, "sub");
    pairs(&|x, y| x * y, &|x, y| x * y, "mul");
    pairs(&|x, y| x / y, &|x, y| x / y, "div");
    pairs(&|x, y| x.min(y), &f32::min, "min");
    pairs(&|x, y| x.max(y), &f32::max, "max");
    pairs(&|x, y| x.copysign(y), &f32::copysign, "copysign");
    pairs(&|x, _| x.abs(), &|x, _| x.abs(), "abs");
    pairs(&|x, _| x.sqrt(), &|x, _| x.sqrt(), "sqrt");
    pairs(&|x, _| x.floor(), &|x, _| x.floor(), "floor");
    pairs(&|x, _| -x, &|x, _| -x, "neg");
    pairs(
        &|x, _| x.clamp(-1.0, 2.0),
        &|x, _| x.clamp(-1.0, 2.0),
        "clamp",
    );
    pairs(
        &|x, y| F::select(x.lt(y), x, y),
        &|x, y| if x < y { x } else { y },
        "select(lt)",
    );
    for (ca, cb) in a.chunks_exact(n).zip(b.chunks_exact(n)) {
        let (x, y) = (F::load(ca), F::load(cb));
        let masks = [
            (x.lt(y), 0),
            (x.le(y), 1),
            (x.gt(y), 2),
            (x.ge(y), 3),
            (x.eq(y), 4),
            (x.ne(y), 5),
            (x.is_nan(), 6),
            (x.is_finite(), 7),
        ];
        for (m, k) in masks {
            for i in 0..n {
                let (p, q) = (ca[i], cb[i]);
                let want = [
                    p < q,
                    p <= q,
                    p > q,
                    p >= q,
                    p == q,
                    p != q,
                    p.is_nan(),
                    p.is_finite(),
                ][k];
                assert_eq!(m.bits() >> i & 1 == 1, want, "comparison {k} of {p}, {q}");
            }
        }
        // Conversions where they are defined (in range, not NaN).
        let ints = x.to_bits();
        for i in 0..n {
            assert_eq!(ints.lane(i), ca[i].to_bits() as i32);
            if ca[i].abs() < 2e9 {
                assert_eq!(x.to_int().lane(i), ca[i] as i32, "to_int({})", ca[i]);
            }
        }
        let back = F::from_int(F::I::splat(-123_457) + ints.shr::<9>());
        for i in 0..n {
            let want = (-123_457i32).wrapping_add((ca[i].to_bits() >> 9) as i32) as f32;
            assert_eq!(bits(back.lane(i)), bits(want));
        }
    }
    // Masks to and from bits, and gathers.
    let table: Vec<f32> = (0..100).map(|i| i as f32 * 0.5).collect();
    let utable: Vec<u32> = (0..100).map(|i| i * 3).collect();
    for _ in 0..200 {
        let bits_in = rng.next_u32() & ((1u64 << n) - 1) as u32;
        assert_eq!(F::M::from_bits(bits_in).bits(), bits_in);
        let idx: Vec<u32> = (0..16).map(|_| rng.next_u32() % 100).collect();
        let iv = F::I::load(&idx);
        let g = F::gather(&table, iv);
        let gi = F::I::gather(&utable, iv);
        for i in 0..n {
            assert_eq!(g.lane(i), table[idx[i] as usize]);
            assert_eq!(gi.lane(i) as u32, utable[idx[i] as usize]);
        }
    }
    // The PCG32 generators: every lane follows its own scalar generator, and only masked lanes
    // move.
    let mut gens: Vec<Pcg32> = (0..16)
        .map(|i| Pcg32::new(rng.next_u32() as u64, i))
        .collect();
    let mut state: Vec<u64> = gens.iter().map(|g| g.raw().0).collect();
    let inc: Vec<u64> = gens.iter().map(|g| g.raw().1).collect();
    for _ in 0..500 {
        let m = rng.next_u32() & ((1u64 << n) - 1) as u32;
        let u = F::pcg_next_f32(&mut state, &inc, F::M::from_bits(m));
        for i in 0..n {
            if m >> i & 1 == 1 {
                assert_eq!(bits(u.lane(i)), bits(gens[i].next_f32()));
            } else {
                assert_eq!(u.lane(i), 0.0);
            }
            assert_eq!(state[i], gens[i].raw().0);
        }
    }
}

#[test]
fn one_lane_is_f32() {
    check::<f32>(&mut Pcg32::new(1, 2));
}

#[cfg(target_arch = "x86_64")]
#[test]
fn eight_lanes_equal_one() {
    on_avx2!({ check::<super::F8>(&mut Pcg32::new(3, 4)) });
}

#[cfg(target_arch = "x86_64")]
#[test]
fn sixteen_lanes_equal_one() {
    on_avx512!({ check::<super::F16>(&mut Pcg32::new(5, 6)) });
}

/// A gather reads the table where every index is in bounds, and panics, rather than reading
/// outside the table, where one lane's index is past the end or negative.
fn gathers_check_their_indices<F: Float>() {
    let n = F::LANES;
    let t: Vec<f32> = (0..40).map(|i| i as f32 * 0.5).collect();
    let u: Vec<u32> = (0..40).map(|i| i * 3).collect();
    let idx: Vec<u32> = (0..n as u32).map(|i| 39 - 2 * i).collect();
    let i = F::I::load(&idx);
    for (k, &j) in idx.iter().enumerate() {
        assert_eq!(F::gather(&t, i).lane(k), t[j as usize]);
        assert_eq!(F::I::gather(&u, i).lane(k), u[j as usize] as i32);
    }
    for bad in [40u32, u32::MAX, 1 << 31] {
        for lane in [0, n - 1] {
            let mut b = idx.clone();
            b[lane] = bad;
            let i = F::I::load(&b);
            let caught = |f: &dyn Fn()| std::panic::catch_unwind(AssertUnwindSafe(f)).is_err();
            let f = caught(&|| {
                std::hint::black_box(F::gather(&t, i).lane(0));
            });
            let g = caught(&|| {
                std::hint::black_box(F::I::gather(&u, i).lane(0));
            });
            assert!(f && g, "index {bad} in lane {lane}");
        }
    }
    let empty: [f32; 0] = [];
    let zero = F::I::splat(0);
    let read = AssertUnwindSafe(|| {
        std::hint::black_box(F::gather(&empty, zero).lane(0));
    });
    assert!(std::panic::catch_unwind(read).is_err());
}

#[test]
fn gathers_check_their_indices_in_every_lane_type() {
    gathers_check_their_indices::<f32>();
    #[cfg(target_arch = "x86_64")]
    {
        on_avx2!({ gathers_check_their_indices::<super::F8>() });
        on_avx512!({ gathers_check_their_indices::<super::F16>() });
    }
}
