//! `roughdielectric`: a rough boundary between two dielectrics — frosted glass, etched
//! surfaces — with microfacet reflection and refraction (Walter et al. 2007, "Microfacet
//! Models for Refraction through Rough Surfaces", EGSR; GGX or Beckmann normals,
//! height-correlated Smith G, visible-normal sampling). The model is [`super::rough::Rough`]
//! over [`super::fresnel::DielectricFresnel`] with η = `int_ior` / `ext_ior`.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `distribution` | string | `beckmann` | — | microfacet normal distribution; one of 'beckmann', 'ggx' |
//! | `alpha` | float or texture | 0.1 | RMS slope | roughness α; between 0 and 10 |
//! | `alpha_u` (0.6: `alphaU`) | float or texture | `alpha` | RMS slope | anisotropic α along ∂p/∂u; between 0 and 10 |
//! | `alpha_v` (0.6: `alphaV`) | float or texture | `alpha` | RMS slope | anisotropic α along ∂p/∂v; between 0 and 10 |
//! | `sample_visible` | boolean | true | — | accepted; visible normals are always sampled |
//! | `int_ior` (0.6: `intIOR`) | float or IOR name | `bk7` | — | index of the interior |
//! | `ext_ior` (0.6: `extIOR`) | float or IOR name | `air` | — | index of the exterior |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//! | `specular_transmittance` | spectrum or texture | 1.0 | — | factor on the transmitted light (not physical) |
//!
//! Two-sided by nature (wo.z < 0 is inside). Known limits: single scattering between
//! microfacets (energy loss at high roughness); real index only; 0.6's `phong` and `as`
//! distributions are not supported.

use super::params::{relative_ior, surface, DIELECTRIC_IORS, FACTORS, ROUGHNESS};
use super::{Interface, Material};
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "roughdielectric" []
    "rough glass: microfacet reflection and refraction"
    [ROUGHNESS, DIELECTRIC_IORS, FACTORS] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let eta = relative_ior(a)?;
    surface(a, Interface::Dielectric { eta }, true)
}
