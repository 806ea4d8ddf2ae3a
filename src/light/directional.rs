//! Directional light (Mitsuba `directional`): a light at infinity whose parallel rays deliver
//! irradiance E(λ) to a surface perpendicular to them.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `irradiance` | spectrum | 1.0 | W·m⁻²·nm⁻¹ | irradiance on a surface facing the light (RGB and numbers: times D65) |
//! | `direction` | vector | `to_world` applied to +z | — | the direction the light travels |
//! | `to_world` | transform | — | — | orients the light when `direction` is absent |
//!
//! Known limits: a delta light (next-event estimation only); the visibility point is placed
//! beyond the scene's bounding sphere, so [`super::Light::preprocess`] must be called first.

use super::infinite::InfiniteLight;
use super::Light;
use crate::math::{Vec2, Vec3, PI};
use crate::plugin::{declare, Args, DefaultValue, Param, SceneError, Ty};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

declare!(PLUGIN: Vec<Light>, Option<u32> = Emitter "directional" []
    "parallel light from infinity"
    [&[
        Param::emission("irradiance")
            .unit("W·m⁻²·nm⁻¹")
            .doc("irradiance on a surface facing the light (RGB and numbers: times D65)"),
        Param::new("direction", Ty::Vector, DefaultValue::Derived("`to_world` applied to +z"))
            .doc("the direction the light travels"),
        Param::new("to_world", Ty::Transform, DefaultValue::None)
            .doc("orients the light when `direction` is absent"),
    ]] load);

fn load(a: &mut Args, _: Option<u32>) -> Result<Vec<Light>, SceneError> {
    let irradiance = a.spectrum("irradiance")?;
    let dir = match a.vector_opt("direction")? {
        Some(d) => d,
        None => a.transform("to_world")?.vector(Vec3::Z),
    };
    let l = DirectionalLight::new(dir, irradiance)
        .ok_or_else(|| a.error("direction", "must be a non-zero vector"))?;
    Ok(vec![Light::Directional(l.into())])
}

/// A directional light.
#[derive(Clone, Debug)]
pub struct DirectionalLight {
    /// Unit direction in which the light travels.
    pub direction: Vec3,
    pub irradiance: Spectrum,
}

impl DirectionalLight {
    /// A light travelling along `direction` (normalised here; `None` if zero or not finite).
    pub fn new(direction: Vec3, irradiance: Spectrum) -> Option<DirectionalLight> {
        let d = direction.normalize_or_zero();
        (d != Vec3::ZERO).then_some(DirectionalLight {
            direction: d,
            irradiance,
        })
    }
}

impl InfiniteLight for DirectionalLight {
    fn sample_wi(&self, _: Vec3, _: Vec2) -> Option<Vec3> {
        Some(-self.direction)
    }

    fn pdf_li(&self, _: Vec3, _: Vec3) -> f32 {
        0.0
    }

    fn le(&self, _: Vec3, _: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::ZERO
    }

    fn is_delta(&self) -> bool {
        true
    }

    fn li(&self, _: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        self.irradiance.sample(wl)
    }

    /// Power through the scene's bounding disk.
    fn power(&self, r: f32) -> f32 {
        PI * r * r * super::spectrum_mean(&self.irradiance)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::wl;
    use super::super::{Light, LightSampleContext};
    use super::*;
    use crate::math::Bounds3;

    #[test]
    fn is_a_delta_light_at_infinity() {
        let dl = DirectionalLight::new(Vec3::new(0.0, 0.0, -2.0), Spectrum::Constant(3.0)).unwrap();
        let mut light = Light::Directional(dl.into());
        assert!(light.is_delta() && light.is_infinite());
        let mut b = Bounds3::from_point(Vec3::splat(-1.0));
        b.grow(Vec3::splat(1.0));
        light.preprocess(&b);
        let ctx = LightSampleContext {
            p: Vec3::new(0.5, 0.0, 0.0),
            n: Vec3::Z,
        };
        let s = light
            .sample_li(&ctx, Vec2::new(0.3, 0.7), &wl(), &[])
            .unwrap();
        assert!(s.is_delta && s.pdf == 1.0);
        assert!((s.wi - Vec3::Z).length() < 1e-6);
        assert_eq!(s.l[2], 3.0);
        // The visibility point lies outside the bounding sphere (radius √3).
        assert!(
            s.p_light.length() > 3f32.sqrt()
                && (s.p_light - ctx.p).normalize().dot(Vec3::Z) > 0.999
        );
        assert_eq!(light.pdf_li(&ctx, Vec3::Z, &[], None), 0.0);
        assert!(light.le(Vec3::Z, &wl()).is_black());
        assert!(DirectionalLight::new(Vec3::ZERO, Spectrum::Constant(1.0)).is_none());
    }
}
