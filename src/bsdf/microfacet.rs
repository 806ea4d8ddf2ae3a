//! Microfacet normal distributions: GGX / Trowbridge–Reitz and Beckmann, anisotropic.
//!
//! - GGX: Trowbridge & Reitz 1975; Walter et al. 2007, "Microfacet Models for Refraction through
//!   Rough Surfaces". Beckmann: Beckmann & Spizzichino 1963, as written in Walter et al. 2007.
//! - Anisotropy by stretching (Heitz 2014, "Understanding the Masking-Shadowing Function in
//!   Microfacet-Based BRDFs"): `alpha_x`, `alpha_y` are the roughnesses along the local x and y.
//! - Shadowing-masking: Smith's Λ of each distribution, combined **height-correlated**,
//!   G(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi)), everywhere in ophis.
//! - Sampling of visible normals, exact for both: GGX by Heitz 2018, "Sampling the GGX
//!   Distribution of Visible Normals" (JCGT 7(4)); Beckmann by the slope-space method of Heitz &
//!   d'Eon 2014 ("Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible
//!   Normals"), with the one-dimensional inverse CDF solved to machine precision by safeguarded
//!   Newton iteration in f64 instead of their approximate fit.
//!   Density: pdf(wm | w) = G1(w) · max(0, w·wm) · D(wm) / |cos θw|.
//!
//! Directions below the surface (w.z < 0) are treated through −w, so that a microfacet BSDF can
//! sample from inside a dielectric; sampled normals always have wm.z > 0.
//!
//! Known limits: roughness is clamped to ≥ 1e-4 (smaller values underflow in f32); Beckmann's
//! erfc uses a Chebyshev fit with relative error below 1.2e-7.

use crate::math::{Vec2, Vec3, PI};
use crate::simd::fastmath::sin_cos;
use crate::simd::{Float, V3};

/// Which normal distribution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MicrofacetType {
    Ggx,
    Beckmann,
}

impl MicrofacetType {
    /// From Mitsuba's `distribution` parameter (`"ggx"` or `"beckmann"`); `None` otherwise.
    pub fn from_name(name: &str) -> Option<MicrofacetType> {
        match name {
            "ggx" => Some(MicrofacetType::Ggx),
            "beckmann" => Some(MicrofacetType::Beckmann),
            _ => None,
        }
    }
}

/// A microfacet distribution with its roughnesses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MicrofacetDistribution {
    pub kind: MicrofacetType,
    pub alpha_x: f32,
    pub alpha_y: f32,
}

const MIN_ALPHA: f32 = 1e-4;

impl MicrofacetDistribution {
    /// A distribution with roughnesses clamped to at least 1e-4.
    pub fn new(kind: MicrofacetType, alpha_x: f32, alpha_y: f32) -> Self {
        MicrofacetDistribution {
            kind,
            alpha_x: alpha_x.max(MIN_ALPHA),
            alpha_y: alpha_y.max(MIN_ALPHA),
        }
    }

    /// Density of microfacet normals per unit solid angle (0 below the surface); normalised so
    /// that ∫ D(m) cos θm dm = 1.
    pub fn d(&self, wm: Vec3) -> f32 {
        if self.kind == MicrofacetType::Ggx {
            return self.ggx().d(wm.into());
        }
        let z2 = wm.z * wm.z;
        if wm.z <= 0.0 || z2 == 0.0 {
            return 0.0;
        }
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        let e = (wm.x * wm.x / (ax * ax) + wm.y * wm.y / (ay * ay)) / z2;
        let norm = PI * ax * ay * z2 * z2;
        let d = (-e).exp() / norm;
        if d.is_finite() {
            d
        } else {
            0.0
        }
    }

    /// The GGX distribution of these roughnesses, on one lane.
    #[inline]
    fn ggx(&self) -> GgxL<f32> {
        GgxL {
            ax: self.alpha_x,
            ay: self.alpha_y,
        }
    }

    /// Smith's Λ(w) (depends on w only through tan²θ and φ, so it is even in w.z).
    pub fn lambda(&self, w: Vec3) -> f32 {
        let z2 = w.z * w.z;
        if z2 == 0.0 {
            return f32::INFINITY;
        }
        let a2t2 = (self.alpha_x * self.alpha_x * w.x * w.x
            + self.alpha_y * self.alpha_y * w.y * w.y)
            / z2;
        match self.kind {
            MicrofacetType::Ggx => self.ggx().lambda(w.into()),
            MicrofacetType::Beckmann => {
                if a2t2 == 0.0 {
                    return 0.0;
                }
                let a = 1.0 / (a2t2 as f64).sqrt();
                let l = -0.5 * erfc(a) + (-a * a).exp() / (2.0 * a * std::f64::consts::PI.sqrt());
                l.max(0.0) as f32
            }
        }
    }

    /// Smith masking of one direction, 1 / (1 + Λ(w)).
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing of the pair.
    #[inline]
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of visible normals seen from `w` (from −w when `w` is below the surface), per
    /// unit solid angle of `wm`.
    pub fn pdf(&self, w: Vec3, wm: Vec3) -> f32 {
        if self.kind == MicrofacetType::Ggx {
            return self.ggx().pdf(w.into(), wm.into());
        }
        let w = if w.z < 0.0 { -w } else { w };
        if w.z == 0.0 {
            return 0.0;
        }
        let c = w.dot(wm);
        if c <= 0.0 {
            return 0.0;
        }
        self.g1(w) * c * self.d(wm) / w.z
    }

    /// Samples a visible normal as seen from `w` (from −w when `w` is below); wm.z ≥ 0.
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        if self.kind == MicrofacetType::Ggx {
            return self.ggx().sample_wm(w.into(), u.x, u.y).into();
        }
        let w = if w.z < 0.0 { -w } else { w };
        // Stretch to the isotropic unit-roughness configuration.
        let wh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize();
        let nh = sample_beckmann_unit(wh, u);
        // Unstretch (normals transform with the inverse transpose).
        let m = Vec3::new(self.alpha_x * nh.x, self.alpha_y * nh.y, nh.z.max(0.0));
        let len = m.length();
        if len > 0.0 {
            m / len
        } else {
            Vec3::Z
        }
    }
}

/// GGX with its roughnesses per lane: D, Smith's Λ, the visible-normal density and its
/// sampling (Heitz 2018), operation for operation what [`MicrofacetDistribution`] computes for
/// GGX (which calls these on one lane).
#[derive(Clone, Copy, Debug)]
pub struct GgxL<F> {
    pub ax: F,
    pub ay: F,
}

impl<F: Float> GgxL<F> {
    /// Normal density D(wm) (0 below the surface or where it overflows).
    #[inline(always)]
    pub fn d(&self, wm: V3<F>) -> F {
        let zero = F::splat(0.0);
        let one = F::splat(1.0);
        let (ax, ay) = (self.ax, self.ay);
        let z2 = wm.z * wm.z;
        let e = (wm.x * wm.x / (ax * ax) + wm.y * wm.y / (ay * ay)) / z2;
        let norm = F::splat(PI) * ax * ay * z2 * z2;
        let d = one / (norm * (one + e) * (one + e));
        let ok = !(wm.z.le(zero) | z2.eq(zero)) & d.is_finite();
        F::select(ok, d, zero)
    }

    /// Smith's Λ(w) (+∞ at grazing).
    #[inline(always)]
    pub fn lambda(&self, w: V3<F>) -> F {
        let z2 = w.z * w.z;
        let a2t2 = (self.ax * self.ax * w.x * w.x + self.ay * self.ay * w.y * w.y) / z2;
        let l = F::splat(0.5) * ((F::splat(1.0) + a2t2).sqrt() - F::splat(1.0));
        F::select(z2.eq(F::splat(0.0)), F::splat(f32::INFINITY), l)
    }

    /// Smith masking 1 / (1 + Λ(w)).
    #[inline(always)]
    pub fn g1(&self, w: V3<F>) -> F {
        F::splat(1.0) / (F::splat(1.0) + self.lambda(w))
    }

    /// Height-correlated masking-shadowing.
    #[inline(always)]
    pub fn g(&self, wo: V3<F>, wi: V3<F>) -> F {
        F::splat(1.0) / (F::splat(1.0) + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of visible normals seen from `w` (from −w below the surface).
    #[inline(always)]
    pub fn pdf(&self, w: V3<F>, wm: V3<F>) -> F {
        let zero = F::splat(0.0);
        let w = V3::select(w.z.lt(zero), -w, w);
        let c = w.dot(wm);
        let p = self.g1(w) * c * self.d(wm) / w.z;
        F::select(w.z.eq(zero) | c.le(zero), zero, p)
    }

    /// A visible normal seen from `w` (from −w below the surface); wm.z ≥ 0.
    #[inline(always)]
    pub fn sample_wm(&self, w: V3<F>, u0: F, u1: F) -> V3<F> {
        let zero = F::splat(0.0);
        let one = F::splat(1.0);
        let w = V3::select(w.z.lt(zero), -w, w);
        // Stretch to the isotropic unit-roughness configuration.
        let wh = V3::new(self.ax * w.x, self.ay * w.y, w.z).normalize();
        // A uniform point on the projected hemisphere: a disk warped towards the visible half.
        let lensq = wh.x * wh.x + wh.y * wh.y;
        let t1 = V3::new(-wh.y, wh.x, zero) / lensq.sqrt();
        let t1 = V3::select(lensq.gt(zero), t1, V3::new(one, zero, zero));
        let t2 = wh.cross(t1);
        let r = u0.sqrt();
        let phi = F::splat(2.0 * PI) * u1;
        let (s, c) = sin_cos(phi);
        let p1 = r * c;
        let p2 = r * s;
        let h = F::splat(0.5) * (one + wh.z);
        let p2 = (one - h) * (one - p1 * p1).max(zero).sqrt() + h * p2;
        let pz = (one - p1 * p1 - p2 * p2).max(zero).sqrt();
        let nh = t1 * p1 + t2 * p2 + wh * pz;
        // Unstretch (normals transform with the inverse transpose).
        let m = V3::new(self.ax * nh.x, self.ay * nh.y, nh.z.max(zero));
        let len = m.length();
        V3::select(len.gt(zero), m / len, V3::new(zero, zero, one))
    }
}

/// Visible normal of the unit-roughness Beckmann seen from `wh`, through slope space: the slope
/// density along the incident azimuth is ∝ (1 − x tan θ) e^{−x²} for x < cot θ, the orthogonal
/// slope is an independent Gaussian e^{−y²}/√π.
fn sample_beckmann_unit(wh: Vec3, u: Vec2) -> Vec3 {
    let cos_t = (wh.z as f64).clamp(0.0, 1.0);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let tan_t = if cos_t > 0.0 { sin_t / cos_t } else { 1e30 };
    let sqrt_pi = std::f64::consts::PI.sqrt();
    const X_LO: f64 = -9.0;
    let x_hi = if tan_t > 1e-9 {
        (1.0 / tan_t).min(9.0)
    } else {
        9.0
    };
    // CDF (unnormalised) of the slope along the azimuth, and its derivative.
    let cdf = |x: f64| 0.5 * erfc(-x) + tan_t * (-x * x).exp() / (2.0 * sqrt_pi);
    let dens = |x: f64| (-x * x).exp() * (1.0 - x * tan_t) / sqrt_pi;
    let target = (u.x as f64) * cdf(x_hi);
    let sx = solve_monotone(cdf, dens, target, X_LO, x_hi);
    let sy = solve_monotone(
        |y| 0.5 * erfc(-y),
        |y| (-y * y).exp() / sqrt_pi,
        u.y as f64,
        -9.0,
        9.0,
    );
    // Rotate the slopes to the azimuth of wh; the normal is (−slope, 1) normalised.
    let (cp, sp) = if sin_t > 0.0 {
        (wh.x as f64 / sin_t, wh.y as f64 / sin_t)
    } else {
        (1.0, 0.0)
    };
    let mx = cp * sx - sp * sy;
    let my = sp * sx + cp * sy;
    Vec3::new(-mx as f32, -my as f32, 1.0).normalize()
}

/// Solves cdf(x) = target for an increasing `cdf` on [lo, hi] with derivative `dens`, by Newton
/// steps kept inside a shrinking bracket (bisection when a step leaves it).
fn solve_monotone(
    cdf: impl Fn(f64) -> f64,
    dens: impl Fn(f64) -> f64,
    target: f64,
    mut lo: f64,
    mut hi: f64,
) -> f64 {
    let mut x = 0.0f64.clamp(lo, hi);
    for _ in 0..100 {
        let v = cdf(x) - target;
        if v == 0.0 {
            break;
        }
        if v > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        if hi - lo < 1e-13 {
            break;
        }
        let d = dens(x);
        let mut xn = x - v / d;
        if !(xn > lo && xn < hi) {
            xn = 0.5 * (lo + hi);
        }
        if (xn - x).abs() < 1e-14 {
            x = xn;
            break;
        }
        x = xn;
    }
    x
}

/// Complementary error function with relative error below 1.2e-7 (a Chebyshev fit of
/// erfc(z)·exp(z²), Numerical Recipes 2nd ed. §6.2).
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let p = -1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * (-z * z + p).exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::spherical_direction;

    fn dists() -> Vec<MicrofacetDistribution> {
        let mut v = Vec::new();
        for kind in [MicrofacetType::Ggx, MicrofacetType::Beckmann] {
            for (ax, ay) in [(0.05, 0.05), (0.2, 0.2), (0.6, 0.6), (0.1, 0.4)] {
                v.push(MicrofacetDistribution::new(kind, ax, ay));
            }
        }
        v
    }

    /// Midpoint rule over (θ, φ) of the upper hemisphere; fine enough in θ for α = 0.05.
    fn integrate_hemisphere(f: impl Fn(Vec3) -> f64) -> f64 {
        let (nt, np) = (3000, 128);
        let (dt, dp) = (
            0.5 * std::f64::consts::PI / nt as f64,
            2.0 * std::f64::consts::PI / np as f64,
        );
        let mut s = 0.0;
        for i in 0..nt {
            let t = (i as f64 + 0.5) * dt;
            let (st, ct) = t.sin_cos();
            for j in 0..np {
                let p = (j as f64 + 0.5) * dp;
                let w = spherical_direction(st as f32, ct as f32, p as f32);
                s += f(w) * st * dt * dp;
            }
        }
        s
    }

    #[test]
    fn erfc_known_values() {
        for (x, e) in [
            (0.5, 0.520_499_877_8),
            (1.0, 0.842_700_792_9),
            (2.0, 0.995_322_265),
        ] {
            assert!(((1.0 - erfc(x)) - e).abs() < 2e-7, "erf({x})");
            assert!(((erfc(-x) - 1.0) - e).abs() < 2e-7);
        }
    }

    #[test]
    fn projected_area_is_one() {
        // Quadrature error of the midpoint rule at this resolution is well below 1e-3.
        for d in dists() {
            let s = integrate_hemisphere(|m| d.d(m) as f64 * m.z as f64);
            assert!((s - 1.0).abs() < 1e-3, "{d:?}: {s}");
        }
    }

    #[test]
    fn visible_normal_pdf_is_normalised() {
        // ∫ pdf(wm | w) dwm = 1 holds only with the exact Smith Λ, so this also checks Λ.
        for d in dists() {
            for theta in [0.2f32, 0.8, 1.3] {
                let w = spherical_direction(theta.sin(), theta.cos(), 0.7);
                let s = integrate_hemisphere(|m| d.pdf(w, m) as f64);
                assert!((s - 1.0).abs() < 2e-3, "{d:?} θ {theta}: {s}");
            }
        }
    }

    #[test]
    fn sampled_normals_have_the_stated_density() {
        // E[g(wm)] under sampling equals ∫ g pdf for g = wm.z (both sides computed here); 4σ.
        let mut rng = crate::math::Pcg32::new(11, 3);
        for d in dists() {
            let w = spherical_direction(0.8f32.sin(), 0.8f32.cos(), 0.3);
            let n = 20_000;
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let m = d.sample_wm(w, rng.next_vec2());
                assert!(m.z >= 0.0 && (m.length() - 1.0).abs() < 1e-4);
                s += m.z as f64;
                s2 += (m.z as f64).powi(2);
            }
            let mean = s / n as f64;
            let sigma = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
            let exact = integrate_hemisphere(|m| d.pdf(w, m) as f64 * m.z as f64);
            assert!(
                (mean - exact).abs() < 4.0 * sigma + 1e-3,
                "{d:?}: {mean} vs {exact}"
            );
        }
    }
}
