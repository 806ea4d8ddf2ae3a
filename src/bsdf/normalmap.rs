//! `normalmap`: a nested BSDF shaded with normals from a texture, in tangent space (x along
//! ∂p/∂u, y along ∂p/∂v, z the shading normal), as Mitsuba 3's `normalmap`: from a `bitmap`
//! (n = 2·rgb − 1; give the bitmap `raw="true"` so a PNG is not sRGB-decoded) or from a
//! `scales` texture's relief (its slope in cells, times `strength`). The model is in
//! [`super::bumpmap`] (`Material::shading_frame`).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `(nested texture)` | texture | required | — | a `bitmap` (tangent-space normals) or a `scales` texture |
//! | `strength` | float | 1.0 | — | multiplies the slope of the normals |
//! | `(nested bsdf)` | bsdf | `diffuse` | — | the material |
//!
//! Known limits: the displaced surface is not traced (silhouettes stay smooth).

use super::bumpmap::{nested_bsdf, normal_source};
use super::Material;
use crate::plugin::{declare, Args, DefaultValue, Param, SceneError, Ty};

declare!(PLUGIN: Material = Bsdf "normalmap" []
    "a nested BSDF shaded with tangent-space normals from a texture"
    [&[
            Param::new("(nested texture)", Ty::Texture, DefaultValue::Required)
                .doc("a `bitmap` (tangent-space normals) or a `scales` texture"),
            Param::float("strength", 1.0).doc("multiplies the slope of the normals"),
            Param::new(
                "(nested bsdf)",
                Ty::Bsdf,
                DefaultValue::Derived("`diffuse`"),
            )
            .doc("the material"),
        ]] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    Ok(Material::NormalMap {
        source: normal_source(a)?,
        strength: a.float("strength")?,
        inner: Box::new(nested_bsdf(a)?),
    })
}
