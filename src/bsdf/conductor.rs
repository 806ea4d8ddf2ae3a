//! `conductor`: a polished metal (or an ideal mirror), reflecting by the exact Fresnel
//! reflectance of a complex index η + iκ per wavelength (Born & Wolf, §13.2). The model is
//! [`super::smooth::Smooth`] over [`super::fresnel::ConductorFresnel`]; `material = "none"` is
//! a perfect mirror (F = 1). The index is divided by `ext_ior`.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `material` | string | `none` | — | a named metal (`Au`, `Ag`, `Cu`, `Al`, … 71 of Mitsuba's) or `none` (a perfect mirror) |
//! | `eta` | spectrum | 0.0 | — | real part of the metal's index (with `k`, instead of `material`) |
//! | `k` | spectrum | 1.0 | — | imaginary part (extinction) of the metal's index |
//! | `ext_ior`, `ext_eta` (0.6: `extEta`) | float or IOR name | `air` | — | index of the medium outside the metal |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//!
//! One-sided, as in Mitsuba 3. Known limits: unpolarised light only.

use super::params::{conductor_ior, surface, METAL, REFLECTION_FACTOR};
use super::{Interface, Material};
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "conductor" []
    "polished metal or perfect mirror, measured complex indices"
    [METAL, REFLECTION_FACTOR] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let ior = conductor_ior(a)?;
    surface(a, Interface::Conductor(ior), false)
}
