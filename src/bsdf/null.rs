//! `null`: a surface that does not scatter — it only marks a boundary (or carries an
//! emitter); paths pass through it unchanged and the crossing does not count as a bounce, as
//! Mitsuba's `null`.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//!
//! Known limits: none.

use super::Material;
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Material = Bsdf "null" []
    "invisible boundary: paths pass through unchanged"
    [] load);

fn load(_: &mut Args, _: ()) -> Result<Material, SceneError> {
    Ok(Material::Null)
}
