//! `thindielectric`: a thin dielectric sheet — a window pane, a soap film without
//! interference — whose two parallel faces reflect with all internal reflections summed
//! incoherently: with single-face R = F(|cos θ|, η) and T = 1 − R the sheet reflects
//! R' = R + T²R / (1 − R²); what it does not reflect continues undeviated (wi = −wo). The model
//! is [`super::smooth::Smooth`] over [`super::fresnel::ThinSheetFresnel`].
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `int_ior` (0.6: `intIOR`) | float or IOR name | `bk7` | — | index of the interior |
//! | `ext_ior` (0.6: `extIOR`) | float or IOR name | `air` | — | index of the exterior |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//! | `specular_transmittance` | spectrum or texture | 1.0 | — | factor on the transmitted light (not physical) |
//!
//! Two-sided; no η² scaling (the ray leaves into the medium it came from). Known limits: no
//! absorption inside the sheet, no interference (the film plugins have that).

use super::params::{relative_ior, surface, DIELECTRIC_IORS, FACTORS};
use super::{Interface, Material};
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "thindielectric" []
    "a thin sheet (window pane): two faces, light passes straight on"
    [DIELECTRIC_IORS, FACTORS] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let eta = relative_ior(a)?;
    surface(a, Interface::ThinSheet { eta }, false)
}
