//! `tent`: the triangle (tent) reconstruction filter, linear from 1 at the sample to 0 at
//! `radius` pixels.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `radius` | float | 1.0 | pixels | where the triangle reaches zero; in (0, 16] |
//!
//! Known limits: none (the film samples it exactly by inverting its CDF).

use super::Filter;
use crate::plugin::{declare, Args, Param, SceneError};

declare!(PLUGIN: Filter = Rfilter "tent" []
    "triangle reconstruction filter"
    [&[Param::up_to("radius", 1.0, 16.0, "pixels")
        .doc("where the triangle reaches zero")]] load);

fn load(a: &mut Args, _: ()) -> Result<Filter, SceneError> {
    Ok(Filter::Tent {
        radius: a.float("radius")?,
    })
}
