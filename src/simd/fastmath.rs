//! Sine, cosine and the natural logarithm for [`Float`] lanes, so that the scalar code and the
//! eight-lane kernels compute them with the same operations (the C library's `sinf`/`logf`
//! differ from any vector version in the last bit, and a last bit can turn a path).
//!
//! Both follow the classic Cephes single-precision algorithms (S. L. Moshier, "Methods and
//! Programs for Mathematical Functions", 1989): sine and cosine reduce the argument to
//! [−π/4, π/4] by multiples of π/2 subtracted in three parts (Cody–Waite) and evaluate minimax
//! polynomials there; the logarithm splits x = 2^e · m with m in [√½, √2) and evaluates a
//! polynomial in m − 1. Errors stay within a few ulp (checked against f64 in the tests) for
//! |x| < 8192, the range the renderer uses (angles of a turn or two).
use super::{Float, Int};

/// (sin x, cos x) for every lane.
#[inline(always)]
pub fn sin_cos<F: Float>(x: F) -> (F, F) {
    const FOUR_OVER_PI: f32 = 1.273_239_5;
    // π/4 in three parts whose products with small integers are exact.
    const DP1: f32 = 0.785_156_25;
    const DP2: f32 = 2.418_756_5e-4;
    const DP3: f32 = 3.774_895e-8;
    let a = x.abs();
    // The octant, rounded up to an even number.
    let j = (a * F::splat(FOUR_OVER_PI)).to_int();
    let j = (j + F::I::splat(1)) & F::I::splat(!1);
    let y = F::from_int(j);
    let z = ((a - y * F::splat(DP1)) - y * F::splat(DP2)) - y * F::splat(DP3);
    let zz = z * z;
    let s = ((F::splat(-1.951_529_6e-4) * zz + F::splat(8.332_161e-3)) * zz
        + F::splat(-1.666_665_5e-1))
        * zz
        * z
        + z;
    let c = ((F::splat(2.443_315_7e-5) * zz + F::splat(-1.388_731_6e-3)) * zz
        + F::splat(4.166_664_6e-2))
        * zz
        * zz
        - F::splat(0.5) * zz
        + F::splat(1.0);
    // Octants 2 and 6 (j & 2) swap the polynomials; j & 4 flips the signs.
    let swap = (j & F::I::splat(2)).eq(F::I::splat(2));
    let sin_r = F::select(swap, c, s);
    let cos_r = F::select(swap, s, c);
    let flip_sin = (j & F::I::splat(4)).eq(F::I::splat(4));
    let flip_cos = ((j + F::I::splat(2)) & F::I::splat(4)).eq(F::I::splat(4));
    let sin_r = F::select(flip_sin, -sin_r, sin_r);
    let cos_r = F::select(flip_cos, -cos_r, cos_r);
    // sin is odd.
    let neg = x.lt(F::splat(0.0));
    (F::select(neg, -sin_r, sin_r), cos_r)
}

/// Natural logarithm: NaN below zero, −∞ at zero, +∞ at +∞.
#[inline(always)]
pub fn ln<F: Float>(x: F) -> F {
    const SQRT_HALF: f32 = std::f32::consts::FRAC_1_SQRT_2;
    // ln 2 in two parts (the first exact in products with small exponents).
    const LN2_HI: f32 = 0.693_359_4;
    const LN2_LO: f32 = -2.121_944_4e-4;
    let zero = F::splat(0.0);
    // Subnormals: scale into the normal range first.
    let tiny = x.lt(F::splat(f32::MIN_POSITIVE));
    let xs = F::select(tiny, x * F::splat(16_777_216.0), x);
    let bits = xs.to_bits();
    // Exponent and mantissa in [0.5, 1).
    let e = (bits.shr::<23>() & F::I::splat(0xff)) - F::I::splat(126);
    let m = F::from_bits((bits & F::I::splat(0x007f_ffff)) | F::I::splat(0x3f00_0000));
    let e = F::from_int(e) - F::select(tiny, F::splat(24.0), zero);
    // m in [√½, √2): below √½ double it and lower the exponent.
    let low = m.lt(F::splat(SQRT_HALF));
    let m = F::select(low, m + m, m) - F::splat(1.0);
    let e = F::select(low, e - F::splat(1.0), e);
    let z = m * m;
    let p = ((((((((F::splat(7.037_683_6e-2) * m + F::splat(-1.151_461e-1)) * m
        + F::splat(1.167_699_9e-1))
        * m
        + F::splat(-1.242_014_1e-1))
        * m
        + F::splat(1.424_932_3e-1))
        * m
        + F::splat(-1.666_805_8e-1))
        * m
        + F::splat(2.000_071_5e-1))
        * m
        + F::splat(-2.499_999_4e-1))
        * m
        + F::splat(3.333_333e-1))
        * m
        * z;
    let r = ((p + e * F::splat(LN2_LO)) - F::splat(0.5) * z + m) + e * F::splat(LN2_HI);
    let r = F::select(x.eq(zero), F::splat(f32::NEG_INFINITY), r);
    let r = F::select(x.eq(F::splat(f32::INFINITY)), x, r);
    F::select(x.lt(zero) | x.is_nan(), F::splat(f32::NAN), r)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(a: f32, b: f64) -> f64 {
        let b32 = b as f32;
        let ulp = (f32::from_bits(b32.abs().to_bits() + 1) - b32.abs()) as f64;
        (a as f64 - b).abs() / ulp.max(f32::MIN_POSITIVE as f64)
    }

    #[test]
    fn sine_and_cosine_within_a_few_ulp() {
        let mut worst = (0.0f64, 0.0f32);
        let n = 200_000;
        for i in 0..=n {
            let x = -20.0 + 40.0 * i as f32 / n as f32;
            let (s, c) = sin_cos(x);
            let (es, ec) = (x as f64).sin_cos();
            // Absolute error near the zeros, where ulps of a tiny value mean nothing.
            for (v, e) in [(s, es), (c, ec)] {
                let err = if e.abs() < 1e-3 {
                    (v as f64 - e).abs() / 6e-8
                } else {
                    ulps(v, e)
                };
                if err > worst.0 {
                    worst = (err, x);
                }
            }
        }
        assert!(worst.0 <= 3.0, "worst {} ulp at {}", worst.0, worst.1);
        assert_eq!(sin_cos(0.0f32), (0.0, 1.0));
    }

    #[test]
    fn logarithm_within_a_few_ulp_and_special_values() {
        let mut worst = 0.0f64;
        let mut x = 1e-40f32;
        while x < 1e38 {
            let e = (x as f64).ln();
            let err = if e.abs() < 1e-2 {
                (ln(x) as f64 - e).abs() / 1e-9
            } else {
                ulps(ln(x), e)
            };
            worst = worst.max(err);
            x *= 1.000_37;
        }
        assert!(worst <= 3.0, "worst {worst} ulp");
        assert_eq!(ln(1.0f32), 0.0);
        assert_eq!(ln(0.0f32), f32::NEG_INFINITY);
        assert_eq!(ln(f32::INFINITY), f32::INFINITY);
        assert!(ln(-1.0f32).is_nan() && ln(f32::NAN).is_nan());
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn eight_lanes_equal_one_lane() {
        on_avx2!({
            use crate::simd::F8;
            let mut rng = crate::math::Pcg32::new(3, 4);
            for _ in 0..20_000 {
                let a: [f32; 8] = std::array::from_fn(|_| (rng.next_f32() - 0.5) * 40.0);
                let (s, c) = sin_cos(F8::load(&a));
                let l = ln(F8::load(&a.map(f32::abs)));
                for (i, &x) in a.iter().enumerate() {
                    let (es, ec) = sin_cos(x);
                    assert_eq!(s.lane(i).to_bits(), es.to_bits());
                    assert_eq!(c.lane(i).to_bits(), ec.to_bits());
                    assert_eq!(l.lane(i).to_bits(), ln(x.abs()).to_bits());
                }
            }
        });
    }
}
