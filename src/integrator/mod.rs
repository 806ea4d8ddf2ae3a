//! Light-transport integrators.

pub mod aov;
pub mod direct;
pub mod path;

pub use path::{radiance, PathStrategy};
