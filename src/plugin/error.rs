//! The reader's error type.

use std::path::PathBuf;

use super::Location;

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The top-level scene file could not be read (missing, a directory, unreadable, not UTF-8).
    #[error("{}: cannot read scene file: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A file is not well-formed XML; `loc` is where the XML parser gave up.
    #[error("{loc}: malformed XML: {message}")]
    Xml { loc: Location, message: String },
    /// Anything else, at a known place in a scene file.
    #[error("{loc}: {message}")]
    At { loc: Location, message: String },
}

impl SceneError {
    /// An error at `loc`; for consumers reporting semantic problems (a negative radius, …).
    pub fn at(loc: &Location, message: impl Into<String>) -> SceneError {
        SceneError::At {
            loc: loc.clone(),
            message: message.into(),
        }
    }

    /// Where the problem is, when known.
    pub fn location(&self) -> Option<&Location> {
        match self {
            SceneError::Io { .. } => None,
            SceneError::Xml { loc, .. } | SceneError::At { loc, .. } => Some(loc),
        }
    }
}
