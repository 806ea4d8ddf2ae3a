//! RGB → spectrum uplift: Jakob & Hanika 2019, "A Low-Dimensional Function Space for Efficient
//! Spectral Upsampling" (Computer Graphics Forum 38(2), Eurographics).
//!
//! A linear-sRGB reflectance in [0, 1]³ becomes the smooth spectrum
//! s(λ) = S(c0 λ² + c1 λ + c2), S(x) = ½ + x / (2√(1 + x²)), λ in nm, which lies in [0, 1] at every
//! wavelength and, as a reflectance under D65 seen by the CIE 1931 observer, has the input colour.
//! The coefficients come from a table fitted by `build.rs` (Gauss–Newton on CIELAB error) and are
//! trilinearly interpolated here. The table has three 64³ blocks, one per largest channel; within a
//! block the axes are the largest channel's value z (grid denser near 0 and 1) and the other two
//! channels divided by z.
//!
//! Limits: interpolating coefficients is not exact between grid points; the round-trip colour
//! error in linear sRGB is ~2e-4 on average and up to ~4e-3 for bright near-whites and very
//! saturated colours (see the tests). Exactly grey input is represented exactly
//! by a constant.

include!(concat!(env!("OUT_DIR"), "/rgb2spec_meta.rs"));

/// `[largest channel][z][y][x][c0, c1, c2]` as little-endian f32 (written by `build.rs`).
static TABLE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/rgb2spec.bin"));

/// s(λ) = sigmoid(c0 λ² + c1 λ + c2), λ in nm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SigmoidPolynomial {
    pub c0: f32,
    pub c1: f32,
    pub c2: f32,
}

/// S(x) = ½ + x / (2√(1 + x²)); ±∞ → 1 or 0, NaN → 0 (no energy from malformed input).
#[inline]
fn sigmoid(x: f32) -> f32 {
    sigmoid_lanes(x)
}

/// [`SigmoidPolynomial`]'s sigmoid on lanes.
#[inline(always)]
pub fn sigmoid_lanes<F: crate::simd::Float>(x: F) -> F {
    // Clamping first makes the formula safe without branches: NaN goes to −1e18 (S = 0, as
    // `max` drops a NaN), and beyond ±1e18, where 1 + x² would overflow, S is within 1e-36 of
    // its limit, which the clamped value gives exactly.
    let x = x.max(F::splat(-1e18)).min(F::splat(1e18));
    F::splat(0.5) + F::splat(0.5) * x / (F::splat(1.0) + x * x).sqrt()
}

/// [`SigmoidPolynomial::eval`] on lanes, with coefficients per lane.
#[inline(always)]
pub fn sigmoid_poly_lanes<F: crate::simd::Float>(c0: F, c1: F, c2: F, lambda: F) -> F {
    // With c0 = c1 = 0 and c2 = ±∞ (constant 0 or 1) the products are 0, not NaN.
    let zero = F::splat(0.0);
    let constant = c0.eq(zero) & c1.eq(zero);
    sigmoid_lanes(F::select(constant, c2, (c0 * lambda + c1) * lambda + c2))
}

impl SigmoidPolynomial {
    /// A constant spectrum of value `v` (clamped to [0, 1]): c0 = c1 = 0 and S(c2) = v,
    /// with c2 = ±∞ for 1 and 0.
    pub fn constant(v: f32) -> SigmoidPolynomial {
        let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
        // S(x) = v  ⇔  x = 2u / √(1 − 4u²) with u = v − ½.
        let u = v - 0.5;
        let d = 1.0 - 4.0 * u * u;
        let c2 = if d <= 0.0 {
            if u > 0.0 {
                f32::INFINITY
            } else {
                f32::NEG_INFINITY
            }
        } else {
            2.0 * u / d.sqrt()
        };
        SigmoidPolynomial {
            c0: 0.0,
            c1: 0.0,
            c2,
        }
    }

    /// Value at `lambda` nm, in [0, 1].
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        // With c0 = c1 = 0 and c2 = ±∞ (constant 0 or 1) the products are 0, not NaN.
        let x = if self.c0 == 0.0 && self.c1 == 0.0 {
            self.c2
        } else {
            (self.c0 * lambda + self.c1) * lambda + self.c2
        };
        sigmoid(x)
    }

    /// Values at four wavelengths (the branch on a constant polynomial is taken once).
    #[inline]
    pub fn eval4(&self, lambda: [f32; 4]) -> [f32; 4] {
        if self.c0 == 0.0 && self.c1 == 0.0 {
            return [sigmoid(self.c2); 4];
        }
        // Lane by lane rather than `lambda.map(…)`, whose closure is not always inlined.
        let f = |l: f32| sigmoid((self.c0 * l + self.c1) * l + self.c2);
        [f(lambda[0]), f(lambda[1]), f(lambda[2]), f(lambda[3])]
    }

    /// Largest value over 360–830 nm: at an end or at the polynomial's stationary point.
    pub fn max_value(&self) -> f32 {
        let mut m = self.eval(360.0).max(self.eval(830.0));
        if self.c0 != 0.0 {
            let l = -self.c1 / (2.0 * self.c0);
            if (360.0..=830.0).contains(&l) {
                m = m.max(self.eval(l));
            }
        }
        m
    }
}

/// Reads coefficient triple `n` of the table.
#[inline]
fn entry(n: usize) -> [f32; 3] {
    std::array::from_fn(|q| {
        let o = 4 * (3 * n + q);
        f32::from_le_bytes([TABLE[o], TABLE[o + 1], TABLE[o + 2], TABLE[o + 3]])
    })
}

/// Coefficients for a linear-sRGB reflectance in [0, 1]³ (components clamped; NaN → 0).
pub fn rgb_to_sigmoid(rgb: [f32; 3]) -> SigmoidPolynomial {
    let rgb = rgb.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) });
    if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
        return SigmoidPolynomial::constant(rgb[0]);
    }
    // The largest channel picks the block; it is > 0 since the channels differ.
    let l = if rgb[0] >= rgb[1] && rgb[0] >= rgb[2] {
        0
    } else if rgb[1] >= rgb[2] {
        1
    } else {
        2
    };
    let z = rgb[l];
    let last = (RES - 1) as f32;
    let x = rgb[(l + 1) % 3] / z * last;
    let y = rgb[(l + 2) % 3] / z * last;
    let xi = (x as usize).min(RES - 2);
    let yi = (y as usize).min(RES - 2);
    let zi = Z_GRID.partition_point(|&g| g <= z).clamp(1, RES - 1) - 1;
    let (tx, ty) = (x - xi as f32, y - yi as f32);
    let tz = ((z - Z_GRID[zi]) / (Z_GRID[zi + 1] - Z_GRID[zi])).clamp(0.0, 1.0);
    let mut c = [0.0f32; 3];
    for (dz, wz) in [(0, 1.0 - tz), (1, tz)] {
        for (dy, wy) in [(0, 1.0 - ty), (1, ty)] {
            for (dx, wx) in [(0, 1.0 - tx), (1, tx)] {
                let w = wz * wy * wx;
                if w == 0.0 {
                    continue;
                }
                let e = entry(((l * RES + zi + dz) * RES + yi + dy) * RES + xi + dx);
                for q in 0..3 {
                    c[q] += w * e[q];
                }
            }
        }
    }
    SigmoidPolynomial {
        c0: c[0],
        c1: c[1],
        c2: c[2],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::cie;

    /// The colour (linear sRGB) of a reflectance under normalised D65, by 1 nm sums.
    fn reflectance_to_rgb(s: impl Fn(f32) -> f32) -> [f32; 3] {
        let mut xyz = [0.0f64; 3];
        for l in 360..=830 {
            let l = l as f32;
            let v = s(l) as f64 * cie::d65(l) as f64;
            let b = cie::xyz_bar(l);
            for c in 0..3 {
                xyz[c] += v * b[c] as f64;
            }
        }
        cie::xyz_to_linear_srgb(xyz.map(|v| (v / cie::CIE_Y_INTEGRAL as f64) as f32))
    }

    /// A small xorshift generator so the test needs no dependency and is reproducible.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    #[test]
    fn round_trip_random_colours() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let (mut worst, mut sum) = (0.0f32, 0.0f64);
        let n = 1000;
        for _ in 0..n {
            let rgb = [rng.next(), rng.next(), rng.next()];
            let p = rgb_to_sigmoid(rgb);
            let back = reflectance_to_rgb(|l| p.eval(l));
            let e = (0..3).map(|c| (back[c] - rgb[c]).abs()).fold(0.0, f32::max);
            worst = worst.max(e);
            sum += e as f64;
        }
        let mean = sum / n as f64;
        // Each table entry is fitted to < 1e-6 in CIELAB (build.rs warns otherwise), so what
        // remains is the error of interpolating coefficients trilinearly between entries.
        // It is largest for bright near-white and very saturated colours, where the spectrum
        // presses against 0 or 1 and the coefficients change fastest: over 20 000 random
        // colours the worst channel error was 4.1e-3, the 99th percentile 6e-4 (this seed:
        // worst 1.6e-3, mean 2.2e-4). Both are far below a just-noticeable difference (Jakob &
        // Hanika likewise report interpolation errors well under 1e-2). Bounds: worst 5e-3,
        // mean 3e-4; a table off by one cell or a wrong matrix fails both by orders of magnitude.
        assert!(worst < 5e-3, "worst round-trip error {worst}");
        assert!(mean < 3e-4, "mean round-trip error {mean}");
    }

    #[test]
    fn grid_points_round_trip_tightly() {
        // On a grid point there is no interpolation: the error is the fit's (< 1e-4).
        let l = |i: usize| i as f32 / (RES - 1) as f32;
        let k = 50;
        for (a, b) in [(0usize, 0usize), (63, 10), (7, 40), (63, 63)] {
            let z = Z_GRID[k];
            let rgb = [l(b) * z, z, l(a) * z];
            if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
                continue;
            }
            let p = rgb_to_sigmoid(rgb);
            let back = reflectance_to_rgb(|x| p.eval(x));
            for c in 0..3 {
                assert!((back[c] - rgb[c]).abs() < 1e-4, "{rgb:?} → {back:?}");
            }
        }
    }

    #[test]
    fn spectra_stay_in_unit_interval() {
        let mut rng = Rng(12345);
        for _ in 0..300 {
            let rgb = [rng.next(), rng.next(), rng.next()];
            let p = rgb_to_sigmoid(rgb);
            let mut m = 0.0f32;
            for l in 360..=830 {
                let v = p.eval(l as f32);
                assert!((0.0..=1.0).contains(&v), "{rgb:?} at {l}: {v}");
                m = m.max(v);
            }
            // max_value is at least every sample (up to f32 cancellation in the polynomial,
            // ~1e-7 relative to terms of size |c0| λ²) and at most 1.
            let mv = p.max_value();
            assert!(mv >= m - 1e-5 && mv <= 1.0, "{rgb:?}: {mv} < {m}");
        }
    }

    #[test]
    fn white_black_and_grey_are_constant() {
        let one = rgb_to_sigmoid([1.0; 3]);
        let zero = rgb_to_sigmoid([0.0; 3]);
        let grey = rgb_to_sigmoid([0.25; 3]);
        for l in (360..=830).step_by(10) {
            let l = l as f32;
            assert_eq!(one.eval(l), 1.0);
            assert_eq!(zero.eval(l), 0.0);
            assert!((grey.eval(l) - 0.25).abs() < 1e-6);
        }
        // Out-of-range and NaN input is clamped, not a panic.
        assert_eq!(rgb_to_sigmoid([2.0, 5.0, f32::INFINITY]).eval(500.0), 1.0);
        assert_eq!(rgb_to_sigmoid([f32::NAN, -1.0, 0.0]).eval(500.0), 0.0);
    }

    #[test]
    fn eval_is_robust_to_extreme_coefficients() {
        let big = SigmoidPolynomial {
            c0: 0.0,
            c1: 1e30,
            c2: 0.0,
        };
        assert_eq!(big.eval(500.0), 1.0);
        let neg = SigmoidPolynomial {
            c0: -1e30,
            c1: 0.0,
            c2: 0.0,
        };
        assert_eq!(neg.eval(500.0), 0.0);
        let nan = SigmoidPolynomial {
            c0: f32::INFINITY,
            c1: f32::NEG_INFINITY,
            c2: 0.0,
        };
        assert_eq!(nan.eval(500.0), 0.0);
        assert_eq!(sigmoid(0.0), 0.5);
    }

    #[test]
    fn max_value_finds_interior_peak() {
        // A downward parabola peaking at 550 nm: x = −1e-4 (λ − 550)² + 1.
        let p = SigmoidPolynomial {
            c0: -1e-4,
            c1: 0.11,
            c2: 1.0 - 1e-4 * 550.0 * 550.0,
        };
        assert!(
            (p.max_value() - sigmoid(1.0)).abs() < 1e-4,
            "{}",
            p.max_value()
        );
        assert!(p.max_value() > p.eval(360.0).max(p.eval(830.0)));
    }
}
