//! Tools that sit above the renderer and use it (the BSDF inspector, quick renders): nothing
//! in the renderer imports them.

pub mod inspect;
pub mod preview;
