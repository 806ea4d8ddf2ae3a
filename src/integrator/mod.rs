//! Light-transport integrators.

pub mod aov;
pub mod path;

pub use path::{radiance, PathStrategy};
