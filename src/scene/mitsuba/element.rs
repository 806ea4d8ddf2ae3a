//! One parsed file (byte offsets → line:column) and its elements with `$name`-substituted
//! attributes, plus the message helpers that name the element.

use std::cell::Cell;
use std::collections::HashMap;
use std::fmt::Display;
use std::path::PathBuf;
use std::sync::Arc;

use roxmltree::Document;

use super::{literal, Location, SceneError};

/// One parsed file: positions in it and how to read it.
pub struct Source<'d, 'i> {
    doc: &'d Document<'i>,
    line_starts: Vec<usize>,
    pub file: Arc<PathBuf>,
    /// The folder that relative paths in this file are resolved against.
    pub dir: PathBuf,
    /// Whether this is a 0.x file whose names get upgraded.
    pub upgrade: bool,
    /// The last position computed (byte, line, column): positions are asked for in document
    /// order, so columns are counted on from there instead of from the line start, which keeps
    /// a huge one-line file linear rather than quadratic.
    cursor: Cell<(usize, usize, usize)>,
}

impl<'d, 'i> Source<'d, 'i> {
    pub fn new(doc: &'d Document<'i>, file: Arc<PathBuf>) -> Self {
        let text = doc.input_text();
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        let dir = file.parent().map(PathBuf::from).unwrap_or_default();
        Source {
            doc,
            line_starts,
            file,
            dir,
            upgrade: false,
            cursor: Cell::new((0, 1, 1)),
        }
    }

    /// The 1-based line and column (in characters) of a byte offset.
    pub fn loc(&self, byte: usize) -> Location {
        let text = self.doc.input_text();
        let byte = byte.min(text.len());
        let line = self.line_starts.partition_point(|&s| s <= byte).max(1);
        let (c_byte, c_line, c_col) = self.cursor.get();
        let col = if c_line == line && c_byte <= byte {
            c_col + text.get(c_byte..byte).map_or(0, |s| s.chars().count())
        } else {
            let start = self.line_starts[line - 1];
            1 + text.get(start..byte).map_or(0, |s| s.chars().count())
        };
        self.cursor.set((byte, line, col));
        Location {
            file: self.file.clone(),
            line: line as u32,
            col: col as u32,
        }
    }
}

/// An attribute after `$name` substitution.
pub(crate) struct Attr {
    pub name: String,
    pub value: String,
    pub loc: Location,
}

/// An element with its attributes substituted, for the value parsers.
pub(crate) struct Elem {
    pub tag: String,
    pub loc: Location,
    pub attrs: Vec<Attr>,
}

impl Elem {
    pub fn new(
        node: roxmltree::Node,
        src: &Source,
        params: &HashMap<String, String>,
    ) -> Result<Elem, SceneError> {
        let tag = node.tag_name().name().to_string();
        let loc = src.loc(node.range().start);
        let mut attrs = Vec::new();
        for a in node.attributes().filter(|a| a.namespace().is_none()) {
            let aloc = src.loc(a.range().start);
            let value = literal::substitute(a.value(), params).map_err(|m| {
                let what = match node.attribute("name") {
                    Some(n) => format!("<{tag} name=\"{n}\">"),
                    None => format!("<{tag}>"),
                };
                SceneError::at(
                    &aloc,
                    format!("{what}: attribute '{}': found {m}", a.name()),
                )
            })?;
            attrs.push(Attr {
                name: a.name().to_string(),
                value,
                loc: aloc,
            });
        }
        Ok(Elem { tag, loc, attrs })
    }

    pub fn get(&self, name: &str) -> Option<&Attr> {
        self.attrs.iter().find(|a| a.name == name)
    }

    pub(crate) fn require(&self, name: &str) -> Result<&Attr, SceneError> {
        self.get(name)
            .ok_or_else(|| self.err(format!("attribute '{name}' is missing; it is required")))
    }

    /// `<float name="radius">`, for messages.
    pub fn describe(&self) -> String {
        match self.get("name") {
            Some(n) => format!("<{} name=\"{}\">", self.tag, n.value),
            None => format!("<{}>", self.tag),
        }
    }

    pub fn err(&self, msg: impl Display) -> SceneError {
        SceneError::at(&self.loc, format!("{}: {msg}", self.describe()))
    }

    pub(crate) fn attr_err(&self, a: &Attr, msg: impl Display) -> SceneError {
        SceneError::at(
            &a.loc,
            format!("{}: attribute '{}': found {msg}", self.describe(), a.name),
        )
    }
}
