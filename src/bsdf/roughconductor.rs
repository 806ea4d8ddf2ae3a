//! `roughconductor`: a rough metal, the Cook–Torrance microfacet BRDF (Cook & Torrance 1982)
//! in the form of Walter et al. 2007, f = F(wo·wm) D(wm) G(wo, wi) / (4 cos θo cos θi), with
//! the exact conductor Fresnel term, GGX or Beckmann normals (anisotropic), height-correlated
//! Smith G and visible-normal sampling. The model is [`super::rough::Rough`] over
//! [`super::fresnel::ConductorFresnel`].
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
//! | `material` | string | `none` | — | a named metal (`Au`, `Ag`, `Cu`, `Al`, … 71 of Mitsuba's) or `none` (a perfect mirror) |
//! | `eta` | spectrum | 0.0 | — | real part of the metal's index (with `k`, instead of `material`) |
//! | `k` | spectrum | 1.0 | — | imaginary part (extinction) of the metal's index |
//! | `ext_ior`, `ext_eta` (0.6: `extEta`) | float or IOR name | `air` | — | index of the medium outside the metal |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//!
//! One-sided. Known limits: single scattering only, so energy is lost at high roughness;
//! 0.6's `phong` and `as` distributions are not supported.

use super::params::{conductor_ior, surface, METAL, REFLECTION_FACTOR, ROUGHNESS};
use super::{Interface, Material};
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "roughconductor" []
    "rough metal: microfacet reflection with measured complex indices"
    [ROUGHNESS, METAL, REFLECTION_FACTOR] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let ior = conductor_ior(a)?;
    surface(a, Interface::Conductor(ior), true)
}
