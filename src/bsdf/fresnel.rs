//! Fresnel equations for smooth interfaces (unpolarised light).
//!
//! - Dielectric: the textbook s/p amplitude reflectances of a real index ratio
//!   (Born & Wolf, *Principles of Optics*, §1.5), averaged in intensity.
//! - Conductor: the same equations with a complex index η + iκ, evaluated exactly with complex
//!   arithmetic (no approximation such as Schlick's or the "artist friendly" fit).
//! - Hemispherical (cosine-weighted) average of the dielectric reflectance, the "diffuse Fresnel
//!   reflectance" used by the plastic models: computed by composite Simpson quadrature in f64 on
//!   the side η > 1, where the integrand is smooth, and mapped to η < 1 through the exact
//!   reciprocity identity 1 − F̄(1/η) = (1 − F̄(η))/η² (no polynomial fit).
//!
//! Index convention: `eta` is n_transmitted / n_incident for light arriving from the side the
//! normal points to (cos θi > 0); a negative cosine means the other side, where 1/η applies.
//!
//! [`Fresnel`] is what a surface asks of its interface: the reflectance at the path's
//! wavelengths and how light goes on through it. The smooth and microfacet surfaces
//! ([`super::smooth`], [`super::rough`]) are generic over it; its implementations are the
//! dielectric and thin-sheet interfaces here, the conductor ([`ConductorFresnel`]), and the thin
//! film ([`super::filmfresnel::FilmFresnel`]).

use crate::math::Vec3;
use crate::simd::Float;
use crate::spectrum::SampledSpectrum;
use std::fmt::Debug;

/// How light that is not reflected leaves an interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Transmission {
    /// It does not: it is absorbed (a metal).
    Absorbed,
    /// It refracts into a medium of relative index `eta` (interior / exterior).
    Refract { eta: f32 },
    /// It passes straight on, undeviated (a thin sheet with parallel faces).
    Straight,
}

/// An interface's Fresnel term at one shading point.
pub trait Fresnel: Clone + Debug {
    /// Reflectance per wavelength for light meeting the interface at `cos` (signed: negative
    /// is from inside), and the probability with which sampling should choose reflection (a
    /// value close to the mean of the reflectances keeps the path weights near 1).
    fn reflectance(&self, cos: f32) -> (SampledSpectrum, f32);

    /// The reflectance of microfacet `wm` for the pair (wo, wi); by default at wo·wm.
    fn microfacet(&self, wo: Vec3, _wi: Vec3, wm: Vec3) -> (SampledSpectrum, f32) {
        self.reflectance(wo.dot(wm))
    }

    /// What happens to the light that is not reflected.
    fn transmission(&self) -> Transmission;
}

/// A smooth boundary between two dielectrics of relative index `eta` (interior / exterior).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricFresnel {
    pub eta: f32,
}

impl Fresnel for DielectricFresnel {
    #[inline]
    fn reflectance(&self, cos: f32) -> (SampledSpectrum, f32) {
        let f = fresnel_dielectric(cos, self.eta);
        (SampledSpectrum::splat(f), f)
    }

    /// Mathematically F(wo·wm) = F(wi·wm) for a refraction pair; evaluating it from the
    /// optically thinner side avoids the cancellation in cos θt near total internal
    /// reflection, which keeps f reciprocal to f32 precision.
    #[inline]
    fn microfacet(&self, wo: Vec3, wi: Vec3, wm: Vec3) -> (SampledSpectrum, f32) {
        let w = if (wo.z > 0.0) == (self.eta >= 1.0) {
            wo
        } else {
            wi
        };
        self.reflectance(w.dot(wm))
    }

    fn transmission(&self) -> Transmission {
        Transmission::Refract { eta: self.eta }
    }
}

/// The two parallel faces of a thin dielectric sheet of relative index `eta`, with every
/// internal reflection summed incoherently: R' = R + T²R / (1 − R²) from the single-face
/// R = F(|cos θ|, η), T = 1 − R; what is not reflected passes straight through.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinSheetFresnel {
    pub eta: f32,
}

impl ThinSheetFresnel {
    /// Reflectance of the sheet including interreflections.
    pub(crate) fn sheet_reflectance(&self, cos: f32) -> f32 {
        let r = fresnel_dielectric(cos.abs(), self.eta);
        if r < 1.0 {
            let t = 1.0 - r;
            r + t * t * r / (1.0 - r * r)
        } else {
            1.0
        }
    }
}

impl Fresnel for ThinSheetFresnel {
    #[inline]
    fn reflectance(&self, cos: f32) -> (SampledSpectrum, f32) {
        let r = self.sheet_reflectance(cos);
        (SampledSpectrum::splat(r), r)
    }
    fn transmission(&self) -> Transmission {
        Transmission::Straight
    }
}

// The scalar reference that the tests check the lanes version against.
#[cfg(test)]
/// s- and p-polarised reflectances (|r_s|², |r_p|²) of a dielectric interface, and the signed
/// cosine of the refracted direction (opposite sign to `cos_theta_i`, 0 under total internal
/// reflection, where both reflectances are 1).
pub(crate) fn fresnel_dielectric_polarized(cos_theta_i: f32, eta: f32) -> (f32, f32, f32) {
    let (cos_i, eta) = if cos_theta_i < 0.0 {
        (-cos_theta_i, 1.0 / eta)
    } else {
        (cos_theta_i, eta)
    };
    let cos_i = cos_i.min(1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return (1.0, 1.0, 0.0);
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    (rs * rs, rp * rp, -cos_t.copysign(cos_theta_i))
}

/// Unpolarised reflectance of a dielectric interface with relative index `eta`.
#[inline]
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    fresnel_dielectric_lanes(cos_theta_i, eta)
}

/// [`fresnel_dielectric`] on lanes (the operations of [`fresnel_dielectric_polarized`]).
#[inline(always)]
pub fn fresnel_dielectric_lanes<F: Float>(cos_theta_i: F, eta: F) -> F {
    let one = F::splat(1.0);
    let inside = cos_theta_i.lt(F::splat(0.0));
    let cos_i = F::select(inside, -cos_theta_i, cos_theta_i).min(one);
    let eta = F::select(inside, one / eta, eta);
    let sin2_t = (one - cos_i * cos_i) / (eta * eta);
    let cos_t = (one - sin2_t).max(F::splat(0.0)).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r = F::splat(0.5) * (rs * rs + rp * rp);
    F::select(sin2_t.ge(one), one, r)
}

#[cfg(test)]
/// Unpolarised reflectance and the signed cosine of the refracted direction (see
/// [`fresnel_dielectric_polarized`]).
#[inline]
pub(crate) fn fresnel_dielectric_cos_t(cos_theta_i: f32, eta: f32) -> (f32, f32) {
    let (rs, rp, cos_t) = fresnel_dielectric_polarized(cos_theta_i, eta);
    (0.5 * (rs + rp), cos_t)
}

/// Unpolarised reflectance of a conductor with complex relative index `eta + i k`, per
/// wavelength; `cos_theta_i` is taken in absolute value (metals are opaque).
pub(crate) fn fresnel_conductor(
    cos_theta_i: f32,
    eta: SampledSpectrum,
    k: SampledSpectrum,
) -> SampledSpectrum {
    SampledSpectrum::from_fn(|j| fresnel_conductor_lanes(cos_theta_i, eta[j], k[j]))
}

/// Complex numbers on lanes, with the few operations the conductor needs.
#[derive(Clone, Copy, Debug)]
struct Complex<F> {
    re: F,
    im: F,
}

impl<F: Float> Complex<F> {
    #[inline(always)]
    fn new(re: F, im: F) -> Self {
        Complex { re, im }
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Complex::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let n = o.re * o.re + o.im * o.im;
        Complex::new(
            (self.re * o.re + self.im * o.im) / n,
            (self.im * o.re - self.re * o.im) / n,
        )
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Complex::new(self.re + o.re, self.im + o.im)
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Complex::new(self.re - o.re, self.im - o.im)
    }
    #[inline(always)]
    fn norm_sqr(self) -> F {
        self.re * self.re + self.im * self.im
    }
    /// The principal square root (Re ≥ 0), algebraically: with r = |z|, the larger of the two
    /// parts is √((r + |Re z|)/2) and the other follows by division, free of cancellation.
    #[inline(always)]
    fn sqrt(self) -> Self {
        let zero = F::splat(0.0);
        let r = self.norm_sqr().sqrt();
        let t = ((r + self.re.abs()) * F::splat(0.5)).sqrt();
        let other = self.im.abs() / (t + t);
        let nonneg = self.re.ge(zero);
        let re = F::select(nonneg, t, other);
        let im = F::select(nonneg, self.im / (t + t), t.copysign(self.im));
        let z = t.eq(zero);
        Complex::new(F::select(z, zero, re), F::select(z, zero, im))
    }
}

/// [`fresnel_conductor`] for one wavelength on lanes.
#[inline(always)]
pub fn fresnel_conductor_lanes<F: Float>(cos_theta_i: F, eta: F, k: F) -> F {
    let zero = F::splat(0.0);
    let one = F::splat(1.0);
    let cos_i = cos_theta_i.abs().min(one);
    let sin2_i = one - cos_i * cos_i;
    let n = Complex::new(eta, k);
    // Snell's law with a complex index: cos θt = sqrt(1 − sin²θi / n²), principal root.
    let cos_t = Complex::new(one, zero)
        .sub(Complex::new(sin2_i, zero).div(n.mul(n)))
        .sqrt();
    let ci = Complex::new(cos_i, zero);
    let nc = n.mul(cos_t);
    let rs = ci.sub(nc).div(ci.add(nc));
    let nci = n.mul(ci);
    let rp = nci.sub(cos_t).div(nci.add(cos_t));
    F::splat(0.5) * (rs.norm_sqr() + rp.norm_sqr())
}

/// The Fresnel behaviour of a conductor: a perfect mirror (Mitsuba's `material = "none"`) or a
/// complex index (already divided by the exterior index) per wavelength.
#[derive(Clone, Copy, Debug)]
pub enum ConductorFresnel {
    /// Reflects everything (F = 1).
    Mirror,
    /// Complex relative index η + iκ.
    Complex {
        eta: SampledSpectrum,
        k: SampledSpectrum,
    },
}

impl ConductorFresnel {
    /// Reflectance at the given cosine.
    #[inline]
    pub fn eval(&self, cos_theta_i: f32) -> SampledSpectrum {
        match self {
            ConductorFresnel::Mirror => SampledSpectrum::ONE,
            ConductorFresnel::Complex { eta, k } => fresnel_conductor(cos_theta_i, *eta, *k),
        }
    }
}

impl Fresnel for ConductorFresnel {
    #[inline]
    fn reflectance(&self, cos: f32) -> (SampledSpectrum, f32) {
        // Metals only reflect, so the choice probability is never used for a lobe choice.
        (self.eval(cos), 1.0)
    }
    fn transmission(&self) -> Transmission {
        Transmission::Absorbed
    }
}

/// Cosine-weighted hemispherical average 2∫₀¹ F(μ, η) μ dμ of the dielectric reflectance for
/// light arriving from the side where the relative index is `eta` (so `1/eta` gives the
/// internal average seen from inside a coating of index `eta`).
pub(crate) fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    if eta == 1.0 {
        return 0.0;
    }
    if eta > 1.0 {
        diffuse_reflectance_dense(eta as f64) as f32
    } else {
        // Reciprocity: the cosine-weighted energy transmitted from the dense side equals that
        // transmitted into it, divided by the index ratio squared.
        let e = 1.0 / eta as f64;
        (1.0 - (1.0 - diffuse_reflectance_dense(e)) / (e * e)) as f32
    }
}

fn diffuse_reflectance_dense(eta: f64) -> f64 {
    // Composite Simpson over μ ∈ [0, 1]; the integrand has a √ behaviour only in cos θt, which
    // is bounded away from 0 for η > 1, so the rule converges at its nominal fourth order.
    let f = |mu: f64| {
        let sin2_t = (1.0 - mu * mu) / (eta * eta);
        let ct = (1.0 - sin2_t).sqrt();
        let rs = (mu - eta * ct) / (mu + eta * ct);
        let rp = (eta * mu - ct) / (eta * mu + ct);
        0.5 * (rs * rs + rp * rp) * mu
    };
    let n = 2048;
    let h = 1.0 / n as f64;
    let mut s = f(0.0) + f(1.0);
    for i in 1..n {
        s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    2.0 * s * h / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_matches_closed_form() {
        for &eta in &[1.33f32, 1.5, 2.4] {
            let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
            assert!((fresnel_dielectric(1.0, eta) - r0).abs() < 1e-6);
            // From inside, the same value at normal incidence.
            assert!((fresnel_dielectric(-1.0, eta) - r0).abs() < 1e-6);
        }
    }

    #[test]
    fn brewster_angle_cancels_p() {
        let eta = 1.5f32;
        let cos_b = eta.atan().cos();
        let (rs, rp, _) = fresnel_dielectric_polarized(cos_b, eta);
        assert!(rp < 1e-10, "rp {rp}");
        assert!(rs > 0.1);
    }

    #[test]
    fn total_internal_reflection_beyond_critical_angle() {
        let eta = 1.5f32;
        let sin_c = 1.0 / eta;
        let cos_c = (1.0 - sin_c * sin_c).sqrt();
        // Inside the dense medium (cos < 0): just beyond the critical angle reflects all.
        assert_eq!(fresnel_dielectric(-(cos_c - 0.01), eta), 1.0);
        assert!(fresnel_dielectric(-(cos_c + 0.01), eta) < 1.0);
    }

    #[test]
    fn refracted_cosine_obeys_snell() {
        let eta = 1.5f32;
        let ci = 0.6f32;
        let (_, ct) = fresnel_dielectric_cos_t(ci, eta);
        let si = (1.0 - ci * ci).sqrt();
        let st = (1.0 - ct * ct).sqrt();
        assert!(ct < 0.0);
        assert!((si - eta * st).abs() < 1e-6);
    }

    #[test]
    fn conductor_normal_incidence_gold() {
        // Gold at 550 nm: n = 0.4, k = 2.4 → ((n−1)² + k²)/((n+1)² + k²) = 6.12/7.72.
        let r = fresnel_conductor(
            1.0,
            SampledSpectrum::splat(0.4),
            SampledSpectrum::splat(2.4),
        );
        assert!((r[0] - 6.12 / 7.72).abs() < 1e-6, "{}", r[0]);
    }

    #[test]
    fn conductor_with_zero_k_is_dielectric() {
        for &c in &[1.0f32, 0.7, 0.3, 0.05] {
            let r = fresnel_conductor(c, SampledSpectrum::splat(1.5), SampledSpectrum::ZERO);
            assert!((r[0] - fresnel_dielectric(c, 1.5)).abs() < 1e-5);
        }
    }

    #[test]
    fn diffuse_reflectance_is_consistent() {
        // Compare with a brute-force midpoint integral of the f32 Fresnel on both sides.
        for &eta in &[1.33f32, 1.5, 1.0 / 1.5] {
            let n = 200_000;
            let s: f64 = (0..n)
                .map(|i| {
                    let mu = (i as f64 + 0.5) / n as f64;
                    2.0 * fresnel_dielectric(mu as f32, eta) as f64 * mu / n as f64
                })
                .sum();
            let q = fresnel_diffuse_reflectance(eta) as f64;
            assert!((s - q).abs() < 1e-5, "eta {eta}: {s} vs {q}");
        }
        // The internal average of a glass coating is large (≈ 0.6 for η = 1.5).
        assert!(fresnel_diffuse_reflectance(1.0 / 1.5) > 0.55);
    }
}
