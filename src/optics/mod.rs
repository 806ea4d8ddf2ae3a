//! Wave optics used by the materials: coherent thin-film interference, and the film tool.

pub mod filmtool;
pub mod thinfilm;
