//! Materials: BSDF parameters as textures, evaluated per shading point into a [`super::Bxdf`].
//! (stub; implemented by the BSDF work)

/// A material.
#[derive(Clone, Debug)]
pub enum Material {}
