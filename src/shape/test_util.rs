//! Helpers shared by the shapes' unit tests.

use super::{Hit, Shape, ShapeSample, SurfaceInteraction};
use crate::math::{Pcg32, Vec2, Vec3};

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

/// E[1/pdf] over `n` direct samples of `shape` seen from `r` (the solid angle it subtends) and
/// its standard error. Each sample's density must agree with `pdf_direct` to the relative
/// tolerance `tol`, and passes `check`.
pub(crate) fn subtended_solid_angle(
    shape: &Shape,
    r: Vec3,
    rng: &mut Pcg32,
    (n, tol): (usize, f32),
    mut check: impl FnMut(&ShapeSample),
) -> (f64, f64) {
    mean_and_error(n, || {
        let s = shape.sample_direct(r, rng.next_vec2()).unwrap();
        check(&s);
        let pdf = shape.pdf_direct(r, s.p, s.n);
        assert!(
            (pdf - s.pdf).abs() <= tol * pdf.min(s.pdf),
            "{pdf} vs {}",
            s.pdf
        );
        1.0 / s.pdf as f64
    })
}
