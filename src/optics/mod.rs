//! Wave optics used by the materials: coherent thin-film interference.

pub mod thinfilm;
