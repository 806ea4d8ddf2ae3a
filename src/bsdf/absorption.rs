//! Absorbing layer over a Lambertian base, the thesis's "capa de absorción" (Bielsa 2022,
//! §3.5, algorithm 2; Padrón-Griffe et al., CEIG 2023): Beer–Lambert attenuation along the path
//! in and the path out of a layer of thickness d and absorption coefficient σa,
//!
//! f = ρ/π · exp(−σa d (1/cos θi + 1/cos θo)),
//!
//! sampled by cosine weighting (exact pdf). The thesis multiplies σa by the thickness and by the
//! length of the path through the layer (algorithm 2, eq. 3.2); the length of a straight path
//! through a slab of unit thickness is 1/cos θ on each way.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `reflectance` | spectrum or texture | 0.5 | — | albedo of the base |
//! | `sigma_a` (0.6: `sigmaA`) | spectrum or texture | 0.0 | 1/(unit of `thickness`) | absorption coefficient |
//! | `thickness` | float | 1.0 | — | thickness of the layer; non-negative |
//!
//! The thesis's Mitsuba 0.6 plugin is `Absorption` (an alias here). It applied the same factor
//! as a straight pass-through interface inside its `multilayered` stack; here it is the opaque
//! base the thesis describes, which `multilayered` can use as its bottom surface.
//!
//! Physical limits: the layer has the index of the outside (no refraction at its top, no
//! internal reflection) and does not scatter; the base is Lambertian. Under those assumptions
//! the formula is exact — it equals [`super::layered::closed_form`] with η = 1. One-sided;
//! energy ≤ ρ (absorption only removes light). For a layer under a coat of another index use
//! `multilayered`, whose closed form includes refraction and internal reflection.

use super::{BsdfSample, BxdfFlags, Material};
use crate::math::{warp, Vec2, Vec3, INV_PI};
use crate::plugin::{declare, Args, Check, Param, SceneError};
use crate::spectrum::SampledSpectrum;

/// The parameters.
const PARAMS: &[Param] = &[
    Param::reflectance("reflectance", 0.5).doc("albedo of the base"),
    Param::coefficient("sigma_a", 0.0)
        .v06("sigmaA")
        .unit("1/(unit of `thickness`)")
        .doc("absorption coefficient"),
    Param::float("thickness", 1.0)
        .check(Check::NonNegative)
        .doc("thickness of the layer"),
];

declare!(PLUGIN: Material = Bsdf "absorption" ["Absorption"]
    "the thesis's pigment layer: Beer–Lambert absorption over a Lambertian base"
    [PARAMS] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    Ok(Material::Absorption {
        reflectance: a.spectrum_texture("reflectance")?,
        sigma_a: a.spectrum_texture("sigma_a")?,
        thickness: a.float("thickness")?,
    })
}

/// Lambertian base of albedo `rho` under a layer of optical depth `tau` = σa·d.
#[derive(Clone, Debug)]
pub struct AbsorptionBxdf {
    pub rho: SampledSpectrum,
    pub tau: SampledSpectrum,
}

impl AbsorptionBxdf {
    /// Base albedo `rho`, absorption coefficient `sigma_a`, layer `thickness`.
    pub fn new(rho: SampledSpectrum, sigma_a: SampledSpectrum, thickness: f32) -> Self {
        AbsorptionBxdf {
            rho,
            tau: sigma_a * thickness,
        }
    }
    /// A Lambertian base's: the slab only dims it.
    pub(crate) fn flags(&self) -> BxdfFlags {
        super::diffuse::DiffuseBxdf::new(self.rho).flags()
    }
    pub fn f(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let path = 1.0 / wo.z + 1.0 / wi.z;
        self.rho * INV_PI * (-self.tau * path).exp()
    }
    pub(crate) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        warp::square_to_cosine_hemisphere_pdf(wi)
    }
    pub fn sample_f(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = warp::square_to_cosine_hemisphere(u);
        let pdf = warp::square_to_cosine_hemisphere_pdf(wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = self.f(wo, wi);
        Some(BsdfSample::new(f, wi, pdf, BxdfFlags::DIFFUSE_REFLECTION))
    }
}
