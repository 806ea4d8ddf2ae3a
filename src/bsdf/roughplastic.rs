//! `roughplastic`: a diffuse substrate under a rough dielectric coating — the plastic model
//! of [`super::plastic`] with a microfacet coat (Walter et al. 2007; GGX or Beckmann,
//! isotropic, height-correlated Smith G, visible-normal sampling of the specular lobe).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `distribution` | string | `beckmann` | — | microfacet normal distribution; one of 'beckmann', 'ggx' |
//! | `alpha` | float or texture | 0.1 | RMS slope | roughness α; between 0 and 10 |
//! | `sample_visible` | boolean | true | — | accepted; visible normals are always sampled |
//! | `diffuse_reflectance` (0.6: `diffuseReflectance`) | spectrum or texture | 0.5 | — | albedo of the substrate |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//! | `int_ior` (0.6: `intIOR`) | float or IOR name | 1.49 | — | index of the coating (polypropylene) |
//! | `ext_ior` (0.6: `extIOR`) | float or IOR name | `air` | — | index of the exterior |
//! | `nonlinear` | boolean | false | — | account for the substrate's colour in the internal reflections |
//!
//! Known limits: as `plastic`; the coat's transmittance into and out of the substrate is that
//! of a smooth interface (see [`super::plastic`]).

use super::params::{ALPHA, DISTRIBUTION, SAMPLE_VISIBLE};
use super::plastic::{load_plastic, PLASTIC};
use super::Material;
use crate::bsdf::microfacet::MicrofacetType;
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "roughplastic" []
    "diffuse substrate under a rough dielectric coating"
    [&[DISTRIBUTION, ALPHA, SAMPLE_VISIBLE], PLASTIC] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let kind = match a.string("distribution")?.as_str() {
        "ggx" => MicrofacetType::Ggx,
        _ => MicrofacetType::Beckmann,
    };
    a.bool("sample_visible")?;
    let alpha = a.float_texture("alpha")?;
    load_plastic(a, Some((kind, alpha)))
}
