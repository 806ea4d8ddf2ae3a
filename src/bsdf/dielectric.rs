//! `dielectric`: a smooth boundary between two dielectrics — glass, water, a clear varnish —
//! reflecting and refracting by the exact unpolarised Fresnel equations (Born & Wolf,
//! *Principles of Optics*, §1.5). The model is [`super::smooth::Smooth`] over
//! [`super::fresnel::DielectricFresnel`] with η = `int_ior` / `ext_ior`.
//!
//! Sampling picks reflection with probability F and transmission with 1 − F, so the path weight
//! is exactly `specular_reflectance` or `specular_transmittance` (R + T = 1 for white factors).
//! Radiance crossing into a medium of relative index η is scaled by 1/η² (radiance mode only).
//! Two-sided by nature: wo.z < 0 means the ray is inside.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `int_ior` (0.6: `intIOR`) | float or IOR name | `bk7` | — | index of the interior |
//! | `ext_ior` (0.6: `extIOR`) | float or IOR name | `air` | — | index of the exterior |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//! | `specular_transmittance` | spectrum or texture | 1.0 | — | factor on the transmitted light (not physical) |
//!
//! Known limits: the index is a single real number (no dispersion, no absorption).

use super::params::{relative_ior, surface, DIELECTRIC_IORS, FACTORS};
use super::{Interface, Material};
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "dielectric" []
    "smooth glass or water: Fresnel reflection and refraction"
    [DIELECTRIC_IORS, FACTORS] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let eta = relative_ior(a)?;
    surface(a, Interface::Dielectric { eta }, false)
}
