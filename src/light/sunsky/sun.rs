//! The sun part of `sunsky` (and Mitsuba 0.6's `sun`): a disk of uniform radiance at infinity,
//! sampled uniformly in its cone of directions.
//!
//! Spectrum: a 5778 K blackbody (the sun's effective temperature; its radiance, ≈ 2.6·10⁴
//! W·m⁻²·sr⁻¹·nm⁻¹ at 550 nm, gives the solar constant over the disk's 6.8·10⁻⁵ sr) attenuated by
//! the atmosphere's Rayleigh and aerosol transmittances of Preetham, Shirley & Smits (1999),
//! Appendix A.1 (after Iqbal, "An Introduction to Solar Radiation", 1983):
//! τ_R = exp(−0.008735 λ^−4.08 m), τ_a = exp(−β λ^−α m) with λ in µm, α = 1.3,
//! β = 0.04608 T − 0.04586, and the relative optical mass
//! m = 1 / (cos θ_s + 0.15 (93.885 − θ_s[°])^−1.253) (Kasten 1966).
//! Ozone, water-vapour and mixed-gas absorption (tabulated in the paper) are left out: they
//! take a few per cent in the visible (ozone's Chappuis band near 600 nm) and more in the
//! near infrared (O₂ at 760 nm, H₂O at 720 and 820 nm). No limb darkening.
//!
//! The path's wavelengths read the spectrum from a table at 0.5 nm steps, linearly
//! interpolated: the formula costs four transcendental functions per wavelength (an f64
//! exponential and power in Planck's law, two powers and an exponential in the transmittance),
//! 16 per light sample, and took ~5 % of the flagship's render. Both factors are smooth on that
//! scale: the interpolation errs by at most (Δλ)²/8 · |f″/f| relative (tested against that
//! bound), below 1e-4 for a clear sky (turbidity ≤ 3) with the sun 10° or more above the
//! horizon; for a low sun in haze the bluest wavelengths' transmittance falls steeply and the
//! relative error there grows (5e-4 at 5° and turbidity 10), on values far below the red end's.

use crate::light::infinite::InfiniteLight;
use crate::math::{Frame, Vec2, Vec3, PI};
use crate::spectrum::spectra::blackbody;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};
use std::sync::Arc;

/// The sun's mean angular radius seen from the earth, degrees.
pub(crate) const SUN_ANGULAR_RADIUS_DEG: f64 = 0.2667;
/// The sun's effective temperature, kelvin.
pub(crate) const SUN_TEMPERATURE: f32 = 5778.0;
/// Directions within this relative margin of the disk's edge (in sin² of the angle) count as on
/// the disk, so that a direction the sampler drew never falls off it by rounding.
const EDGE_MARGIN: f32 = 1e-3;

/// Spacing of [`SunSpectrum`]'s table, nm.
const TABLE_STEP: f32 = 0.5;

/// The sun's spectral radiance after its path through the atmosphere.
#[derive(Clone, Debug)]
pub struct SunSpectrum {
    /// Relative optical air mass (0: the sun is below the horizon, no light).
    air_mass: f32,
    /// Ångström turbidity coefficient β.
    beta: f32,
    /// Overall factor (user scale × power-preserving radius factor, or × solid angle).
    scale: f32,
    /// [`SunSpectrum::eval`] at LAMBDA_MIN + k · TABLE_STEP nm, k = 0 … up to LAMBDA_MAX.
    table: Arc<[f32]>,
}

impl SunSpectrum {
    /// The spectrum for turbidity `t` with the sun at zenith angle `theta_s` (radians); black
    /// below the horizon.
    pub fn new(t: f32, theta_s: f32, scale: f32) -> SunSpectrum {
        let deg = theta_s.to_degrees();
        let air_mass = if deg < 90.0 {
            1.0 / (theta_s.cos() + 0.15 * (93.885 - deg).powf(-1.253))
        } else {
            0.0
        };
        let mut s = SunSpectrum {
            air_mass,
            beta: 0.04608 * t - 0.04586,
            scale: if air_mass > 0.0 { scale } else { 0.0 },
            table: Arc::from([]),
        };
        let n = ((LAMBDA_MAX - LAMBDA_MIN) / TABLE_STEP).round() as usize;
        s.table = (0..=n)
            .map(|k| s.eval(LAMBDA_MIN + k as f32 * TABLE_STEP))
            .collect();
        s
    }

    /// [`SunSpectrum::eval`] interpolated in the table (the formula outside its range).
    #[inline]
    fn lookup(&self, lambda: f32) -> f32 {
        let x = (lambda - LAMBDA_MIN) * (1.0 / TABLE_STEP);
        let last = self.table.len() - 1;
        if !(x >= 0.0 && x < last as f32) {
            return self.eval(lambda);
        }
        let i = x as usize;
        let (a, b) = (self.table[i], self.table[i + 1]);
        a + (x - i as f32) * (b - a)
    }

    /// Transmittance of the atmosphere along the sun's path at `lambda` nm.
    pub fn transmittance(&self, lambda: f32) -> f32 {
        let um = lambda * 1e-3;
        let rayleigh = 0.008735 * um.powf(-4.08);
        let aerosol = self.beta * um.powf(-1.3);
        (-(rayleigh + aerosol) * self.air_mass).exp()
    }

    /// Radiance (times the factor) at `lambda` nm.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        if self.scale == 0.0 {
            return 0.0;
        }
        self.scale * blackbody(lambda, SUN_TEMPERATURE) * self.transmittance(lambda)
    }

    fn sample(&self, wl: &SampledWavelengths) -> SampledSpectrum {
        let l = wl.lambda;
        SampledSpectrum([
            self.lookup(l[0]),
            self.lookup(l[1]),
            self.lookup(l[2]),
            self.lookup(l[3]),
        ])
    }

    /// Mean over the rendered range at 10 nm steps.
    fn mean(&self) -> f32 {
        let n = ((LAMBDA_MAX - LAMBDA_MIN) / 10.0) as usize;
        (0..=n)
            .map(|i| self.eval(LAMBDA_MIN + 10.0 * i as f32))
            .sum::<f32>()
            / (n + 1) as f32
    }
}

/// The solar disk as a light.
#[derive(Clone, Debug)]
pub struct SunLight {
    /// Unit direction towards the sun (world).
    dir: Vec3,
    frame: Frame,
    /// 1 − cos α of the disk's angular radius α (0 for a delta light).
    one_minus_cos: f32,
    /// sin² α.
    sin2_max: f32,
    /// Solid angle of the disk, sr.
    solid_angle: f32,
    /// Radiance, or for a delta sun the irradiance.
    spectrum: SunSpectrum,
    delta: bool,
}

impl SunLight {
    /// The sun along `dir_world` (normalised here; `None` if zero), seen at zenith angle
    /// `theta_s` (radians) in the sky's frame, for turbidity `t`. `radius_scale` scales the
    /// disk's angular radius while keeping its power (0 makes it a directional light), and
    /// `scale` multiplies the radiance.
    pub fn new(
        dir_world: Vec3,
        theta_s: f32,
        t: f32,
        scale: f32,
        radius_scale: f32,
    ) -> Option<SunLight> {
        let dir = dir_world.normalize_or_zero();
        if dir == Vec3::ZERO {
            return None;
        }
        let true_alpha = SUN_ANGULAR_RADIUS_DEG.to_radians();
        let true_omega = 4.0 * PI as f64 * (0.5 * true_alpha).sin().powi(2);
        let delta = radius_scale.is_nan() || radius_scale <= 0.0;
        let alpha = true_alpha * radius_scale.max(0.0) as f64;
        // 1 − cos α = 2 sin²(α/2), accurate for the sun's tiny α, unlike 1 − cos in f32.
        let one_minus_cos = 2.0 * (0.5 * alpha).sin().powi(2);
        let omega = 2.0 * PI as f64 * one_minus_cos;
        let factor = if delta {
            true_omega
        } else {
            true_omega / omega
        };
        Some(SunLight {
            dir,
            frame: Frame::from_z(dir),
            one_minus_cos: one_minus_cos as f32,
            sin2_max: alpha.sin().powi(2) as f32,
            solid_angle: omega as f32,
            spectrum: SunSpectrum::new(t, theta_s, scale * factor as f32),
            delta,
        })
    }

    #[cfg(test)]
    /// Solid angle of the disk (0 for a delta sun).
    pub(crate) fn solid_angle(&self) -> f32 {
        self.solid_angle
    }

    /// The spectrum (radiance; irradiance for a delta sun).
    pub fn spectrum(&self) -> &SunSpectrum {
        &self.spectrum
    }

    /// Whether the world direction `d` is on the disk.
    #[inline]
    fn on_disk(&self, d: Vec3) -> bool {
        let d = d.normalize_or_zero();
        d.dot(self.dir) > 0.0
            && d.cross(self.dir).length_squared() <= self.sin2_max * (1.0 + EDGE_MARGIN)
    }
}

impl InfiniteLight for SunLight {
    /// Uniform in the disk's cone of directions; the sun's direction when it is a delta light.
    fn sample_wi(&self, _: Vec3, u: Vec2) -> Option<Vec3> {
        if self.spectrum.scale == 0.0 {
            return None;
        }
        if self.delta {
            return Some(self.dir);
        }
        let omc = u.x * self.one_minus_cos;
        let cos_theta = 1.0 - omc;
        let sin_theta = (omc * (2.0 - omc)).max(0.0).sqrt();
        let (s, c) = (2.0 * PI * u.y).sin_cos();
        let wi = Vec3::new(sin_theta * c, sin_theta * s, cos_theta);
        Some(self.frame.to_world(wi).normalize())
    }

    /// Uniform over the disk (0 for a delta sun).
    fn pdf_li(&self, _: Vec3, wi: Vec3) -> f32 {
        if self.delta || self.spectrum.scale == 0.0 || !self.on_disk(wi) {
            return 0.0;
        }
        1.0 / self.solid_angle
    }

    /// Radiance seen along the escaping direction `dir` (zero off the disk).
    fn le(&self, dir: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if self.delta || !self.on_disk(dir) {
            return SampledSpectrum::ZERO;
        }
        self.spectrum.sample(wl)
    }

    /// Whether the sun is a directional (delta) light.
    fn is_delta(&self) -> bool {
        self.delta
    }

    /// The radiance on the disk, or a delta sun's irradiance.
    fn li(&self, wi: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if self.delta {
            self.spectrum.sample(wl)
        } else {
            self.le(wi, wl)
        }
    }

    /// Power through the scene's bounding disk: π r² E, with E the irradiance's spectral mean.
    fn power(&self, r: f32) -> f32 {
        let e = if self.delta {
            self.spectrum.mean()
        } else {
            self.spectrum.mean() * self.solid_angle
        };
        PI * r * r * e
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::{mean_and_sigma, wl};
    use super::*;
    use crate::light::{Light, LightSampleContext};
    use crate::math::Pcg32;

    #[test]
    fn disk_has_the_suns_solid_angle_and_sampling_matches_pdf() {
        let dir = Vec3::new(0.3, 0.8, -0.5);
        let sun = SunLight::new(dir, 0.6, 3.0, 1.0, 1.0).unwrap();
        // Ω = 2π(1 − cos 0.2667°) = 6.80691e-5 sr.
        assert!(
            (sun.solid_angle() - 6.80691e-5).abs() < 1e-9,
            "{}",
            sun.solid_angle()
        );
        let light = Light::Sun(sun.clone().into());
        assert!(light.is_infinite() && !light.is_delta());
        let ctx = LightSampleContext {
            p: Vec3::ZERO,
            n: Vec3::ZERO,
        };
        let mut rng = Pcg32::new(5, 0);
        let axis = dir.normalize();
        let cos_max = SUN_ANGULAR_RADIUS_DEG.to_radians().cos() as f32;
        let mut inner = 0;
        let n = 20_000;
        for _ in 0..n {
            let s = light.sample_li(&ctx, rng.next_vec2(), &wl(), &[]).unwrap();
            assert_eq!(s.pdf, light.pdf_li(&ctx, s.wi, &[], None));
            assert!((s.pdf * sun.solid_angle() - 1.0).abs() < 1e-5);
            assert!(s.wi.dot(axis) >= cos_max - 1e-6);
            assert_eq!(light.le(s.wi, &wl())[2], s.l[2]);
            // Uniform in solid angle: the inner half of the cone's solid angle gets half.
            let sin2 = s.wi.cross(axis).length_squared();
            if sin2 < 0.5 * sun.sin2_max {
                inner += 1;
            }
        }
        let p = inner as f64 / n as f64;
        let sigma = (0.25 / n as f64).sqrt();
        assert!((p - 0.5).abs() < 4.0 * sigma, "{p}");
        // Off the disk: nothing.
        let off = (axis + 0.01 * Vec3::X).normalize();
        assert!(light.le(off, &wl()).is_black() && light.pdf_li(&ctx, off, &[], None) == 0.0);
    }

    #[test]
    fn irradiance_is_radiance_times_solid_angle_and_radius_scale_keeps_power() {
        let dir = Vec3::new(0.0, 1.0, 0.2);
        let n_surf = Vec3::new(0.0, 1.0, 0.0);
        let ctx = LightSampleContext {
            p: Vec3::ZERO,
            n: n_surf,
        };
        let mut rng = Pcg32::new(8, 0);
        let mut irr = |radius_scale: f32| {
            let sun = SunLight::new(dir, 0.2, 3.0, 1.0, radius_scale).unwrap();
            let light = Light::Sun(sun.into());
            mean_and_sigma((0..20_000).map(|_| {
                let s = light.sample_li(&ctx, rng.next_vec2(), &wl(), &[]).unwrap();
                (s.l[1] * s.wi.dot(n_surf).max(0.0) / s.pdf) as f64
            }))
        };
        let (e1, s1) = irr(1.0);
        let (e5, s5) = irr(5.0);
        let (e0, _) = irr(0.0);
        let cos = dir.normalize().dot(n_surf) as f64;
        // The delta sun's irradiance, projected, is the reference.
        let tol = |s: f64| 4.0 * s + 1e-5 * e0;
        assert!((e1 - e0).abs() <= tol(s1), "{e1} vs {e0}");
        // A 5× larger disk spreads over ±1.3°: the cosine varies, its mean over the disk stays
        // within ~1e-4 of the centre's.
        assert!((e5 - e0).abs() <= tol(s5) + 2e-4 * e0, "{e5} vs {e0}");
        // Sanity of the absolute value: ≈ 1.26 W/m²/nm at 520 nm for T = 3, θs = 11.5°
        // (measured clear-sky direct normal irradiance is ≈ 1.0–1.5 there).
        assert!(e0 / cos > 1.0 && e0 / cos < 1.5, "{}", e0 / cos);
    }

    #[test]
    fn tabulated_spectrum_follows_the_formula() {
        // Every 0.01 nm across the range, for clear and hazy skies and the sun from the zenith
        // to near the horizon, against the bound of linear interpolation at step h:
        // |error| ≤ h²/8 · max |f″| on the interval, and f″/f = ((ln f)′)² + (ln f)″ with
        // ln f = ln B − (τ_R + τ_a) m + const, τ_R = 0.008735 µm^−4.08 · … (module doc), so
        // (ln f)′ = (ln B)′ + (4.08 τ_R + 1.3 τ_a) m / λ and
        // (ln f)″ = (ln B)″ − (4.08 · 5.08 τ_R + 1.3 · 2.3 τ_a) m / λ²; for Planck's law
        // (ln B)′ = (x eˣ/(eˣ − 1) − 5)/λ, x = hc/(λkT), whose own derivative is below
        // 2 (ln B)′/λ + 10/λ² in size. The bound is taken at the interval's bluer end (the
        // transmittance's terms, which dominate, fall with λ; over 0.5 nm the others barely
        // change) with 10 % for f32 rounding. Where the sun is low and the blue end's value
        // tiny, the relative bound is large, as it should be.
        let h = TABLE_STEP as f64;
        for t in [2.0, 3.0, 6.0, 10.0] {
            for elevation in [90.0f32, 60.0, 30.0, 10.0, 5.0, 2.0, 0.5] {
                let s = SunSpectrum::new(t, (90.0 - elevation).to_radians(), 1.0);
                let (m, beta) = (s.air_mass as f64, s.beta as f64);
                let bound = |l: f64| {
                    let um = l * 1e-3;
                    let tau_r = 0.008735 * um.powf(-4.08) * m;
                    let tau_a = beta * um.powf(-1.3) * m;
                    let x = 1.438_777e7 / (l * SUN_TEMPERATURE as f64);
                    let dlb = (x * x.exp() / (x.exp() - 1.0) - 5.0) / l;
                    let d1 = dlb + (4.08 * tau_r + 1.3 * tau_a) / l;
                    let d2 = 2.0 * dlb.abs() / l
                        + 10.0 / (l * l)
                        + (4.08 * 5.08 * tau_r + 1.3 * 2.3 * tau_a) / (l * l);
                    1.1 * h * h / 8.0 * (d1 * d1 + d2)
                };
                let n = ((LAMBDA_MAX - LAMBDA_MIN) * 100.0) as usize;
                for k in 0..=n {
                    let l = LAMBDA_MIN + k as f32 * 0.01;
                    let (want, got) = (s.eval(l) as f64, s.lookup(l) as f64);
                    let lo = LAMBDA_MIN as f64 + ((l - LAMBDA_MIN) / TABLE_STEP).floor() as f64 * h;
                    let tol = (bound(lo) + 1e-6) * want;
                    assert!(
                        (got - want).abs() <= tol,
                        "T {t}, elevation {elevation}°, {l} nm: {got} vs {want} (bound {})",
                        bound(lo)
                    );
                }
                if elevation >= 10.0 && t <= 3.0 {
                    // The figure the module doc quotes (the bound without its rounding margin).
                    let b = bound(LAMBDA_MIN as f64) / 1.1;
                    assert!(b < 1e-4, "{b}");
                }
            }
        }
    }

    #[test]
    fn transmittance_follows_the_papers_formula() {
        // T = 3, θs = 60° (evaluated independently in f64): m = 1 / (0.5 + 0.15 · 33.885^−1.253)
        // = 1.992764; β = 0.09238; at 500 nm: Rayleigh 0.008735 · 0.5^−4.08 = 0.147729,
        // aerosol 0.09238 · 0.5^−1.3 = 0.227466; τ = exp(−0.375195 · 1.992764) = 0.473466.
        let s = SunSpectrum::new(3.0, 60f32.to_radians(), 1.0);
        let t = s.transmittance(500.0);
        assert!((t - 0.473466).abs() < 1e-4, "{t}");
        // Redder at low sun, black below the horizon.
        let low = SunSpectrum::new(3.0, 85f32.to_radians(), 1.0);
        assert!(low.transmittance(450.0) / low.transmittance(650.0) < t / s.transmittance(650.0));
        assert_eq!(SunSpectrum::new(3.0, 1.7, 1.0).eval(550.0), 0.0);
    }
}
