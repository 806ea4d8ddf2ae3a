//! Mitsuba's `cube`: the cube [−1, 1]³ with outward normals, as 12 triangles (the mesh is built in [`super::primitives`]).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |

use super::{Parts, TriangleMesh};
use crate::math::Transform;
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Parts, Transform = Shape "cube" []
    "the cube [−1, 1]³ with outward normals, as 12 triangles"
    [super::PLACEMENT] load);

fn load(a: &mut Args, parent: Transform) -> Result<Parts, SceneError> {
    super::primitives::load(a, &parent, TriangleMesh::cube)
}
