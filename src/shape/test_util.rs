//! Helpers shared by the shapes' unit tests.

use super::{Hit, SurfaceInteraction};
use crate::math::Vec2;

/// The interaction at an analytic shape's hit, from what its `intersect` found (distance and
/// surface parameters) and its `interaction`.
pub(crate) fn first_hit(
    found: Option<(f32, Vec2)>,
    interaction: impl FnOnce(&Hit) -> SurfaceInteraction,
) -> Option<SurfaceInteraction> {
    let (t, uv) = found?;
    let h = Hit {
        t,
        shape: 0,
        prim: 0,
        uv,
    };
    Some(interaction(&h))
}

/// The mean of `n` draws of `x` and its standard error (for 4σ checks of Monte Carlo means).
pub(crate) fn mean_and_error(n: usize, mut x: impl FnMut() -> f64) -> (f64, f64) {
    let (mut s1, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let v = x();
        s1 += v;
        s2 += v * v;
    }
    let mean = s1 / n as f64;
    (mean, ((s2 / n as f64 - mean * mean) / n as f64).sqrt())
}
