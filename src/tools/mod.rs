//! Tools that sit above the renderer and use it (the BSDF inspector, quick renders, figures):
//! nothing in the renderer imports them.

pub mod inspect;
pub mod plot;
pub mod preview;
