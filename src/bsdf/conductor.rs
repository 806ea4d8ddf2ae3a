//! `conductor`: a polished metal (or an ideal mirror), reflecting by the exact Fresnel
//! reflectance of a complex index η + iκ per wavelength (Born & Wolf, §13.2). The model is
//! [`super::smooth::Smooth`] over [`super::fresnel::ConductorFresnel`]; `material = "none"` is
//! a perfect mirror (F = 1). The index is divided by `ext_ior`.
//!
//! ## Parameters
//!
//! PARAMS
//!
//! One-sided, as in Mitsuba 3. Known limits: unpolarised light only.

use super::params::{conductor_ior, surface, METAL, REFLECTION_FACTOR};
use super::{Interface, Material};
use crate::plugin::{Args, Info, Plugin, SceneError, Tag};

/// The `conductor` plugin.
pub(crate) const PLUGIN: Plugin<Material> = Plugin {
    info: Info {
        name: "conductor",
        aliases: &[],
        tag: Tag::Bsdf,
        summary: "polished metal or perfect mirror, measured complex indices",
        params: &[METAL, REFLECTION_FACTOR],
        file: file!(),
    },
    load,
};

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let ior = conductor_ior(a)?;
    surface(a, Interface::Conductor(ior), false)
}
