//! `twosided`: one BSDF on both sides of a surface, or one on each side (Mitsuba 3's
//! `twosided`): directions below the surface are mirrored to the front before evaluation, and
//! with two nested BSDFs the second one is used where the ray arrives from the back.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `(nested)` | bsdf | required | — | one BSDF for both sides, or two: front, then back |
//!
//! Known limits: none.

use super::Material;
use crate::plugin::{declare, Args, DefaultValue, Param, SceneError, Tag, Ty};

declare!(PLUGIN: Material = Bsdf "twosided" []
    "the same BSDF on both sides, or one per side"
    [&[Param::new("(nested)", Ty::Bsdf, DefaultValue::Required)
            .doc("one BSDF for both sides, or two: front, then back")]] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let inner = a.children(Tag::Bsdf);
    let (front, back) = match inner.as_slice() {
        [front] => (a.bsdf(front)?, None),
        [front, back] => (a.bsdf(front)?, Some(a.bsdf(back)?)),
        _ => {
            return Err(SceneError::at(
                &a.node().loc,
                format!(
                    "twosided needs one or two nested BSDFs, found {}",
                    inner.len()
                ),
            ))
        }
    };
    Ok(Material::TwoSided {
        front: Box::new(front),
        back: back.map(Box::new),
    })
}
