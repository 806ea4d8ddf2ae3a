//! Four f64 lanes (one per hero wavelength) and the one transcendental the film-stack fast path
//! needs, sin and cos together, written branch-free so that the compiler keeps all four lanes in
//! vector registers (SSE2 pairs on baseline x86-64, one AVX register where the caller was
//! compiled for AVX2).
//!
//! `sincos4`: Cody–Waite reduction by π/2 (π/2 split into three parts of 33, 33 and 53 bits, so
//! j·P1 and j·P2 are exact for |j| < 2^20), then the Taylor series of sin to r^17 and of cos to
//! r^18 on |r| ≤ π/4 (truncation < 1e-18, below f64 rounding), then the quadrant j mod 4 picks
//! and negates by bit operations. Agrees with the C library's sin/cos to a few ulp (tested).
//! Arguments beyond [`SINCOS_LIMIT`] (whose reduction would lose bits) or not finite take the C
//! library per lane instead.
//!
//! `exp4`: x = k ln 2 + r with ln 2 in two parts (32 + 53 bits), the Taylor series of e^r to r^13
//! on |r| ≤ ln2/2 (truncation < 1e-17), times 2^k built in the exponent bits. Results below
//! 2^-1022 flush to 0 (the film stack only needs e^x for attenuation, x ≤ 0).

/// Four lanes.
pub(crate) type F4 = [f64; 4];

/// |x| above which [`sincos4`] hands a lane to the C library (2^19·π/2: |j| < 2^20 with margin).
pub(crate) const SINCOS_LIMIT: f64 = 823_549.6;

const FRAC_2_PI: f64 = std::f64::consts::FRAC_2_PI;
// π/2 = P1 + P2 + P3 (+ 1e-37): P1, P2 have 33 significant bits.
const P1: f64 = 1.5707963267341256;
const P2: f64 = 6.077100506303966e-11;
const P3: f64 = 2.0222662487959506e-21;
// Round-to-nearest-integer by adding 1.5·2^52: the integer lands in the low mantissa bits.
const ROUND_MAGIC: f64 = 6755399441055744.0;

const FRAC_1_LN2: f64 = std::f64::consts::LOG2_E;
const LN2_HI: f64 = 0.6931471803691238;
const LN2_LO: f64 = 1.9082149292705877e-10;

/// 1/k! for k = 0..=13.
const fn exp_taylor() -> [f64; 14] {
    let mut c = [0.0; 14];
    let mut k = 0;
    while k < 14 {
        c[k as usize] = 1.0 / fact(k);
        k += 1;
    }
    c
}
const EXP_C: [f64; 14] = exp_taylor();

/// e^x lane-wise (see the module doc); NaN stays NaN, +∞ stays +∞ beyond 709.
#[inline(always)]
pub(crate) fn exp4(x: F4) -> F4 {
    let mut out = [0.0; 4];
    for i in 0..4 {
        let xc = x[i].clamp(-746.0, 709.0);
        let t = xc * FRAC_1_LN2 + ROUND_MAGIC;
        let k = t - ROUND_MAGIC;
        let r = (xc - k * LN2_HI) - k * LN2_LO;
        let mut p = EXP_C[13];
        for j in (0..13).rev() {
            p = p * r + EXP_C[j];
        }
        let ki = k as i64;
        let scale = f64::from_bits(((ki + 1023).max(0) as u64) << 52);
        out[i] = if ki < -1022 { 0.0 } else { p * scale };
    }
    if x.iter().any(|v| !(*v <= 709.0)) {
        for i in 0..4 {
            if !(x[i] <= 709.0) {
                out[i] = x[i].exp();
            }
        }
    }
    out
}

/// x clamped to [0, 1], NaN to 0 (a degenerate 0/0 reflects or transmits nothing).
#[inline(always)]
pub fn unit(x: f64) -> f64 {
    if x >= 0.0 {
        x.min(1.0)
    } else {
        0.0
    }
}

/// Lane-wise combination of two vectors.
#[inline(always)]
pub(crate) fn zip4(a: F4, b: F4, f: impl Fn(f64, f64) -> f64) -> F4 {
    [f(a[0], b[0]), f(a[1], b[1]), f(a[2], b[2]), f(a[3], b[3])]
}

const fn fact(n: u32) -> f64 {
    let mut f = 1.0;
    let mut i = 2;
    while i <= n {
        f *= i as f64;
        i += 1;
    }
    f
}

/// Taylor coefficients (−1)^k / (2k+1)! and (−1)^(k+1) / (2k+2)! for k = 1..=8, computed at
/// compile time (n! is exact in f64 up to 18!).
const fn taylor(cos: bool) -> [f64; 8] {
    let mut c = [0.0; 8];
    let mut k = 1;
    while k <= 8 {
        let n = if cos { 2 * k + 2 } else { 2 * k + 1 };
        let sign = if (k % 2 == 0) != cos { 1.0 } else { -1.0 };
        c[(k - 1) as usize] = sign / fact(n);
        k += 1;
    }
    c
}
const SIN_C: [f64; 8] = taylor(false);
const COS_C: [f64; 8] = taylor(true);

/// sin(r) and cos(r) for |r| ≤ π/4 + ε: sin r = r + r·r²·(−1/3! + r²/5! − …),
/// cos r = 1 − r²/2 + r⁴·(1/4! − r²/6! + …), by Horner on r².
#[inline(always)]
fn kernel(r: f64) -> (f64, f64) {
    let r2 = r * r;
    let mut s = SIN_C[7];
    let mut c = COS_C[7];
    for k in (0..7).rev() {
        s = s * r2 + SIN_C[k];
        c = c * r2 + COS_C[k];
    }
    let sin = r + r * r2 * s;
    let cos = 1.0 - 0.5 * r2 + r2 * r2 * c;
    (sin, cos)
}

/// (sin x, cos x) lane-wise.
#[inline(always)]
pub(crate) fn sincos4(x: F4) -> (F4, F4) {
    sincos_lanes(x)
}

/// [`sincos4`] on any number of lanes (eight: two films' four wavelengths in one pass).
#[inline(always)]
pub(crate) fn sincos_lanes<const L: usize>(x: [f64; L]) -> ([f64; L], [f64; L]) {
    let mut sin = [0.0; L];
    let mut cos = [0.0; L];
    for i in 0..L {
        let t = x[i] * FRAC_2_PI + ROUND_MAGIC;
        let j = t - ROUND_MAGIC;
        let q = t.to_bits();
        let r = ((x[i] - j * P1) - j * P2) - j * P3;
        let (s, c) = kernel(r);
        // Odd quadrants swap sin and cos; quadrants 2, 3 negate sin, quadrants 1, 2 negate cos.
        let swap = (q & 1).wrapping_neg();
        let (sb, cb) = (s.to_bits(), c.to_bits());
        let sv = (cb & swap) | (sb & !swap);
        let cv = (sb & swap) | (cb & !swap);
        sin[i] = f64::from_bits(sv ^ ((q & 2) << 62));
        cos[i] = f64::from_bits(cv ^ ((q.wrapping_add(1) & 2) << 62));
    }
    if x.iter().any(|v| !(v.abs() < SINCOS_LIMIT)) {
        for i in 0..L {
            if !(x[i].abs() < SINCOS_LIMIT) {
                (sin[i], cos[i]) = x[i].sin_cos();
            }
        }
    }
    (sin, cos)
}

/// √(x + iy), y ≥ 0, on the branch Im ≥ 0.
#[inline(always)]
pub(crate) fn csqrt_up(x: F4, y: F4) -> (F4, F4) {
    let mut u = [0.0; 4];
    let mut v = [0.0; 4];
    for i in 0..4 {
        let m = (x[i] * x[i] + y[i] * y[i]).sqrt();
        let t = (0.5 * (m + x[i].abs())).sqrt();
        let o = if t > 0.0 { y[i] / (2.0 * t) } else { 0.0 };
        (u[i], v[i]) = if x[i] >= 0.0 { (t, o) } else { (o, t) };
    }
    (u, v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sincos_matches_the_c_library() {
        let mut next = crate::math::rng::uniform_f64s(7);
        let mut worst: f64 = 0.0;
        for k in 0..200_000 {
            // Magnitudes from 1e-8 to 1e6 rad (past the limit, so the fallback is exercised too),
            // both signs.
            let mag = 10f64.powf(-8.0 + 14.0 * next());
            let x: F4 = std::array::from_fn(|i| {
                let v = mag * (1.0 + 0.1 * i as f64);
                if k % 2 == 0 {
                    v
                } else {
                    -v
                }
            });
            let (s, c) = sincos4(x);
            for i in 0..4 {
                let (ws, wc) = x[i].sin_cos();
                // Error in units of the result's own ulp scale (absolute near zeros).
                worst = worst
                    .max((s[i] - ws).abs() / ws.abs().max(f64::EPSILON))
                    .max((c[i] - wc).abs() / wc.abs().max(f64::EPSILON));
            }
        }
        // Reduction by a 3-part π/2 and a Taylor kernel: a few ulp, never more.
        assert!(worst < 8.0 * f64::EPSILON, "worst relative error {worst:e}");
        // Exact values and non-finite inputs.
        let (s, c) = sincos4([0.0, -0.0, f64::NAN, f64::INFINITY]);
        assert_eq!((s[0], c[0]), (0.0, 1.0));
        assert!(s[1] == 0.0 && c[1] == 1.0);
        assert!(s[2].is_nan() && s[3].is_nan() && c[3].is_nan());
    }

    #[test]
    fn exp_matches_the_c_library() {
        let mut worst: f64 = 0.0;
        for k in 0..100_000 {
            let x = -745.0 + 1454.0 * (k as f64 + 0.5) / 100_000.0;
            let got = exp4([x, -x.abs() * 1e-9, x * 1e-3, 0.5 * x]);
            for (g, v) in got.iter().zip([x, -x.abs() * 1e-9, x * 1e-3, 0.5 * x]) {
                let want = v.exp();
                if want > f64::MIN_POSITIVE {
                    worst = worst.max((g - want).abs() / want);
                }
            }
        }
        assert!(worst < 4.0 * f64::EPSILON, "worst relative error {worst:e}");
        let e = exp4([-800.0, 0.0, f64::NAN, f64::INFINITY]);
        assert_eq!((e[0], e[1]), (0.0, 1.0));
        assert!(e[2].is_nan() && e[3] == f64::INFINITY);
    }
}
