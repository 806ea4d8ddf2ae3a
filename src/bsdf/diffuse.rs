//! Lambertian reflection (Lambert 1760): f = ρ/π on the upper hemisphere, cosine-weighted
//! sampling (Malley's method through the concentric disk).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `reflectance` | spectrum or texture | 0.5 | — | albedo |
//!
//! One-sided as in Mitsuba 3: black when either direction is below the surface (wrap in
//! `twosided` for both sides). Reflectances are clamped to [0, 1]. Known limits: none.

use super::{BsdfSample, BxdfFlags, Material};
use crate::math::{warp, Vec2, Vec3, INV_PI};
use crate::plugin::{declare, Args, Param, SceneError};
use crate::spectrum::SampledSpectrum;

declare!(PLUGIN: Material = Bsdf "diffuse" []
    "Lambertian reflection"
    [&[Param::reflectance("reflectance", 0.5)
        .doc("albedo")]] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    Ok(Material::diffuse(a.spectrum_texture("reflectance")?))
}

/// Lambertian BSDF with reflectance `r`.
#[derive(Clone, Debug)]
pub struct DiffuseBxdf {
    pub r: SampledSpectrum,
}

impl DiffuseBxdf {
    /// A Lambertian surface of reflectance `r`.
    pub fn new(r: SampledSpectrum) -> Self {
        DiffuseBxdf { r }
    }
    pub fn flags(&self) -> BxdfFlags {
        if self.r.is_black() {
            BxdfFlags::NONE
        } else {
            BxdfFlags::DIFFUSE_REFLECTION
        }
    }
    pub fn f(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.r * INV_PI
    }
    pub fn sample_f(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = warp::square_to_cosine_hemisphere(u);
        let pdf = warp::square_to_cosine_hemisphere_pdf(wi);
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample::new(
            self.r * INV_PI,
            wi,
            pdf,
            BxdfFlags::DIFFUSE_REFLECTION,
        ))
    }
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        warp::square_to_cosine_hemisphere_pdf(wi)
    }
}
