//! `per_scale`: a float that varies from scale to scale — the random id of the `scales` cell
//! under the point, mapped linearly onto a range. Any float parameter can take it; the intended
//! use is a film thickness that differs per scale (e.g. 900 ± 60 nm), the spatially varying
//! layer thickness the thesis lists as future work.
//!
//! Model: value = `min` + id·(`max` − `min`), id ∈ [0, 1) the cell's hash (see `scales.rs`), so
//! values are uniform over [`min`, `max`) and constant over each scale (grooves included: a
//! groove point belongs to its nearest cell).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `(nested)` | texture | required | — | the `scales` texture whose cells are used (nested or `<ref>`; share one with the bump map so that the values follow the visible scales) |
//! | `min` | float | 0.0 | — | value for id = 0 |
//! | `max` | float | 1.0 | — | value for id → 1 |
//! | `mean` | float | — | — | alternative to `min`/`max`: the centre … |
//! | `spread` | float | — | — | … and half width: [mean − spread, mean + spread); non-negative |
//!
//! Limits: uniform distribution only; no filtering (the value is constant per cell, so there is
//! nothing to blur until cells shrink below a pixel, where it should average — it does not).

use super::scales::{load_cells, Scales};
use super::{FloatTexture, Texture, Want};
use crate::math::Vec2;
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Tag, Ty};
use std::sync::Arc;

declare!(PLUGIN: Texture, Want = Texture "per_scale" []
    "a number per scale of a `scales` texture (e.g. a film thickness)"
    [&[
            Param::new("(nested)", Ty::Texture, DefaultValue::Required).doc(
                "the `scales` texture whose cells are used (nested or `<ref>`; share one with \
                 the bump map so that the values follow the visible scales)",
            ),
            Param::float("min", 0.0).doc("value for id = 0"),
            Param::float("max", 1.0).doc("value for id → 1"),
            Param::new("mean", Ty::Float, DefaultValue::None)
                .doc("alternative to `min`/`max`: the centre …"),
            Param::new("spread", Ty::Float, DefaultValue::None)
                .check(Check::NonNegative)
                .doc("… and half width: [mean − spread, mean + spread)"),
        ]] load);

fn load(a: &mut Args, want: Want) -> Result<Texture, SceneError> {
    if want != Want::Float {
        return Err(SceneError::at(
            &a.node().loc,
            "per_scale gives a number per scale; it cannot be used as a colour or for normals",
        ));
    }
    let inner = a.children(Tag::Texture);
    let cells = match inner.as_slice() {
        [c] if super::scales::PLUGIN.info.is_called(&c.plugin) => {
            let info = &super::scales::PLUGIN.info;
            let mut w = Vec::new();
            let cells = load_cells(&Args::new(c, info, &mut w))?;
            a.warnings().extend(w);
            cells
        }
        _ => {
            return Err(SceneError::at(
                &a.node().loc,
                "per_scale needs exactly one nested (or referenced) 'scales' texture",
            ))
        }
    };
    let (lo, hi) = if a.has("mean") || a.has("spread") {
        let mean = a.float_opt("mean")?.unwrap_or(0.5);
        let spread = a.float_opt("spread")?.unwrap_or(0.0);
        (mean - spread, mean + spread)
    } else {
        (a.float("min")?, a.float("max")?)
    };
    Ok(Texture::Float(FloatTexture::PerScale(PerScale {
        cells: Arc::new(cells),
        lo,
        hi,
    })))
}

/// A per-cell value in [`lo`, `hi`).
#[derive(Clone, Debug)]
pub struct PerScale {
    pub cells: Arc<Scales>,
    pub lo: f32,
    pub hi: f32,
}

impl PerScale {
    /// The value of the cell under `uv`.
    #[inline]
    pub fn eval(&self, uv: Vec2) -> f32 {
        self.lo + self.cells.id_at(uv) * (self.hi - self.lo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;

    #[test]
    fn values_fill_the_range_uniformly_and_follow_the_cells() {
        let cells = Arc::new(Scales {
            irregularity: 0.5,
            ..Scales::default()
        });
        let t = PerScale {
            cells: cells.clone(),
            lo: 840.0,
            hi: 960.0,
        };
        let mut rng = Pcg32::new(1, 2);
        let mut seen = std::collections::HashMap::new();
        for _ in 0..20000 {
            let uv = rng.next_vec2();
            let v = t.eval(uv);
            assert!((840.0..960.0).contains(&v));
            let cell = cells.sample(uv).cell;
            // Constant over a cell.
            let prev = *seen.entry(cell).or_insert(v);
            assert_eq!(prev, v);
        }
        // 400 cells: the mean of uniform values on [840, 960) is 900 with σ = 120/√12/√n.
        let n = seen.len() as f32;
        assert!(n > 350.0);
        let mean = seen.values().sum::<f32>() / n;
        let sigma = 120.0 / 12f32.sqrt() / n.sqrt();
        assert!((mean - 900.0).abs() < 4.0 * sigma, "mean {mean}, σ {sigma}");
    }
}
