//! `thinfilm`: a smooth dielectric interface carrying a thin film — a soap bubble, oil on
//! water, the keratin film of a snake scale — reflecting with the film's reflectance
//! R_film(λ, θ) and refracting with 1 − R_film, per hero wavelength. The film is exact: the
//! Airy sum of complex Fresnel amplitudes for s and p (Born & Wolf, *Principles of Optics*,
//! §7.6.1), see [`crate::optics::thinfilm`] and [`super::filmfresnel`]; it is infinitely thin
//! geometrically, so it changes colours, not directions (refraction obeys Snell's law between
//! `ext_ior` and `int_ior`). The model is [`super::smooth::Smooth`] over
//! [`super::filmfresnel::FilmFresnel`].
//!
//! `film_ior = "keratin"` is the Cauchy fit n(λ) = 1.532 + 5890/λ² (Leertouwer, Wilts &
//! Stavenga 2011, Opt. Express 19:24061), evaluated per wavelength. Defaults follow OpenPBR
//! (film index 1.4, 0.5 µm).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `film_ior`, `medium_ior` | float or IOR name | 1.4 | — | index of the film; `keratin` = 1.532 + 5890/λ² (λ in nm) |
//! | `film_thickness`, `thickness` | float or texture | 500.0 | nm | thickness of the film; between 0 and 100000 |
//! | `mode` | string | `spectral` | — | `thesis`: the thesis's 650/510/475 nm point samples and phase term; one of 'spectral', 'thesis' |
//! | `int_ior` (0.6: `intIOR`) | float or IOR name | `bk7` | — | index of the interior |
//! | `ext_ior` (0.6: `extIOR`) | float or IOR name | `air` | — | index of the exterior |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//! | `specular_transmittance` | spectrum or texture | 1.0 | — | factor on the transmitted light (not physical) |
//!
//! The thesis's Mitsuba 0.6 plugin `dielectricThinFilm` loads with its own names and defaults
//! (see `ophis plugins dielectricThinFilm`): `intIOR` = diamond, `mediumIOR` = BK7,
//! `thickness` = 400 nm; either spelling of the film's parameters works in both plugins.
//!
//! Sampling: the four wavelengths share one path, so reflection is chosen with P = mean_λ R_λ
//! and wavelength λ is weighted R_λ/P (reflection) or (1 − R_λ)/(1 − P) (refraction); in
//! thesis mode P is the thesis's mean(r, g, b). Two-sided by nature: wo.z < 0 is inside, where
//! the film is computed with n0 = `int_ior`, n2 = `ext_ior`.
//!
//! Known limits: real, non-dispersive `int_ior`/`ext_ior` (the film index may disperse); no
//! absorption in the film; the thickness is not filtered over the pixel footprint.

use super::film::{load_film_surface, FILM, THESIS_DIELECTRIC_IORS, THESIS_FILM};
use super::params::{DIELECTRIC_IORS, FACTORS};
use super::Material;
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "thinfilm" []
    "smooth dielectric carrying a thin film (exact interference)"
    [FILM, DIELECTRIC_IORS, FACTORS] load);

declare!(THESIS_PLUGIN: Material = Bsdf "dielectricThinFilm" []
    "the thesis's smooth film plugin: `thinfilm` with its defaults"
    [THESIS_FILM, THESIS_DIELECTRIC_IORS, FACTORS] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    load_film_surface(a, false, false)
}
