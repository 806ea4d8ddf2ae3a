//! `roughconductor`: a rough metal, the Cook–Torrance microfacet BRDF (Cook & Torrance 1982)
//! in the form of Walter et al. 2007, f = F(wo·wm) D(wm) G(wo, wi) / (4 cos θo cos θi), with
//! the exact conductor Fresnel term, GGX or Beckmann normals (anisotropic), height-correlated
//! Smith G and visible-normal sampling. The model is [`super::rough::Rough`] over
//! [`super::fresnel::ConductorFresnel`].
//!
//! ## Parameters
//!
//! PARAMS
//!
//! One-sided. Known limits: single scattering only, so energy is lost at high roughness;
//! 0.6's `phong` and `as` distributions are not supported.

use super::params::{conductor_ior, surface, METAL, REFLECTION_FACTOR, ROUGHNESS};
use super::{Interface, Material};
use crate::plugin::{Args, Info, Plugin, SceneError, Tag};

/// The `roughconductor` plugin.
pub(crate) const PLUGIN: Plugin<Material> = Plugin {
    info: Info {
        name: "roughconductor",
        aliases: &[],
        tag: Tag::Bsdf,
        summary: "rough metal: microfacet reflection with measured complex indices",
        params: &[ROUGHNESS, METAL, REFLECTION_FACTOR],
        file: file!(),
    },
    load,
};

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let ior = conductor_ior(a)?;
    surface(a, Interface::Conductor(ior), true)
}
