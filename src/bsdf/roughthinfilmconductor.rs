//! `roughthinfilmconductor`: a thin film over a rough metal: the Cook–Torrance microfacet BRDF
//! (Walter et al. 2007) with each microfacet's Fresnel term replaced by the exact film-over-
//! metal reflectance at wo·wm, as Belcour & Barla 2017 (TOG 36(4):65) do. The model is
//! [`super::rough::Rough`] over [`super::filmfresnel::FilmFresnel`] with a metal base.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `film_ior`, `medium_ior` | float or IOR name | 1.4 | — | index of the film; `keratin` = 1.532 + 5890/λ² (λ in nm) |
//! | `film_thickness`, `thickness` | float or texture | 500.0 | nm | thickness of the film; between 0 and 100000 |
//! | `mode` | string | `spectral` | — | `thesis`: the thesis's 650/510/475 nm point samples and phase term; one of 'spectral', 'thesis' |
//! | `distribution` | string | `beckmann` | — | microfacet normal distribution; one of 'beckmann', 'ggx' |
//! | `alpha` | float or texture | 0.1 | RMS slope | roughness α; between 0 and 10 |
//! | `alpha_u` (0.6: `alphaU`) | float or texture | `alpha` | RMS slope | anisotropic α along ∂p/∂u; between 0 and 10 |
//! | `alpha_v` (0.6: `alphaV`) | float or texture | `alpha` | RMS slope | anisotropic α along ∂p/∂v; between 0 and 10 |
//! | `sample_visible` | boolean | true | — | accepted; visible normals are always sampled |
//! | `material` | string | `Cu` | — | a named metal (`Au`, `Ag`, `Cu`, `Al`, … 71 of Mitsuba's); `none` is refused |
//! | `eta` | spectrum | 0.0 | — | real part of the metal's index (with `k`, instead of `material`) |
//! | `k` | spectrum | 1.0 | — | imaginary part (extinction) of the metal's index |
//! | `ext_ior` (0.6: `extIOR`) | float or IOR name | `air` | — | index of the exterior |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//!
//! One-sided; only reflection. Known limits: single scattering between microfacets; no
//! absorption in the film.

use super::film::{load_film_surface, FILM, METAL_UNDER_FILM};
use super::params::{REFLECTION_FACTOR, ROUGHNESS};
use super::Material;
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "roughthinfilmconductor" []
    "a thin film over a rough metal"
    [FILM, ROUGHNESS, METAL_UNDER_FILM, REFLECTION_FACTOR] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    load_film_surface(a, true, true)
}
