//! `roughdielectric`: a rough boundary between two dielectrics — frosted glass, etched
//! surfaces — with microfacet reflection and refraction (Walter et al. 2007, "Microfacet
//! Models for Refraction through Rough Surfaces", EGSR; GGX or Beckmann normals,
//! height-correlated Smith G, visible-normal sampling). The model is [`super::rough::Rough`]
//! over [`super::fresnel::DielectricFresnel`] with η = `int_ior` / `ext_ior`.
//!
//! ## Parameters
//!
//! PARAMS
//!
//! Two-sided by nature (wo.z < 0 is inside). Known limits: single scattering between
//! microfacets (energy loss at high roughness); real index only; 0.6's `phong` and `as`
//! distributions are not supported.

use super::params::{relative_ior, surface, DIELECTRIC_IORS, FACTORS, ROUGHNESS};
use super::{Interface, Material};
use crate::plugin::{Args, Info, Plugin, SceneError, Tag};

/// The `roughdielectric` plugin.
pub(crate) const PLUGIN: Plugin<Material> = Plugin {
    info: Info {
        name: "roughdielectric",
        aliases: &[],
        tag: Tag::Bsdf,
        summary: "rough glass: microfacet reflection and refraction",
        params: &[ROUGHNESS, DIELECTRIC_IORS, FACTORS],
        file: file!(),
    },
    load,
};

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let eta = relative_ior(a)?;
    surface(a, Interface::Dielectric { eta }, true)
}
