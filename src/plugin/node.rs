//! The scene description: a tree of objects (`<bsdf type="diffuse">…`) with typed parameters,
//! whatever wrote it (the Mitsuba XML reader, or a dictionary from Python). Plugin loaders read
//! it through [`super::Args`]; positions in the source travel with every value so that errors
//! can name file, line and column.

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

use super::Properties;

/// A position in a scene file; displays as `file:line:col` (both 1-based).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Location {
    pub file: Arc<PathBuf>,
    pub line: u32,
    pub col: u32,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.col)
    }
}

/// The kind of a scene object (the XML element name).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Tag {
    Scene,
    Shape,
    Bsdf,
    Emitter,
    Sensor,
    Film,
    Sampler,
    Integrator,
    Texture,
    Rfilter,
    Medium,
    Phase,
    Volume,
    Spectrum,
}

impl Tag {
    /// The element name, e.g. `"bsdf"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Tag::Scene => "scene",
            Tag::Shape => "shape",
            Tag::Bsdf => "bsdf",
            Tag::Emitter => "emitter",
            Tag::Sensor => "sensor",
            Tag::Film => "film",
            Tag::Sampler => "sampler",
            Tag::Integrator => "integrator",
            Tag::Texture => "texture",
            Tag::Rfilter => "rfilter",
            Tag::Medium => "medium",
            Tag::Phase => "phase",
            Tag::Volume => "volume",
            Tag::Spectrum => "spectrum",
        }
    }

    /// The object tag for an element name (`scene` included); `None` for anything else.
    pub(crate) fn from_name(name: &str) -> Option<Tag> {
        const ALL: [Tag; 14] = [
            Tag::Scene,
            Tag::Shape,
            Tag::Bsdf,
            Tag::Emitter,
            Tag::Sensor,
            Tag::Film,
            Tag::Sampler,
            Tag::Integrator,
            Tag::Texture,
            Tag::Rfilter,
            Tag::Medium,
            Tag::Phase,
            Tag::Volume,
            Tag::Spectrum,
        ];
        ALL.into_iter().find(|t| t.as_str() == name)
    }
}

impl fmt::Display for Tag {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A scene object: `<bsdf type="diffuse" id="red">…</bsdf>`. While the scene is being read its
/// children are references not yet resolved (`C`, the reader's own type); once linked, they
/// are [`Child`]ren.
#[derive(Debug)]
pub struct Node<C = Child> {
    pub tag: Tag,
    /// The `type` attribute (`"scene"` for the root).
    pub plugin: String,
    pub id: Option<String>,
    pub props: Properties,
    /// Nested objects and resolved `<ref>`s, in document order.
    pub children: Vec<C>,
    /// Where the element starts.
    pub loc: Location,
}

impl<C> Node<C> {
    /// The same object with each child turned into `f` of it.
    pub(crate) fn map_children<D>(self, f: impl FnMut(C) -> D) -> Node<D> {
        Node {
            tag: self.tag,
            plugin: self.plugin,
            id: self.id,
            props: self.props,
            children: self.children.into_iter().map(f).collect(),
            loc: self.loc,
        }
    }
}

/// A nested object of a [`Node`], or a resolved `<ref>`.
#[derive(Clone, Debug)]
pub struct Child {
    /// The `name` attribute (`"bsdf"`, `"interior"`, …), snake_cased for 0.6 scenes.
    pub name: Option<String>,
    pub node: Arc<Node>,
}

impl Node {
    /// The child given with `name="…"`, if any.
    pub fn child(&self, name: &str) -> Option<&Arc<Node>> {
        self.children
            .iter()
            .find(|c| c.name.as_deref() == Some(name))
            .map(|c| &c.node)
    }

    /// All children with the given tag, named or not.
    pub(crate) fn children_with_tag(&self, tag: Tag) -> impl Iterator<Item = &Arc<Node>> + '_ {
        self.children
            .iter()
            .filter(move |c| c.node.tag == tag)
            .map(|c| &c.node)
    }

    /// "bsdf 'diffuse'" or "bsdf 'diffuse' (id 'red')", for messages.
    pub fn describe(&self) -> String {
        describe(self.tag, &self.plugin, self.id.as_deref())
    }
}

pub(crate) fn describe(tag: Tag, plugin: &str, id: Option<&str>) -> String {
    match (tag, id) {
        (Tag::Scene, _) => "the scene".to_string(),
        (_, Some(id)) => format!("{tag} '{plugin}' (id '{id}')"),
        (_, None) => format!("{tag} '{plugin}'"),
    }
}

/// Something suspicious that does not stop loading.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    pub loc: Location,
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: warning: {}", self.loc, self.message)
    }
}
