//! The reader proper: walks the XML, substitutes parameters, follows includes and `<path>`s,
//! collects objects and references (linked into [`Node`]s at the end, see `arena.rs`).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use roxmltree::{Document, ParsingOptions};

use super::arena::{Arena, Target};
pub(super) use super::builder::Builder;
use super::element::{Attr, Elem, Source};
use super::literal;
use super::resolver::read_text;
use super::{Location, Node, SceneError, Tag, Warning};
use crate::plugin::FileResolver;

/// Deepest nesting of elements and includes accepted; deeper input is an error, not a crash.
const MAX_DEPTH: usize = 100;

/// Reader state shared by a scene file and everything it includes.
pub(crate) struct Reader {
    pub(super) params: HashMap<String, String>,
    objects: Arena,
    /// Files being read, outermost first, for include-cycle detection.
    stack: Vec<PathBuf>,
    /// The folders looked in while reading (includes and `<spectrum filename>`): the current
    /// file's `<path>`s and its includers' folders, then the scene's folder.
    pub(super) search: FileResolver,
    /// The root file's folders once it is read, for plugin file names (see `resolver.rs`).
    files: Arc<OnceLock<FileResolver>>,
    warnings: Vec<Warning>,
}

fn parse_doc<'i>(text: &'i str, file: &Arc<PathBuf>) -> Result<Document<'i>, SceneError> {
    let at = |line, col| Location {
        file: file.clone(),
        line,
        col,
    };
    if text.trim().is_empty() {
        return Err(SceneError::at(
            &at(1, 1),
            "the file is empty; expected a <scene version=\"…\"> document",
        ));
    }
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let opts = ParsingOptions {
        allow_dtd: true,
        ..ParsingOptions::default()
    };
    Document::parse_with_options(text, opts).map_err(|e| {
        let pos = e.pos();
        let msg = e.to_string();
        let suffix = format!(" at {}:{}", pos.row, pos.col);
        let mut message = msg.strip_suffix(&suffix).unwrap_or(&msg).to_string();
        if matches!(e, roxmltree::Error::UnclosedRootNode) {
            // The parser points at the root; say where the text stopped too.
            let lines = text.split('\n').count();
            message.push_str(&format!(" (the file ends on line {lines}; truncated?)"));
        }
        SceneError::Xml {
            loc: at(pos.row, pos.col),
            message,
        }
    })
}

impl Reader {
    pub fn new(defines: &[(String, String)]) -> Reader {
        Reader {
            params: defines.iter().cloned().collect(),
            objects: Arena::default(),
            stack: Vec::new(),
            search: FileResolver::default(),
            files: Arc::default(),
            warnings: Vec::new(),
        }
    }

    /// Reads the scene in `text` (from `file`); warnings go to `warnings` whether or not the
    /// scene could be read, so that those leading up to an error can be shown with it.
    pub(crate) fn read_root(
        mut self,
        text: &str,
        file: &Path,
        warnings: &mut Vec<Warning>,
    ) -> Result<Node, SceneError> {
        let r = self.read_root_inner(text, file);
        warnings.append(&mut self.warnings);
        r
    }

    fn read_root_inner(&mut self, text: &str, file: &Path) -> Result<Node, SceneError> {
        self.search = FileResolver::for_scene(file);
        let file = Arc::new(file.to_path_buf());
        let doc = parse_doc(text, &file)?;
        let mut src = Source::new(&doc, file.clone());
        let root = doc.root_element();
        let loc = self.scene_root(root, &mut src)?;
        self.stack
            .push(std::fs::canonicalize(file.as_ref()).unwrap_or_else(|_| (*file).clone()));
        let mut b = Builder::new(
            Tag::Scene,
            "scene".into(),
            None,
            loc,
            &self.files,
            src.upgrade,
        );
        self.children(root, &src, &mut b, 0)?;
        let _ = self.files.set(self.search.clone());
        std::mem::take(&mut self.objects).link(b.finish()?)
    }

    fn warn(&mut self, loc: &Location, message: String) {
        self.warnings.push(Warning {
            loc: loc.clone(),
            message,
        });
    }

    pub(super) fn check_attrs(&mut self, e: &Elem, allowed: &[&str]) {
        for a in &e.attrs {
            if !allowed.contains(&a.name.as_str()) {
                let msg = format!(
                    "{}: unknown attribute '{}' ignored (expected {})",
                    e.describe(),
                    a.name,
                    allowed.join(", ")
                );
                self.warn(&a.loc.clone(), msg);
            }
        }
    }

    /// An element with its attributes substituted, checked against those it takes.
    fn open(
        &mut self,
        node: roxmltree::Node,
        src: &Source,
        allowed: &[&str],
    ) -> Result<Elem, SceneError> {
        let e = Elem::new(node, src, &self.params)?;
        self.check_attrs(&e, allowed);
        Ok(e)
    }

    /// Checks `<scene version="…">` and decides whether the file needs the 0.6 upgrade.
    fn scene_root(
        &mut self,
        root: roxmltree::Node,
        src: &mut Source,
    ) -> Result<Location, SceneError> {
        let e = Elem::new(root, src, &self.params)?;
        if e.tag != "scene" {
            return Err(e.err(format!(
                "found root element <{}>; expected <scene version=\"…\"> (single-object files \
                 are not supported)",
                e.tag
            )));
        }
        let v = e.require("version")?;
        let (major, _, _) = literal::parse_version(&v.value).map_err(|m| e.attr_err(v, m))?;
        src.upgrade = major < 2;
        self.check_attrs(&e, &["version"]);
        Ok(e.loc)
    }

    fn children(
        &mut self,
        parent: roxmltree::Node,
        src: &Source,
        b: &mut Builder,
        depth: usize,
    ) -> Result<(), SceneError> {
        for child in parent.children() {
            if child.is_element() {
                self.element(child, src, b, depth)?;
            } else if let Some(t) = child
                .text()
                .filter(|t| child.is_text() && !t.trim().is_empty())
            {
                let msg = format!("text '{}' ignored (expected only elements)", t.trim());
                self.warn(&src.loc(child.range().start), msg);
            }
        }
        Ok(())
    }

    fn element(
        &mut self,
        node: roxmltree::Node,
        src: &Source,
        b: &mut Builder,
        depth: usize,
    ) -> Result<(), SceneError> {
        let tag = node.tag_name().name();
        let loc = src.loc(node.range().start);
        if depth >= MAX_DEPTH {
            return Err(SceneError::at(
                &loc,
                format!(
                    "<{tag}>: found elements and includes nested deeper than {MAX_DEPTH} levels"
                ),
            ));
        }
        match tag {
            "default" => self.default(node, src),
            "include" => {
                let e = self.open(node, src, &["filename"])?;
                // Looked up with the including file's folder first.
                self.searching(src.dir.clone(), |r| r.include(src, &e, b, depth))
            }
            "path" => self.path(node, src, b),
            "ref" => self.reference(node, src, b),
            "alias" => self.alias(node, src),
            "float" | "integer" | "boolean" | "string" | "point" | "vector" | "rgb" | "srgb"
            | "blackbody" | "transform" => self.value(node, src, b),
            "spectrum" if !node.has_attribute("type") => self.value(node, src, b),
            "translate" | "rotate" | "scale" | "matrix" | "lookat" | "lookAt" => Err(SceneError::at(
                &loc,
                format!("found <{tag}> outside <transform>; expected it inside <transform name=\"to_world\">"),
            )),
            "scene" => Err(SceneError::at(&loc, "found a nested <scene>; expected it only as the root")),
            _ => match Tag::from_name(tag) {
                Some(t) => self.object(node, src, b, t, depth),
                None => {
                    let msg = format!(
                        "unknown element <{tag}> ignored (expected an object such as <shape>, a \
                         value such as <float>, or <ref>, <include>, <default>, <alias>)"
                    );
                    self.warn(&loc, msg);
                    Ok(())
                }
            },
        }
    }

    /// The `name` attribute, upgraded for 0.6 files; `(name, as written)`.
    pub(super) fn name_of(e: &Elem, src: &Source) -> Option<(String, String)> {
        let orig = e.get("name")?.value.clone();
        let name = if src.upgrade {
            literal::to_snake_case(&orig)
        } else {
            orig.clone()
        };
        Some((name, orig))
    }

    fn register(&mut self, id: &str, index: usize, e: &Elem) -> Result<(), SceneError> {
        if let Some((_, first)) = self.objects.lookup(id) {
            return Err(e.err(format!(
                "found duplicate id '{id}'; it was first declared at {first}"
            )));
        }
        self.objects.register(id.to_string(), index, e.loc.clone());
        Ok(())
    }

    /// An id declared earlier (aliases need one, as in Mitsuba).
    fn lookup(&self, e: &Elem, a: &Attr) -> Result<usize, SceneError> {
        match self.objects.lookup(&a.value) {
            Some((i, _)) => Ok(*i),
            None => Err(e.attr_err(
                a,
                format!(
                    "unknown id '{}'; expected the id of an object declared earlier",
                    a.value
                ),
            )),
        }
    }

    fn object(
        &mut self,
        node: roxmltree::Node,
        src: &Source,
        b: &mut Builder,
        tag: Tag,
        depth: usize,
    ) -> Result<(), SceneError> {
        let e = self.open(node, src, &["type", "id", "name"])?;
        let plugin = e.require("type")?.value.clone();
        let id = e.get("id").map(|a| a.value.clone());
        if id.as_deref() == Some("") || plugin.is_empty() {
            return Err(e.err("found an empty 'type' or 'id'; expected a non-empty one"));
        }
        let mut cb = Builder::new(
            tag,
            plugin,
            id.clone(),
            e.loc.clone(),
            &self.files,
            src.upgrade,
        );
        self.children(node, src, &mut cb, depth + 1)?;
        let index = self.objects.push(cb.finish()?);
        if let Some(id) = &id {
            self.register(id, index, &e)?;
        }
        b.add_child(
            Self::name_of(&e, src).map(|n| n.0),
            Target::Obj(index),
            e.loc,
        )
    }

    fn reference(
        &mut self,
        node: roxmltree::Node,
        src: &Source,
        b: &mut Builder,
    ) -> Result<(), SceneError> {
        let e = self.open(node, src, &["id", "name"])?;
        self.no_children(node, src, &e);
        let id = &e.require("id")?.value;
        // An id declared later is linked once the whole scene is read.
        let target = match self.objects.lookup(id) {
            Some((i, _)) => Target::Obj(*i),
            None => Target::Id(id.clone()),
        };
        b.add_child(Self::name_of(&e, src).map(|n| n.0), target, e.loc.clone())
    }

    fn alias(&mut self, node: roxmltree::Node, src: &Source) -> Result<(), SceneError> {
        let e = self.open(node, src, &["id", "as"])?;
        let target = self.lookup(&e, e.require("id")?)?;
        let new_id = e.require("as")?.value.clone();
        self.register(&new_id, target, &e)
    }

    fn default(&mut self, node: roxmltree::Node, src: &Source) -> Result<(), SceneError> {
        let e = self.open(node, src, &["name", "value"])?;
        let name = e.require("name")?;
        let value = e.require("value")?.value.clone();
        if name.value.is_empty()
            || !name
                .value
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_')
        {
            return Err(e.attr_err(
                name,
                format!(
                    "'{}'; expected a name of letters, digits and '_'",
                    name.value
                ),
            ));
        }
        // Defines given on the command line, and earlier defaults, win.
        self.params.entry(name.value.clone()).or_insert(value);
        Ok(())
    }

    /// Runs `f` with `dir` searched first; what `f` adds to the search list ends with it.
    fn searching<T>(&mut self, dir: PathBuf, f: impl FnOnce(&mut Self) -> T) -> T {
        let saved = self.search.clone();
        self.search.prepend(dir);
        let r = f(self);
        self.search = saved;
        r
    }

    /// `<include filename="…"/>`: the objects of another file, read into `b`.
    fn include(
        &mut self,
        src: &Source,
        e: &Elem,
        b: &mut Builder,
        depth: usize,
    ) -> Result<(), SceneError> {
        let name = Path::new(&e.require("filename")?.value);
        let path = self.search.find(name).unwrap_or_else(|| src.dir.join(name));
        let text = read_text(&path).map_err(|io| {
            e.err(format!(
                "cannot read included file '{}': {io}",
                path.display()
            ))
        })?;
        let key = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        if let Some(i) = self.stack.iter().position(|p| *p == key) {
            let chain: Vec<String> = self.stack[i..]
                .iter()
                .chain(std::iter::once(&key))
                .map(|p| p.display().to_string())
                .collect();
            return Err(e.err(format!("found an include cycle: {}", chain.join(" → "))));
        }
        let file = Arc::new(path);
        let doc = parse_doc(&text, &file)?;
        let mut inner = Source::new(&doc, file);
        let root = doc.root_element();
        self.scene_root(root, &mut inner)?;
        self.stack.push(key);
        let r = self.children(root, &inner, b, depth + 1);
        self.stack.pop();
        r
    }

    /// `<path value="dir"/>`: a folder searched first from now on (see `resolver.rs`).
    fn path(&mut self, node: roxmltree::Node, src: &Source, b: &Builder) -> Result<(), SceneError> {
        let e = self.open(node, src, &["value"])?;
        self.no_children(node, src, &e);
        if b.tag != Tag::Scene {
            return Err(e.err(format!(
                "found <path> inside {}; expected it directly inside <scene>",
                b.props.owner()
            )));
        }
        let a = e.require("value")?;
        let written = Path::new(&a.value);
        let here = src.dir.join(written);
        let dir = if written.is_absolute() || here.is_dir() {
            here
        } else {
            self.search.find(written).unwrap_or(here)
        };
        if !dir.is_dir() {
            return Err(e.attr_err(
                a,
                format!(
                    "'{}', which is not a folder (looked for {}); expected an existing folder",
                    a.value,
                    dir.display()
                ),
            ));
        }
        self.search.prepend(dir);
        Ok(())
    }

    pub(super) fn no_children(&mut self, node: roxmltree::Node, src: &Source, e: &Elem) {
        for c in node.children().filter(|c| c.is_element()) {
            let msg = format!(
                "<{}> inside {} ignored (it takes no nested elements)",
                c.tag_name().name(),
                e.describe()
            );
            self.warn(&src.loc(c.range().start), msg);
        }
    }
}
