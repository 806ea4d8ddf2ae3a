//! The Preetham, Shirley & Smits (1999) clear-sky model, "A Practical Analytic Model for
//! Daylight", SIGGRAPH 99, Appendix A.2, turned into spectral radiance with the CIE daylight
//! basis.
//!
//! The sky's luminance Y and chromaticity (x, y) in a direction at zenith angle θ and angle γ from
//! the sun follow Perez et al.'s (1993) all-weather formula
//! F(θ, γ) = (1 + A e^{B / cos θ}) (1 + C e^{D γ} + E cos² γ), relative to the zenith:
//! Y = Y_z F(θ, γ) / F(0, θ_s), and the same for x and y. The coefficients A–E are the paper's
//! linear fits in turbidity T (its Table A.4 / eq. A.2–A.3); the zenith luminance (kcd/m²) is
//! Y_z = (4.0453 T − 4.9710) tan χ − 0.2155 T + 2.4192 with χ = (4/9 − T/120)(π − 2θ_s), and the
//! zenith chromaticities are the paper's cubic-in-θ_s, quadratic-in-T polynomials (Table A.5).
//!
//! Spectrum: the chromaticity fixes the CIE D-series weights (CIE 015:2018 eq. 4.7–4.8)
//! M1 = (−1.3515 − 1.7703x + 5.9114y) / (0.0241 + 0.2562x − 0.7341y),
//! M2 = (0.0300 − 31.4424x + 30.0717y) / (0.0241 + 0.2562x − 0.7341y), and
//! S(λ) = S0(λ) + M1 S1(λ) + M2 S2(λ) (basis from `data/cie_daylight_basis.csv`, written by
//! `tools/gen_daylight_basis.py`), scaled so that 683 lm/W · ∫ L ȳ dλ equals Y: radiance comes out
//! in W·m⁻²·sr⁻¹·nm⁻¹, as the paper does it.
//!
//! Limits: the model is fitted for the sun above the horizon and turbidity ≈ 2–10 (the paper's
//! range); values are clamped to be non-negative.

use crate::math::Vec3;
use crate::spectrum::cie::xyz_bar;
use std::sync::OnceLock;

/// Luminous efficacy at 555 nm, lm/W.
pub(crate) const LUMINOUS_EFFICACY: f32 = 683.0;

/// The five Perez coefficients of one quantity (Y, x or y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Perez {
    pub a: f32,
    pub b: f32,
    pub c: f32,
    pub d: f32,
    pub e: f32,
}

impl Perez {
    /// Coefficients as linear functions of turbidity: rows of (slope, intercept) for A..E.
    fn linear(t: f32, rows: [(f32, f32); 5]) -> Perez {
        let f = |i: usize| rows[i].0 * t + rows[i].1;
        Perez {
            a: f(0),
            b: f(1),
            c: f(2),
            d: f(3),
            e: f(4),
        }
    }

    /// Luminance distribution coefficients (Preetham et al. 1999, eq. A.2).
    pub fn luminance(t: f32) -> Perez {
        Self::linear(
            t,
            [
                (0.1787, -1.4630),
                (-0.3554, 0.4275),
                (-0.0227, 5.3251),
                (0.1206, -2.5771),
                (-0.0670, 0.3703),
            ],
        )
    }

    /// Chromaticity x distribution coefficients (eq. A.3, first set).
    pub(crate) fn chroma_x(t: f32) -> Perez {
        Self::linear(
            t,
            [
                (-0.0193, -0.2592),
                (-0.0665, 0.0008),
                (-0.0004, 0.2125),
                (-0.0641, -0.8989),
                (-0.0033, 0.0452),
            ],
        )
    }

    /// Chromaticity y distribution coefficients (eq. A.3, second set).
    pub(crate) fn chroma_y(t: f32) -> Perez {
        Self::linear(
            t,
            [
                (-0.0167, -0.2608),
                (-0.0950, 0.0092),
                (-0.0079, 0.2102),
                (-0.0441, -1.6537),
                (-0.0109, 0.0529),
            ],
        )
    }

    /// F(θ, γ) from cos θ (> 0) and γ (radians).
    #[inline]
    pub fn eval(&self, cos_theta: f32, gamma: f32) -> f32 {
        self.eval_cos(cos_theta, gamma, gamma.cos())
    }

    /// [`Perez::eval`] given cos γ too (the sky evaluates three functions at one direction).
    #[inline]
    pub fn eval_cos(&self, cos_theta: f32, gamma: f32, cos_gamma: f32) -> f32 {
        (1.0 + self.a * (self.b / cos_theta).exp())
            * (1.0 + self.c * (self.d * gamma).exp() + self.e * cos_gamma * cos_gamma)
    }
}

/// Zenith luminance in kcd/m² for turbidity `t` and solar zenith angle `theta_s` (radians).
pub(crate) fn zenith_luminance(t: f32, theta_s: f32) -> f32 {
    let chi = (4.0 / 9.0 - t / 120.0) * (std::f32::consts::PI - 2.0 * theta_s);
    (4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192
}

/// Zenith chromaticity (x, y) for turbidity `t` and solar zenith angle `theta_s` (radians):
/// [T² T 1] · M · [θ³ θ² θ 1]ᵀ with the paper's matrices.
pub(crate) fn zenith_chromaticity(t: f32, theta_s: f32) -> (f32, f32) {
    const MX: [[f32; 4]; 3] = [
        [0.00166, -0.00375, 0.00209, 0.0],
        [-0.02903, 0.06377, -0.03202, 0.00394],
        [0.11693, -0.21196, 0.06052, 0.25886],
    ];
    const MY: [[f32; 4]; 3] = [
        [0.00275, -0.00610, 0.00317, 0.0],
        [-0.04214, 0.08970, -0.04153, 0.00516],
        [0.15346, -0.26756, 0.06670, 0.26688],
    ];
    let th = [theta_s.powi(3), theta_s * theta_s, theta_s, 1.0];
    let tt = [t * t, t, 1.0];
    let eval = |m: &[[f32; 4]; 3]| -> f32 {
        (0..3)
            .map(|r| tt[r] * (0..4).map(|c| m[r][c] * th[c]).sum::<f32>())
            .sum()
    };
    (eval(&MX), eval(&MY))
}

/// The CIE daylight basis S0, S1, S2 on its 5 nm grid, and their luminance integrals.
struct DaylightBasis {
    lambda0: f32,
    step: f32,
    s: [Vec<f32>; 3],
    /// ∫ Sᵢ ȳ dλ over 360–830 nm (1 nm sums, the CIE table's own grid).
    y: [f32; 3],
}

fn basis() -> &'static DaylightBasis {
    static B: OnceLock<DaylightBasis> = OnceLock::new();
    B.get_or_init(|| {
        let text = include_str!("../../../data/cie_daylight_basis.csv");
        let mut lambda = Vec::new();
        let mut s: [Vec<f32>; 3] = Default::default();
        for line in text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.is_empty())
        {
            let v: Vec<f32> = line.split(',').map(|x| x.trim().parse().unwrap()).collect();
            lambda.push(v[0]);
            for i in 0..3 {
                s[i].push(v[i + 1]);
            }
        }
        let mut b = DaylightBasis {
            lambda0: lambda[0],
            step: lambda[1] - lambda[0],
            s,
            y: [0.0; 3],
        };
        for l in 360..=830 {
            let ybar = xyz_bar(l as f32)[1];
            let v = b.eval(l as f32);
            for (y, s) in b.y.iter_mut().zip(v) {
                *y += s * ybar;
            }
        }
        b
    })
}

impl DaylightBasis {
    /// (S0, S1, S2) at `lambda` nm, linearly interpolated; 0 outside the table.
    #[inline]
    fn eval(&self, lambda: f32) -> [f32; 3] {
        let x = (lambda - self.lambda0) / self.step;
        let n = self.s[0].len();
        if !(x >= 0.0 && x <= (n - 1) as f32) {
            return [0.0; 3];
        }
        let i = (x as usize).min(n - 2);
        let t = x - i as f32;
        std::array::from_fn(|k| self.s[k][i] + t * (self.s[k][i + 1] - self.s[k][i]))
    }
}

/// The CIE D-series weights (M1, M2) of chromaticity (x, y).
pub(crate) fn daylight_weights(x: f32, y: f32) -> (f32, f32) {
    let d = 0.0241 + 0.2562 * x - 0.7341 * y;
    (
        (-1.3515 - 1.7703 * x + 5.9114 * y) / d,
        (0.0300 - 31.4424 * x + 30.0717 * y) / d,
    )
}

/// A daylight spectrum with chromaticity (x, y) and luminance `lum` (cd/m²), as spectral
/// radiance (W·m⁻²·sr⁻¹·nm⁻¹) at the given wavelengths.
pub(crate) fn daylight_radiance<const N: usize>(
    x: f32,
    y: f32,
    lum: f32,
    lambda: [f32; N],
) -> [f32; N] {
    let b = basis();
    let (m1, m2) = daylight_weights(x, y);
    let y_int = b.y[0] + m1 * b.y[1] + m2 * b.y[2];
    if !(y_int > 0.0 && lum > 0.0) {
        return [0.0; N];
    }
    let k = lum / (LUMINOUS_EFFICACY * y_int);
    // A loop rather than `lambda.map(…)`, whose closure was not inlined (0.7 % of the
    // flagship's render).
    let mut out = [0.0; N];
    for (o, &l) in out.iter_mut().zip(&lambda) {
        let s = b.eval(l);
        *o = (k * (s[0] + m1 * s[1] + m2 * s[2])).max(0.0);
    }
    out
}

/// A clear sky for one sun position and turbidity, in the sky's local frame (+y = zenith).
#[derive(Clone, Debug)]
pub struct PreethamSky {
    /// Unit direction towards the sun (local frame).
    pub sun: Vec3,
    pub turbidity: f32,
    perez: [Perez; 3],
    /// Zenith value / F(0, θ_s) for Y (cd/m²), x and y.
    norm: [f32; 3],
}

impl PreethamSky {
    /// The sky for turbidity `t` with the sun along `sun` (local frame, normalised here);
    /// `None` when the sun is below the horizon, where the model does not apply.
    pub fn new(t: f32, sun: Vec3) -> Option<PreethamSky> {
        let sun = sun.normalize_or_zero();
        if sun.y <= 0.0 || t.is_nan() || t <= 0.0 {
            return None;
        }
        let theta_s = crate::math::safe_acos(sun.y);
        let perez = [Perez::luminance(t), Perez::chroma_x(t), Perez::chroma_y(t)];
        let (zx, zy) = zenith_chromaticity(t, theta_s);
        let zenith = [1000.0 * zenith_luminance(t, theta_s).max(0.0), zx, zy];
        let norm = std::array::from_fn(|i| zenith[i] / perez[i].eval(1.0, theta_s));
        Some(PreethamSky {
            sun,
            turbidity: t,
            perez,
            norm,
        })
    }

    /// Luminance (cd/m²) and chromaticity (x, y) towards the unit local direction `d`; zero
    /// luminance below the horizon.
    #[inline]
    pub(crate) fn xyy(&self, d: Vec3) -> (f32, f32, f32) {
        if d.y <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        // cos γ is the dot product itself (clamped as `safe_acos` clamps it), not cos(acos(…)).
        let cg = d.dot(self.sun).clamp(-1.0, 1.0);
        let gamma = crate::math::safe_acos(cg);
        let f = |i: usize| self.norm[i] * self.perez[i].eval_cos(d.y, gamma, cg);
        let v = [f(0), f(1), f(2)];
        (v[0].max(0.0), v[1], v[2])
    }

    /// Luminance (cd/m²) towards `d`.
    pub fn luminance(&self, d: Vec3) -> f32 {
        self.xyy(d).0
    }

    /// Spectral radiance (W·m⁻²·sr⁻¹·nm⁻¹) towards `d` at the given wavelengths.
    pub fn radiance<const N: usize>(&self, d: Vec3, lambda: [f32; N]) -> [f32; N] {
        let (lum, x, y) = self.xyy(d);
        if lum <= 0.0 {
            return [0.0; N];
        }
        daylight_radiance(x, y, lum, lambda)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::cie::CIE_Y_INTEGRAL;

    #[test]
    fn zenith_values_match_the_papers_formulas_by_hand() {
        // The paper's equations evaluated independently (by hand / in Python, in f64) for
        // T = 3, θs = 30°: χ = (4/9 − 3/120)(π − π/3) = 0.878482, tan χ = 1.205933,
        // Y_z = (12.1359 − 4.9710) · 1.205933 − 0.6465 + 2.4192 = 10.41309 kcd/m².
        let th = 30f32.to_radians();
        let y = zenith_luminance(3.0, th);
        assert!((y - 10.41309).abs() < 2e-3, "{y}");
        // x_z with θ = 0.523599 (θ³ = 0.143547, θ² = 0.274156): the T² row gives 0.00030453,
        // the T row 0.00049009, the constant row 0.24922318, so
        // x_z = 9 · 0.00030453 + 3 · 0.00049009 + 0.24922318 = 0.253434.
        let (x, _) = zenith_chromaticity(3.0, th);
        assert!((x - 0.253434).abs() < 2e-5, "{x}");
        // The sky at the zenith reproduces the zenith values exactly.
        let sun = Vec3::new(th.sin(), th.cos(), 0.0);
        let sky = PreethamSky::new(3.0, sun).unwrap();
        let (l, sx, _) = sky.xyy(Vec3::Y);
        assert!((l - 1000.0 * y).abs() < 1e-3 * l && (sx - x).abs() < 1e-5);
    }

    #[test]
    fn perez_function_by_hand() {
        // F(θ = 60°, γ = 45°) for T = 3: A = −0.9269, B = −0.6387, C = 5.2570, D = −2.2153,
        // E = 0.1693. (1 + A e^{2B}) = 0.741616; (1 + C e^{Dγ} + E/2) = 2.007460;
        // F = 1.488765.
        let p = Perez::luminance(3.0);
        let f = p.eval(0.5, std::f32::consts::FRAC_PI_4);
        assert!((f - 1.488765).abs() < 1e-4, "{f}");
    }

    #[test]
    fn daylight_spectrum_has_the_requested_luminance_and_chromaticity() {
        // D65's chromaticity; luminance 1000 cd/m².
        let (x, y) = (0.31271, 0.32902);
        let lambda: [f32; 471] = std::array::from_fn(|i| 360.0 + i as f32);
        let l = daylight_radiance(x, y, 1000.0, lambda);
        let mut xyz = [0.0f32; 3];
        for (i, &v) in l.iter().enumerate() {
            let b = xyz_bar(lambda[i]);
            for c in 0..3 {
                xyz[c] += v * b[c];
            }
        }
        let lum = LUMINOUS_EFFICACY * xyz[1];
        assert!((lum - 1000.0).abs() < 0.1, "{lum}");
        let s = xyz[0] + xyz[1] + xyz[2];
        assert!((xyz[0] / s - x).abs() < 2e-3 && (xyz[1] / s - y).abs() < 2e-3);
        // Mean radiance ≈ luminance / (683 · ∫ȳ) for a near-flat spectrum.
        let flat = 1000.0 / (LUMINOUS_EFFICACY * CIE_Y_INTEGRAL);
        assert!((l[200] / flat - 1.0).abs() < 0.2);
    }
}
