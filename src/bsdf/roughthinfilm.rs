//! `roughthinfilm`: a rough dielectric interface carrying a thin film: the microfacet model of
//! Walter et al. 2007 with the Fresnel term of each microfacet replaced by the exact film
//! reflectance R_film(λ, wo·wm), as Belcour & Barla 2017, "A Practical Extension to Microfacet
//! Theory for the Modeling of Varying Iridescence" (TOG 36(4):65) do: D, G and sampling
//! unchanged, transmission with 1 − R_film. The model is [`super::rough::Rough`] over
//! [`super::filmfresnel::FilmFresnel`].
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
//! | `int_ior` (0.6: `intIOR`) | float or IOR name | `bk7` | — | index of the interior |
//! | `ext_ior` (0.6: `extIOR`) | float or IOR name | `air` | — | index of the exterior |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//! | `specular_transmittance` | spectrum or texture | 1.0 | — | factor on the transmitted light (not physical) |
//!
//! The thesis's `roughdielectricThinFilm` loads with its own names and defaults (those of
//! `dielectricThinFilm`, plus the roughness).
//!
//! `f` and `sample_f` return the same *coloured* value (the thesis's rough plugin returned a
//! grey value from `eval`, so light-sampled paths lost the iridescence; that defect is not
//! reproduced, not even in thesis mode). Reflection is chosen with P = mean_λ R_λ(wo·wm)
//! (thesis mode: mean(r, g, b)), and `pdf` includes that choice. Reciprocal: R_film from either
//! side of a lossless film gives the same 1 − R at conjugate angles, so f(a, b) = f(b, a) up to
//! η².
//!
//! Known limits: single scattering between microfacets; real `int_ior`/`ext_ior`.

use super::film::{load_film_surface, FILM, THESIS_DIELECTRIC_IORS, THESIS_FILM};
use super::params::{DIELECTRIC_IORS, FACTORS, ROUGHNESS};
use super::Material;
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "roughthinfilm" []
    "rough dielectric carrying a thin film on every microfacet"
    [FILM, ROUGHNESS, DIELECTRIC_IORS, FACTORS] load);

declare!(THESIS_PLUGIN: Material = Bsdf "roughdielectricThinFilm" []
    "the thesis's rough film plugin: `roughthinfilm` with its defaults"
    [THESIS_FILM, ROUGHNESS, THESIS_DIELECTRIC_IORS, FACTORS] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    load_film_surface(a, false, true)
}
