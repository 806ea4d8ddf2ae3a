//! `box`: the box reconstruction filter — every sample counts fully for the pixel it falls
//! in and for no other (radius half a pixel). The sharpest filter, and the one whose pixels
//! are plain averages, which is why comparisons with other renderers use it.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//!
//! Known limits: none.

use super::Filter;
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Filter = Rfilter "box" []
    "box reconstruction filter: each sample counts for its own pixel only"
    [] load);

fn load(_: &mut Args, _: ()) -> Result<Filter, SceneError> {
    Ok(Filter::Box)
}
