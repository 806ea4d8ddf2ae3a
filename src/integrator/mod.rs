//! Light-transport integrators.

pub mod path;

pub use path::{radiance, PathStrategy};
