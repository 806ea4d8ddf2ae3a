//! What the lights at infinity share (`constant`, `directional`, `envmap`, `sky`, `sun`): one
//! sampling routine over each light's own distribution of directions, the scene's bounding
//! sphere they are placed around, and the latitude–longitude density of the map lights
//! (`envmap`, `sky`).
//!
//! A light at infinity only says which directions it sends light from and how much; where the
//! shadow ray ends and how much power reaches the scene depend on the scene's size, which
//! [`AtInfinity`] adds once for all of them.

use super::envmap::direction_to_uv;
use super::{point_at_infinity, LightLiSample, LightSampleContext};
use crate::math::{Vec2, Vec3, PI};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use std::ops::Deref;

/// A light at infinity: directions and the radiance arriving along them, the same at every
/// point of the scene (only the shading normal may shape the sampling).
pub trait InfiniteLight {
    /// A world direction towards the light drawn with `u`, for a shading point with normal `n`
    /// (zero for none), or a delta light's one direction; `None` when the light is off.
    fn sample_wi(&self, n: Vec3, u: Vec2) -> Option<Vec3>;

    /// Solid-angle density with which [`Self::sample_wi`] chooses the world direction `wi`
    /// (0 for delta lights: no other technique can find them).
    fn pdf_li(&self, n: Vec3, wi: Vec3) -> f32;

    /// Radiance seen by a ray escaping in the world direction `dir` (0 for delta lights).
    fn le(&self, dir: Vec3, wl: &SampledWavelengths) -> SampledSpectrum;

    /// Whether the light is a delta distribution in direction (density 1 per sample).
    fn is_delta(&self) -> bool {
        false
    }

    /// What a sample along `wi` carries: the radiance seen there, or a delta light's irradiance.
    fn li(&self, wi: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.le(wi, wl)
    }

    /// Power reaching a scene bounded by a sphere of radius `r`.
    fn power(&self, r: f32) -> f32;
}

/// A light at infinity placed around the scene's bounding sphere: where its shadow rays end and
/// what its power is spread over (the unit sphere until [`super::Light::preprocess`] places it).
/// Dereferences to the light itself.
#[derive(Clone, Debug)]
pub struct AtInfinity<L> {
    light: L,
    center: Vec3,
    radius: f32,
}

impl<L> From<L> for AtInfinity<L> {
    fn from(light: L) -> Self {
        AtInfinity {
            light,
            center: Vec3::ZERO,
            radius: 1.0,
        }
    }
}

impl<L> Deref for AtInfinity<L> {
    type Target = L;

    fn deref(&self) -> &L {
        &self.light
    }
}

impl<L: InfiniteLight> AtInfinity<L> {
    /// Places the light around the sphere of centre `center` and radius `radius`.
    pub(crate) fn place(&mut self, center: Vec3, radius: f32) {
        (self.center, self.radius) = (center, radius);
    }

    /// A direction towards the light from `ctx`. Density and radiance are re-derived from the
    /// direction (by `pdf_li` and `le`) so that they agree exactly with what those report for it.
    pub(crate) fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        wl: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        let wi = self.light.sample_wi(ctx.n, u)?;
        let is_delta = self.light.is_delta();
        let pdf = if is_delta {
            1.0
        } else {
            self.light.pdf_li(ctx.n, wi)
        };
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(LightLiSample {
            l: self.light.li(wi, wl),
            wi,
            pdf,
            p_light: point_at_infinity(ctx.p, wi, self.center, self.radius),
            is_delta,
        })
    }

    /// Power reaching the scene it is placed around.
    pub(crate) fn power(&self) -> f32 {
        self.light.power(self.radius)
    }
}

/// Solid-angle density of a latitude–longitude map light towards the local direction `d`,
/// given the density `map_pdf` of the map point (u, v) there (0 at the poles).
#[inline]
pub(crate) fn latlong_pdf(d: Vec3, map_pdf: impl FnOnce(Vec2) -> f32) -> f32 {
    let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
    if sin_theta.is_nan() || sin_theta <= 0.0 {
        return 0.0;
    }
    map_pdf(direction_to_uv(d)) / (2.0 * PI * PI * sin_theta)
}
