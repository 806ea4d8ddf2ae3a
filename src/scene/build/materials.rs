//! Materials for shapes: the BSDF a shape names (nested or `<ref>`), built once per node
//! through the plugin registry, and Mitsuba's implicit default.

use super::Builder;
use crate::bsdf::Material;
use crate::plugin::{registry, Node, SceneError, Warning};
use std::sync::Arc;

impl Builder<'_> {
    /// Mitsuba's implicit BSDF for shapes without one: a diffuse 0.5.
    pub(crate) fn default_material(&mut self) -> u32 {
        if let Some(m) = self.default_material {
            return m;
        }
        self.materials.push(Material::default_diffuse());
        let i = self.materials.len() as u32 - 1;
        self.default_material = Some(i);
        i
    }
}

/// The material index for a BSDF node, building it once per node (shared through `<ref>`).
pub(crate) fn material_for(b: &mut Builder, node: &Arc<Node>) -> Result<u32, SceneError> {
    let key = Arc::as_ptr(node);
    if let Some(&i) = b.material_ids.get(&key) {
        return Ok(i);
    }
    let m = build_material(node, b.warnings)?;
    b.materials.push(m);
    let i = b.materials.len() as u32 - 1;
    b.material_ids.insert(key, i);
    Ok(i)
}

/// The material a `<bsdf>` node describes (nested BSDFs and textures included).
pub fn build_material(node: &Node, warnings: &mut Vec<Warning>) -> Result<Material, SceneError> {
    registry::bsdf(node, warnings)
}
