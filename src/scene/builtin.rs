//! Scenes built into the library, which need no file beside them.

/// The flagship (`scenes/xenopeltis.xml`): the sunbeam snake that `ophis render` renders
/// without a scene argument.
pub const XENOPELTIS_XML: &str = include_str!("../../scenes/xenopeltis.xml");
