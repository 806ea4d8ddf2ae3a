//! `thinfilmconductor`: a thin dielectric film over a polished metal — oxide layers on steel
//! or titanium, tempered colours, a film-coated mirror. The reflectance is the exact Airy sum
//! with a complex base index n + ik (Born & Wolf, *Principles of Optics*, §1.6.4 and §13.4; see
//! [`crate::optics::thinfilm`] and [`super::filmfresnel`]). The model is
//! [`super::smooth::Smooth`] over [`super::filmfresnel::FilmFresnel`] with a metal base.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `film_ior`, `medium_ior` | float or IOR name | 1.4 | — | index of the film; `keratin` = 1.532 + 5890/λ² (λ in nm) |
//! | `film_thickness`, `thickness` | float or texture | 500.0 | nm | thickness of the film; between 0 and 100000 |
//! | `mode` | string | `spectral` | — | `thesis`: the thesis's 650/510/475 nm point samples and phase term; one of 'spectral', 'thesis' |
//! | `material` | string | `Cu` | — | a named metal (`Au`, `Ag`, `Cu`, `Al`, … 71 of Mitsuba's); `none` is refused |
//! | `eta` | spectrum | 0.0 | — | real part of the metal's index (with `k`, instead of `material`) |
//! | `k` | spectrum | 1.0 | — | imaginary part (extinction) of the metal's index |
//! | `ext_ior` (0.6: `extIOR`) | float or IOR name | `air` | — | index of the exterior |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//!
//! The thesis's `conductorThinFilm` (`thickness`, `mediumIOR`, default film index BK7 and
//! 400 nm) loads with its own names and defaults.
//!
//! Only reflection exists; the power not reflected, 1 − R, enters the metal and is absorbed.
//! One-sided, as Mitsuba's conductors. In thesis mode the three point samples use the exact
//! Airy reflectance (the thesis's real-amplitude phase formula has no meaning over a metal).
//! Known limits: no absorption in the film.

use super::film::{load_film_surface, FILM, METAL_UNDER_FILM, THESIS_FILM};
use super::params::REFLECTION_FACTOR;
use super::Material;
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "thinfilmconductor" []
    "a thin film over a polished metal"
    [FILM, METAL_UNDER_FILM, REFLECTION_FACTOR] load);

declare!(THESIS_PLUGIN: Material = Bsdf "conductorThinFilm" []
    "the thesis's film-over-metal plugin: `thinfilmconductor` with its defaults"
    [THESIS_FILM, METAL_UNDER_FILM, REFLECTION_FACTOR] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    load_film_surface(a, true, false)
}
