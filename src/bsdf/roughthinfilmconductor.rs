//! `roughthinfilmconductor`: a thin film over a rough metal: the Cook–Torrance microfacet BRDF
//! (Walter et al. 2007) with each microfacet's Fresnel term replaced by the exact film-over-
//! metal reflectance at wo·wm, as Belcour & Barla 2017 (TOG 36(4):65) do. The model is
//! [`super::rough::Rough`] over [`super::filmfresnel::FilmFresnel`] with a metal base.
//!
//! ## Parameters
//!
//! PARAMS
//!
//! One-sided; only reflection. Known limits: single scattering between microfacets; no
//! absorption in the film.

use super::film::{load_film_surface, FILM, METAL_UNDER_FILM};
use super::params::{REFLECTION_FACTOR, ROUGHNESS};
use super::Material;
use crate::plugin::{Args, Info, Plugin, SceneError, Tag};

/// The `roughthinfilmconductor` plugin.
pub(crate) const PLUGIN: Plugin<Material> = Plugin {
    info: Info {
        name: "roughthinfilmconductor",
        aliases: &[],
        tag: Tag::Bsdf,
        summary: "a thin film over a rough metal",
        params: &[FILM, ROUGHNESS, METAL_UNDER_FILM, REFLECTION_FACTOR],
        file: file!(),
    },
    load,
};

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    load_film_surface(a, true, true)
}
