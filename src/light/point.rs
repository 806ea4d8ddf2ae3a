//! Isotropic point light (Mitsuba `point`): radiant intensity I(λ) in every direction, so the
//! irradiance at distance d on a surface facing it is I/d² (inverse-square law).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `intensity` | spectrum | 1.0 | W·sr⁻¹·nm⁻¹ | radiant intensity (RGB and numbers: times D65) |
//! | `position` | point | `to_world`'s translation | world units | where the light is |
//! | `to_world` | transform | — | — | places the light at its translation when `position` is absent |
//!
//! Known limits: a delta light — only reachable by next-event estimation, never by BSDF sampling;
//! no spot cone or goniometric profile.

use super::{Light, LightLiSample, LightSampleContext};
use crate::math::Vec3;
use crate::plugin::{declare, Args, DefaultValue, Param, SceneError, Ty};
use crate::spectrum::{SampledWavelengths, Spectrum};

declare!(PLUGIN: Vec<Light>, Option<u32> = Emitter "point" []
    "isotropic point light"
    [&[
        Param::emission("intensity")
            .unit("W·sr⁻¹·nm⁻¹")
            .doc("radiant intensity (RGB and numbers: times D65)"),
        Param::new("position", Ty::Point, DefaultValue::Derived("`to_world`'s translation"))
            .unit("world units")
            .doc("where the light is"),
        Param::new("to_world", Ty::Transform, DefaultValue::None)
            .doc("places the light at its translation when `position` is absent"),
    ]] load);

fn load(a: &mut Args, _: Option<u32>) -> Result<Vec<Light>, SceneError> {
    let intensity = a.spectrum("intensity")?;
    let pos = match a.point_opt("position")? {
        Some(p) => p,
        None => a.transform("to_world")?.point(Vec3::ZERO),
    };
    Ok(vec![Light::Point(PointLight::new(pos, intensity))])
}

/// A point light.
#[derive(Clone, Debug)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Spectrum,
}

impl PointLight {
    /// A point light at `position` with radiant intensity `intensity`.
    pub fn new(position: Vec3, intensity: Spectrum) -> PointLight {
        PointLight {
            position,
            intensity,
        }
    }

    pub(crate) fn sample_li(
        &self,
        ctx: &LightSampleContext,
        wl: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        let d = self.position - ctx.p;
        let dist2 = d.length_squared();
        if !(dist2 > 0.0 && dist2.is_finite()) {
            return None;
        }
        let wi = d / dist2.sqrt();
        Some(LightLiSample {
            l: self.intensity.sample(wl) / dist2,
            wi,
            pdf: 1.0,
            p_light: self.position,
            is_delta: true,
        })
    }

    pub(crate) fn power(&self) -> f32 {
        4.0 * crate::math::PI * super::spectrum_mean(&self.intensity)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::wl;
    use super::super::{Light, LightSampleContext};
    use super::*;
    use crate::math::Vec2;

    #[test]
    fn falls_off_with_inverse_square_distance() {
        let light = Light::Point(PointLight::new(
            Vec3::new(1.0, 2.0, 3.0),
            Spectrum::Constant(5.0),
        ));
        assert!(light.is_delta() && !light.is_infinite());
        for d in [0.5f32, 1.0, 4.0] {
            let ctx = LightSampleContext {
                p: Vec3::new(1.0, 2.0, 3.0 - d),
                n: Vec3::Z,
            };
            let s = light.sample_li(&ctx, Vec2::ZERO, &wl(), &[]).unwrap();
            assert!((s.l[0] - 5.0 / (d * d)).abs() < 1e-5 * s.l[0]);
            assert!((s.wi - Vec3::Z).length() < 1e-6);
            assert!(s.is_delta && s.pdf == 1.0);
            assert_eq!(s.p_light, Vec3::new(1.0, 2.0, 3.0));
            assert_eq!(light.pdf_li(&ctx, Vec3::Z, &[], None), 0.0);
        }
        let at = LightSampleContext {
            p: Vec3::new(1.0, 2.0, 3.0),
            n: Vec3::ZERO,
        };
        assert!(light.sample_li(&at, Vec2::ZERO, &wl(), &[]).is_none());
        assert!((light.power(&[]) - 20.0 * crate::math::PI).abs() < 1e-4);
    }
}
