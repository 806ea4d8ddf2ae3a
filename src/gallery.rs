//! The figures of the thesis and the CEIG 2023 paper as a gallery: which scenes, with which
//! parameters, in which grid; rendering them and composing contact sheets (`ophis gallery`).
//! Also the built-in Xenopeltis scene that `ophis render` renders without a scene argument.

/// The flagship scene (`scenes/xenopeltis.xml`), built into the binary. It needs no other file.
pub const XENOPELTIS_XML: &str = include_str!("../scenes/xenopeltis.xml");
