//! Light-transport integrators.

pub mod aov;
pub mod direct;
pub mod path;
pub mod wave;

pub use path::{radiance, PathStrategy};
