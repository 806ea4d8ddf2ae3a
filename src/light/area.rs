//! Diffuse area light (Mitsuba `area`, attached to a shape): constant radiance L(λ) leaving the
//! front side of the shape (the side its geometric normal points to), nothing from the back.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `radiance` | spectrum | 1.0 | W·m⁻²·sr⁻¹·nm⁻¹ | radiance leaving the front side (RGB and numbers: times D65) |
//!
//! Sampling delegates to [`Shape::sample_direct`] (solid-angle density as seen from the shading
//! point: cone sampling for spheres, uniform area otherwise) and [`Shape::pdf_direct`].
//!
//! Known limits: one-sided only (Mitsuba has no two-sided `area`); textured radiance is not
//! supported; the power estimate π A L assumes a flat-ish emitter.

use super::{Light, LightLiSample, LightSampleContext};
use crate::plugin::{declare, Args, Param, SceneError};

declare!(PLUGIN: Vec<Light>, Option<u32> = Emitter "area" []
    "diffuse emission from a shape's front side (nested in the shape)"
    [&[
        Param::emission("radiance")
            .unit("W·m⁻²·sr⁻¹·nm⁻¹")
            .doc("radiance leaving the front side (RGB and numbers: times D65)"),
    ]] load);

fn load(a: &mut Args, shape: Option<u32>) -> Result<Vec<Light>, SceneError> {
    let Some(shape) = shape else {
        return Err(SceneError::at(
            &a.node().loc,
            "an 'area' emitter must be nested inside a shape",
        ));
    };
    Ok(vec![Light::Area(AreaLight::new(
        shape,
        a.spectrum("radiance")?,
    ))])
}
use crate::math::{Vec2, Vec3, PI};
use crate::shape::{Shape, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

/// An emitter attached to one shape of the scene.
#[derive(Clone, Debug)]
pub struct AreaLight {
    /// Index of the emitting shape in the scene's shape list.
    pub shape: u32,
    pub radiance: Spectrum,
}

impl AreaLight {
    /// Emission `radiance` from the front of shape `shape_index`.
    pub fn new(shape_index: u32, radiance: Spectrum) -> AreaLight {
        AreaLight {
            shape: shape_index,
            radiance,
        }
    }

    /// The emitting shape among the scene's `shapes` (`None` if the index is out of range):
    /// the one the methods below are given.
    pub(crate) fn shape_in<'s>(&self, shapes: &'s [Shape]) -> Option<&'s Shape> {
        shapes.get(self.shape as usize)
    }

    /// Samples a point of the light's shape `shape` as seen from `ctx`.
    pub(crate) fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        wl: &SampledWavelengths,
        shape: &Shape,
    ) -> Option<LightLiSample> {
        let ss = shape.sample_direct(ctx.p, u)?;
        let d = ss.p - ctx.p;
        let dist2 = d.length_squared();
        if !(ss.pdf > 0.0 && ss.pdf.is_finite() && dist2 > 0.0) {
            return None;
        }
        let wi = d / dist2.sqrt();
        // One-sided: only the side the normal points to emits.
        if ss.n.dot(-wi) <= 0.0 {
            return None;
        }
        Some(LightLiSample {
            l: self.radiance.sample(wl),
            wi,
            pdf: ss.pdf,
            p_light: ss.p,
            is_delta: false,
        })
    }

    /// The density of [`Self::sample_li`] choosing `hit`, a point of some shape.
    pub(crate) fn pdf_li(
        &self,
        ctx: &LightSampleContext,
        hit: &SurfaceInteraction,
        shape: &Shape,
    ) -> f32 {
        if hit.shape != self.shape {
            return 0.0;
        }
        shape.pdf_direct(ctx.p, hit.p, hit.ng)
    }

    pub(crate) fn l(
        &self,
        si: &SurfaceInteraction,
        w: Vec3,
        wl: &SampledWavelengths,
    ) -> SampledSpectrum {
        if si.ng.dot(w) > 0.0 {
            self.radiance.sample(wl)
        } else {
            SampledSpectrum::ZERO
        }
    }

    /// π A L: the power of a one-sided Lambertian emitter of area A.
    pub(crate) fn power(&self, shape: &Shape) -> f32 {
        PI * shape.area() * super::spectrum_mean(&self.radiance)
    }
}

#[cfg(test)]
mod tests;
