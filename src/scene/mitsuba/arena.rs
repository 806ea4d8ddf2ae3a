//! Objects as read, before references are resolved: a `<ref id="…"/>` may name an object
//! declared later in the file (as in Mitsuba 3, which resolves references after parsing), so
//! the reader collects every object here and links the tree once the whole scene is read.
//!
//! Linking walks the objects depth first with an explicit stack (a long chain of references
//! cannot overflow the call stack) and refuses a reference cycle, naming the reference that
//! closes it.

use std::collections::HashMap;
use std::sync::Arc;

use super::{Child, Location, Node, SceneError};

/// What a child slot points to.
#[derive(Debug)]
pub(super) enum Target {
    /// An object read already (nested, or a reference to an earlier id).
    Obj(usize),
    /// A reference to an id not seen yet when the `<ref>` was read.
    Id(String),
}

/// A nested object or a reference, in document order.
#[derive(Debug)]
pub(super) struct PendingChild {
    pub name: Option<String>,
    pub target: Target,
    /// Where the nested object or the `<ref>` is written.
    pub loc: Location,
}

/// An object read but not yet linked.
pub(super) type Pending = Node<PendingChild>;

/// Every object of a scene (its includes too) and the ids declared.
#[derive(Default)]
pub(super) struct Arena {
    objects: Vec<Option<Pending>>,
    ids: HashMap<String, (usize, Location)>,
}

impl Arena {
    /// Stores an object; returns its index.
    pub fn push(&mut self, p: Pending) -> usize {
        self.objects.push(Some(p));
        self.objects.len() - 1
    }

    /// The index and declaration of an id.
    pub(crate) fn lookup(&self, id: &str) -> Option<&(usize, Location)> {
        self.ids.get(id)
    }

    /// Declares `id` for object `index`; the caller has checked that it is new.
    pub(crate) fn register(&mut self, id: String, index: usize, loc: Location) {
        self.ids.insert(id, (index, loc));
    }

    /// Links every object into the tree under `root`.
    pub(crate) fn link(mut self, root: Pending) -> Result<Node, SceneError> {
        let root_index = self.push(root);
        // Resolve forward references by id.
        for obj in self.objects.iter_mut().flatten() {
            for c in &mut obj.children {
                if let Target::Id(id) = &c.target {
                    match self.ids.get(id) {
                        Some((i, _)) => c.target = Target::Obj(*i),
                        None => {
                            return Err(SceneError::at(
                                &c.loc,
                                format!(
                                    "<ref id=\"{id}\">: unknown id '{id}'; expected the id of \
                                     an object declared in the scene"
                                ),
                            ))
                        }
                    }
                }
            }
        }
        let n = self.objects.len();
        let child_index = |c: &PendingChild| match c.target {
            Target::Obj(i) => i,
            Target::Id(_) => unreachable!("resolved above"),
        };
        // 0 = not visited, 1 = its children are being linked, 2 = built.
        let mut state = vec![0u8; n];
        let mut built: Vec<Option<Arc<Node>>> = vec![None; n];
        let mut stack = vec![root_index];
        while let Some(&top) = stack.last() {
            match state[top] {
                0 => {
                    state[top] = 1;
                    let obj = self.objects[top]
                        .as_ref()
                        .expect("unbuilt objects are present");
                    for c in &obj.children {
                        let i = child_index(c);
                        if state[i] == 1 {
                            let target = self.objects[i].as_ref().expect("in progress");
                            return Err(SceneError::at(
                                &c.loc,
                                format!(
                                    "found a reference cycle: {} (declared at {}) contains \
                                     itself through this reference; expected references \
                                     without loops",
                                    super::describe(
                                        target.tag,
                                        &target.plugin,
                                        target.id.as_deref()
                                    ),
                                    target.loc
                                ),
                            ));
                        }
                        if state[i] == 0 {
                            stack.push(i);
                        }
                    }
                }
                1 => {
                    stack.pop();
                    let obj = self.objects[top].take().expect("built once");
                    let node = obj.map_children(|c| Child {
                        node: built[child_index(&c)].clone().expect("children first"),
                        name: c.name,
                    });
                    built[top] = Some(Arc::new(node));
                    state[top] = 2;
                }
                _ => {
                    stack.pop();
                }
            }
        }
        let root = built[root_index].take().expect("the root is built last");
        // Nothing else holds the root: it is nobody's child.
        Ok(Arc::try_unwrap(root).expect("the root is not shared"))
    }
}
