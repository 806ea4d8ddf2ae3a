//! Light-transport integrators: each plugin's manual, declaration, loader and estimator in its
//! own file (`moment` only loads: it renders its nested integrator).

pub mod aov;
pub mod direct;
pub(crate) mod moment;
pub mod path;
pub mod wave;

pub use path::{radiance, PathStrategy};
