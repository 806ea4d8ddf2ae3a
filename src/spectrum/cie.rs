//! CIE 1931 2° colour-matching functions, the D65 illuminant, XYZ ↔ linear sRGB and the sRGB
//! transfer function.
//!
//! Data: `data/cie1931_2deg_1nm.csv` (CIE 1931 2° standard observer, 1 nm, 360–830 nm) and
//! `data/d65_5nm.csv` (CIE illuminant D65, 5 nm), both written by `tools/gen_spectral_data.py`
//! from colour-science's copies of the CIE tables (CIE 015:2018) and turned into `const` arrays by
//! `build.rs`. The sRGB matrices are derived in `build.rs` from the IEC 61966-2-1 primaries
//! (0.64, 0.33), (0.30, 0.60), (0.15, 0.06) and the white of the D65 table as these CMFs see it,
//! (x, y) = (0.31271, 0.32902), instead of sRGB's rounded (0.3127, 0.3290) (a 1e-5 difference):
//! so D65 maps to rgb (1, 1, 1) exactly and a constant reflectance of 1 is exactly rgb white.
//!
//! Both curves are linearly interpolated between table entries, which is how the CIE tabulates
//! them; outside 360–830 nm they are 0.

use crate::simd::{Float, Int};

include!(concat!(env!("OUT_DIR"), "/cie_tables.rs"));

/// ∫ ȳ(λ) dλ over 360–830 nm (the 1 nm table's sum × 1 nm, ≈ 106.857).
pub const CIE_Y_INTEGRAL: f32 = CIE_Y_SUM;

const LMIN: f32 = 360.0;
const LMAX: f32 = 830.0;

/// x̄, ȳ, z̄ at `lambda` nm (0 outside 360–830).
pub fn xyz_bar(lambda: f32) -> [f32; 3] {
    xyz_bar_lanes(lambda)
}

/// D65 normalised so that ∫ D65·ȳ dλ / CIE_Y_INTEGRAL = 1.
pub fn d65(lambda: f32) -> f32 {
    d65_lanes(lambda)
}

/// Where `lambda` falls on a grid of spacing `step` nm from 360 nm: (inside 360–830 nm, index,
/// fraction); lanes outside (NaN included) get index 0.
#[inline(always)]
fn locate_lanes<F: Float>(lambda: F, step: f32, len: usize) -> (F::M, F::I, F) {
    let inside = lambda.ge(F::splat(LMIN)) & lambda.le(F::splat(LMAX));
    let x = (lambda - F::splat(LMIN)) / F::splat(step);
    let last = F::I::splat(len as i32 - 2);
    let i = x.to_int();
    let i = F::I::select(i.gt(last), last, i);
    let i = F::I::select(inside, i, F::I::splat(0));
    (inside, i, x - F::from_int(i))
}

/// Linear interpolation in `table` at (index, fraction).
#[inline(always)]
fn lerp_lanes<F: Float>(table: &[f32], i: F::I, t: F) -> F {
    let a = F::gather(table, i);
    let b = F::gather(table, i + F::I::splat(1));
    a + t * (b - a)
}

/// [`xyz_bar`] on lanes.
#[inline(always)]
pub fn xyz_bar_lanes<F: Float>(lambda: F) -> [F; 3] {
    let (inside, i, t) = locate_lanes(lambda, 1.0, CIE_Y.len());
    let zero = F::splat(0.0);
    // Written out rather than mapped: see `integrator::wave::vertex::spec`.
    [
        F::select(inside, lerp_lanes(&CIE_X, i, t), zero),
        F::select(inside, lerp_lanes(&CIE_Y, i, t), zero),
        F::select(inside, lerp_lanes(&CIE_Z, i, t), zero),
    ]
}

/// [`d65`] on lanes.
#[inline(always)]
pub fn d65_lanes<F: Float>(lambda: F) -> F {
    let (inside, i, t) = locate_lanes(lambda, 5.0, D65_5NM.len());
    F::select(
        inside,
        F::splat(D65_SCALE) * lerp_lanes(&D65_5NM, i, t),
        F::splat(0.0),
    )
}

#[inline]
fn mul(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

/// The linear-sRGB colour-matching functions r̄, ḡ, b̄ (XYZ_TO_SRGB applied to x̄, ȳ, z̄) at
/// table node `k`, i.e. at 360 + k nm (k ≤ 470).
pub(crate) fn srgb_bar_node(k: usize) -> [f32; 3] {
    mul(&XYZ_TO_SRGB, [CIE_X[k], CIE_Y[k], CIE_Z[k]])
}

/// Number of nodes of the 1 nm tables (360–830 nm).
pub(crate) const NODES: usize = CIE_Y.len();

/// XYZ → linear sRGB (D65 white).
pub fn xyz_to_linear_srgb(xyz: [f32; 3]) -> [f32; 3] {
    mul(&XYZ_TO_SRGB, xyz)
}

/// Linear sRGB (D65 white) → XYZ.
pub fn linear_srgb_to_xyz(rgb: [f32; 3]) -> [f32; 3] {
    mul(&SRGB_TO_XYZ, rgb)
}

/// The sRGB transfer function (IEC 61966-2-1): linear → encoded, for values in [0, 1].
/// Negative input maps to 0 and NaN to 0.
pub fn srgb_encode(v: f32) -> f32 {
    if v.is_nan() || v <= 0.0 {
        0.0
    } else if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// Inverse of [`srgb_encode`]: encoded → linear. Negative input maps to 0 and NaN to 0.
pub fn srgb_decode(v: f32) -> f32 {
    if v.is_nan() || v <= 0.0 {
        0.0
    } else if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Σ over the 1 nm grid of f(λ) · 1 nm, in f64.
    fn integrate(f: impl Fn(f32) -> [f64; 3]) -> [f64; 3] {
        (360..=830).fold([0.0; 3], |a, l| {
            let v = f(l as f32);
            [a[0] + v[0], a[1] + v[1], a[2] + v[2]]
        })
    }

    #[test]
    fn y_integral_matches_table_sum() {
        let s: f64 = CIE_Y.iter().map(|&v| v as f64).sum();
        // The constant is the f64 sum rounded to f32: half an ulp at ~107 is 3.8e-6.
        assert!((s - CIE_Y_INTEGRAL as f64).abs() < 1e-5, "{s}");
        assert!((CIE_Y_INTEGRAL - 106.857).abs() < 1e-3);
    }

    #[test]
    fn xyz_bar_interpolates_and_vanishes_outside() {
        assert_eq!(xyz_bar(359.9), [0.0; 3]);
        assert_eq!(xyz_bar(830.1), [0.0; 3]);
        assert_eq!(xyz_bar(f32::NAN), [0.0; 3]);
        assert_eq!(xyz_bar(555.0)[1], CIE_Y[195]);
        // ȳ peaks at 1.0 at 555 nm in the CIE table.
        assert!((xyz_bar(555.0)[1] - 1.0).abs() < 1e-4);
        let mid = xyz_bar(555.5)[1];
        assert!((mid - 0.5 * (CIE_Y[195] + CIE_Y[196])).abs() < 1e-7);
        // The last entry is reachable (no off-by-one at 830 nm).
        assert_eq!(xyz_bar(830.0)[0], CIE_X[470]);
    }

    #[test]
    fn d65_has_unit_luminance_and_is_white_in_srgb() {
        let xyz = integrate(|l| {
            let b = xyz_bar(l);
            let d = d65(l) as f64;
            [0, 1, 2].map(|c| d * b[c] as f64 / CIE_Y_INTEGRAL as f64)
        });
        // f32 table sums over 471 terms: errors of order 1e-6.
        assert!((xyz[1] - 1.0).abs() < 1e-5, "Y = {}", xyz[1]);
        let rgb = xyz_to_linear_srgb(xyz.map(|v| v as f32));
        for c in rgb {
            // The matrices are built on this D65's white, so only f32 rounding remains.
            assert!((c - 1.0).abs() < 1e-5, "{rgb:?}");
        }
    }

    #[test]
    fn equal_energy_is_at_one_third() {
        let xyz = integrate(|l| xyz_bar(l).map(|v| v as f64));
        let s = xyz[0] + xyz[1] + xyz[2];
        // The CIE normalised the CMFs so that their three integrals are equal (illuminant E
        // is at (1/3, 1/3)); at 1 nm over 360–830 nm they agree to ~1e-5.
        assert!((xyz[0] / s - 1.0 / 3.0).abs() < 1e-3, "{xyz:?}");
        assert!((xyz[1] / s - 1.0 / 3.0).abs() < 1e-3, "{xyz:?}");
    }

    #[test]
    fn srgb_matrices_are_inverse_and_map_white() {
        let w = linear_srgb_to_xyz([1.0; 3]);
        // sRGB white (0.3127, 0.3290) at Y = 1, up to the 1e-5 chromaticity difference between
        // that and the tables' D65 (X moves by ~2e-5, Z by ~2.3e-4).
        assert!((w[0] - 0.3127 / 0.3290).abs() < 1e-4, "{w:?}");
        assert!(
            (w[2] - (1.0 - 0.3127 - 0.3290) / 0.3290).abs() < 5e-4,
            "{w:?}"
        );
        assert!((w[1] - 1.0).abs() < 1e-6);
        for rgb in [[0.2f32, 0.7, 0.1], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]] {
            let back = xyz_to_linear_srgb(linear_srgb_to_xyz(rgb));
            for c in 0..3 {
                assert!((back[c] - rgb[c]).abs() < 1e-5, "{rgb:?} → {back:?}");
            }
        }
    }

    #[test]
    fn srgb_transfer_round_trips_and_is_continuous() {
        for i in 0..=1000 {
            let v = i as f32 / 1000.0;
            assert!((srgb_decode(srgb_encode(v)) - v).abs() < 2e-6, "{v}");
        }
        // The two pieces meet at the breakpoint (to the precision of the standard's constants).
        assert!(
            (12.92 * 0.003_130_8 - (1.055 * 0.003_130_8f32.powf(1.0 / 2.4) - 0.055)).abs() < 1e-6
        );
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert_eq!(srgb_encode(-1.0), 0.0);
        assert_eq!(srgb_encode(f32::NAN), 0.0);
        assert!((srgb_encode(0.5) - 0.735_357).abs() < 1e-5);
        assert_eq!(srgb_decode(f32::NAN), 0.0);
    }
}
