//! Light sources: point, directional, constant environment, image-based environment map,
//! daylight (sun and sky) and diffuse area lights, with Mitsuba 3's plugin names and parameters, and the light sampler.
//!
//! Every light answers the same questions for next-event estimation with multiple importance
//! sampling: `sample_li` draws a direction towards the light from a shading point, `pdf_li` gives
//! the (solid-angle) density with which it would have drawn a direction that BSDF sampling found,
//! and `le` / `l` give the radiance a ray sees when it escapes the scene or hits an emitter.

pub mod area;
pub mod choice;
pub mod constant;
pub mod directional;
pub mod distribution;
pub mod envmap;
pub(crate) mod infinite;
pub mod point;
pub mod sunsky;

pub use area::AreaLight;
pub use choice::LightSampler;
pub use constant::ConstantLight;
pub use directional::DirectionalLight;
pub use distribution::{Distribution1D, Distribution2D};
pub use envmap::{EnvMapError, EnvMapLight};
pub use infinite::AtInfinity;
pub use point::PointLight;
pub use sunsky::{SkyLight, SunLight};

use crate::math::{Bounds3, Vec2, Vec3};
use crate::shape::{Shape, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum, LAMBDA_MAX, LAMBDA_MIN};
use infinite::InfiniteLight;

/// The shading point a light is sampled from.
#[derive(Clone, Copy, Debug)]
pub struct LightSampleContext {
    /// Position (world space).
    pub p: Vec3,
    /// Geometric normal at the shading point, or zero (e.g. in a medium, or when the caller wants
    /// directions over the whole sphere).
    pub n: Vec3,
}

/// A direction sampled towards a light.
#[derive(Clone, Copy, Debug)]
pub struct LightLiSample {
    /// Radiance arriving along `-wi` (not divided by the pdf).
    pub l: SampledSpectrum,
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Density in solid angle; 1 for delta lights.
    pub pdf: f32,
    /// The point to test visibility to (far outside the scene for infinite lights).
    pub p_light: Vec3,
    /// Whether the light is a delta distribution (no MIS with BSDF sampling).
    pub is_delta: bool,
}

/// A light source.
// Scenes hold a handful of lights, so the environment map's size in the enum costs nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum Light {
    Point(PointLight),
    Directional(AtInfinity<DirectionalLight>),
    Constant(AtInfinity<ConstantLight>),
    EnvMap(AtInfinity<EnvMapLight>),
    Area(AreaLight),
    /// Preetham's clear sky (`sunsky`, `sky`).
    Sky(AtInfinity<SkyLight>),
    /// The solar disk (`sunsky`, `sun`).
    Sun(AtInfinity<SunLight>),
}

impl Light {
    /// Samples a direction towards the light from `ctx`; `None` when no light arrives.
    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        wl: &SampledWavelengths,
        shapes: &[Shape],
    ) -> Option<LightLiSample> {
        match self {
            Light::Point(l) => l.sample_li(ctx, wl),
            Light::Directional(l) => l.sample_li(ctx, u, wl),
            Light::Constant(l) => l.sample_li(ctx, u, wl),
            Light::EnvMap(l) => l.sample_li(ctx, u, wl),
            Light::Area(l) => l.sample_li(ctx, u, wl, l.shape_in(shapes)?),
            Light::Sky(l) => l.sample_li(ctx, u, wl),
            Light::Sun(l) => l.sample_li(ctx, u, wl),
        }
    }

    /// Solid-angle density with which [`Light::sample_li`] would choose `wi` from `ctx`; for area
    /// lights `hit` is the point where the ray along `wi` met the light (0 without one). Delta
    /// lights return 0: no other technique can find them.
    pub fn pdf_li(
        &self,
        ctx: &LightSampleContext,
        wi: Vec3,
        shapes: &[Shape],
        hit: Option<&SurfaceInteraction>,
    ) -> f32 {
        match self {
            Light::Point(_) => 0.0,
            Light::Directional(l) => l.pdf_li(ctx.n, wi),
            Light::Constant(l) => l.pdf_li(ctx.n, wi),
            Light::EnvMap(l) => l.pdf_li(ctx.n, wi),
            Light::Area(l) => match (hit, l.shape_in(shapes)) {
                (Some(hit), Some(shape)) => l.pdf_li(ctx, hit, shape),
                _ => 0.0,
            },
            Light::Sky(l) => l.pdf_li(ctx.n, wi),
            Light::Sun(l) => l.pdf_li(ctx.n, wi),
        }
    }

    /// Radiance seen by a ray that escapes the scene in direction `dir` (infinite lights only).
    pub fn le(&self, dir: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Light::Directional(l) => l.le(dir, wl),
            Light::Constant(l) => l.le(dir, wl),
            Light::EnvMap(l) => l.le(dir, wl),
            Light::Sky(l) => l.le(dir, wl),
            Light::Sun(l) => l.le(dir, wl),
            Light::Point(_) | Light::Area(_) => SampledSpectrum::ZERO,
        }
    }

    /// Radiance leaving an area light at `si` in direction `w` (towards the viewer).
    pub fn l(&self, si: &SurfaceInteraction, w: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Light::Area(l) => l.l(si, w, wl),
            _ => SampledSpectrum::ZERO,
        }
    }

    /// Whether the light is a delta distribution in position or direction.
    pub fn is_delta(&self) -> bool {
        match self {
            Light::Point(_) | Light::Directional(_) => true,
            Light::Sun(l) => l.is_delta(),
            _ => false,
        }
    }

    /// Whether the light is at infinity (seen by escaping rays).
    pub fn is_infinite(&self) -> bool {
        matches!(
            self,
            Light::Directional(_)
                | Light::Constant(_)
                | Light::EnvMap(_)
                | Light::Sky(_)
                | Light::Sun(_)
        )
    }

    /// Gives lights at infinity the scene's bounding sphere.
    pub fn preprocess(&mut self, scene_bounds: &Bounds3) {
        let (c, r) = scene_bounds.bounding_sphere();
        let r = r.max(1e-3);
        match self {
            Light::Directional(l) => l.place(c, r),
            Light::Constant(l) => l.place(c, r),
            Light::EnvMap(l) => l.place(c, r),
            Light::Sky(l) => l.place(c, r),
            Light::Sun(l) => l.place(c, r),
            Light::Point(_) | Light::Area(_) => {}
        }
    }

    /// Approximate emitted power (W, with spectra reduced to their mean over the visible range),
    /// which half of the light choice follows ([`LightSampler`]). Area lights need the shapes.
    pub fn power(&self, shapes: &[Shape]) -> f32 {
        match self {
            Light::Point(l) => l.power(),
            Light::Directional(l) => l.power(),
            Light::Constant(l) => l.power(),
            Light::EnvMap(l) => l.power(),
            Light::Area(l) => l.shape_in(shapes).map_or(0.0, |s| l.power(s)),
            Light::Sky(l) => l.power(),
            Light::Sun(l) => l.power(),
        }
    }
}

/// The mean of a spectrum over the rendered range (10 nm steps): a scalar stand-in for power.
pub fn spectrum_mean(s: &Spectrum) -> f32 {
    if let Spectrum::Constant(v) = s {
        return *v;
    }
    let n = ((LAMBDA_MAX - LAMBDA_MIN) / 10.0) as usize;
    let sum: f32 = (0..=n)
        .map(|i| s.eval(LAMBDA_MIN + 10.0 * i as f32).max(0.0))
        .sum();
    sum / (n + 1) as f32
}

/// A point beyond the scene's bounding sphere (centre `c`, radius `r`) along `wi` from `p`, for
/// visibility tests towards lights at infinity.
#[inline]
pub(crate) fn point_at_infinity(p: Vec3, wi: Vec3, c: Vec3, r: f32) -> Vec3 {
    p + wi * (2.0 * (r + (p - c).length()))
}

#[cfg(test)]
pub(crate) mod test_util {
    use crate::spectrum::SampledWavelengths;

    /// Four fixed wavelengths for tests.
    pub fn wl() -> SampledWavelengths {
        SampledWavelengths::fixed([450.0, 520.0, 600.0, 680.0])
    }

    /// Mean and standard error of `n` values.
    pub fn mean_and_sigma(values: impl Iterator<Item = f64>) -> (f64, f64) {
        let (mut n, mut s, mut s2) = (0usize, 0.0, 0.0);
        for v in values {
            n += 1;
            s += v;
            s2 += v * v;
        }
        let mean = s / n as f64;
        let var = (s2 / n as f64 - mean * mean).max(0.0);
        (mean, (var / n as f64).sqrt())
    }
}
