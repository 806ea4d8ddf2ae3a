//! `per_scale`: a float that varies from scale to scale — the random id of the `scales` cell
//! under the point, mapped linearly onto a range. Any float parameter can take it; the intended
//! use is a film thickness that differs per scale (e.g. 900 ± 60 nm), the spatially varying
//! layer thickness the thesis lists as future work.
//!
//! Model: value = `min` + id·(`max` − `min`) + `band_spread`·b(v_c/`band_length`), id ∈ [0, 1)
//! the cell's hash (see `scales.rs`), so the first part is uniform over [`min`, `max`); all of
//! it is constant over each scale (grooves included: a groove point belongs to its nearest
//! cell). The optional second part varies smoothly along v, the length of a `snake`'s body, so
//! that neighbouring scales share most of their value and it changes in broad bands over many
//! scales: v_c is the v of the cell's centre and b a smooth noise in [−1, 1] — independent
//! uniform values at v = k·`band_length` (k whole; drawn from the `scales` seed), joined by
//! smoothstep, so b is C¹ and spends as long near each value as it takes to pass through it.
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
//! | `band_spread` | float | 0.0 | — | half width of a smooth variation along v shared by neighbouring scales; non-negative |
//! | `band_length` | float | 1.0 | UV | distance along v between its independent values; positive |
//!
//! Limits: uniform distribution only; no filtering (the value is constant per cell, so there is
//! nothing to blur until cells shrink below a pixel, where it should average — it does not).

use super::scales::{load_cells, mix, unit, Scales};
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
            Param::float("band_spread", 0.0)
                .check(Check::NonNegative)
                .doc("half width of a smooth variation along v shared by neighbouring scales"),
            Param::float("band_length", 1.0)
                .check(Check::Positive)
                .unit("UV")
                .doc("distance along v between its independent values"),
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
        band_spread: a.float("band_spread")?,
        band_length: a.float("band_length")?,
    })))
}

/// A per-cell value in [`lo`, `hi`), plus a smooth variation along v of ±`band_spread`.
#[derive(Clone, Debug)]
pub struct PerScale {
    pub cells: Arc<Scales>,
    pub lo: f32,
    pub hi: f32,
    pub band_spread: f32,
    /// Distance along v between the band's independent values (UV units).
    pub band_length: f32,
}

impl PerScale {
    /// The value of the cell under `uv`.
    #[inline]
    pub fn eval(&self, uv: Vec2) -> f32 {
        if self.band_spread == 0.0 {
            return self.lo + self.cells.id_at(uv) * (self.hi - self.lo);
        }
        let (_, h, c) = self.cells.nearest_center(uv);
        let v = c.y / self.cells.cells_per_uv().y;
        let band = smooth_noise(v / self.band_length, self.cells.seed);
        self.lo + unit(h) * (self.hi - self.lo) + self.band_spread * band
    }
}

/// A value in [−1, 1) for the whole number `k` (a hash of it and `seed`).
#[inline]
fn knot(k: i64, seed: u32) -> f32 {
    let h = mix(k as u64 as u32 ^ mix((k as u64 >> 32) as u32 ^ mix(seed ^ 0x2545_f491)));
    2.0 * unit(h) - 1.0
}

/// Smooth 1-D noise in [−1, 1]: independent uniform values at the whole numbers, joined by
/// smoothstep (C¹, zero slope at the knots).
pub fn smooth_noise(x: f32, seed: u32) -> f32 {
    let k = x.floor();
    let t = x - k;
    let s = t * t * (3.0 - 2.0 * t);
    let (a, b) = (knot(k as i64, seed), knot(k as i64 + 1, seed));
    a + (b - a) * s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;

    /// `PerScale` over `cells` with values in [lo, hi) and bands of `band_spread` (length 1).
    fn per_scale(cells: Scales, lo: f32, hi: f32, band_spread: f32) -> (Arc<Scales>, PerScale) {
        let cells = Arc::new(cells);
        let t = PerScale {
            cells: cells.clone(),
            lo,
            hi,
            band_spread,
            band_length: 1.0,
        };
        (cells, t)
    }

    /// The values of `t` at 20,000 points drawn by `uv`, by the key of their cell; each value
    /// in `range`, one value per cell.
    fn values_by_cell<K: std::hash::Hash + Eq>(
        t: &PerScale,
        mut uv: impl FnMut() -> Vec2,
        key: impl Fn(Vec2) -> K,
        range: impl std::ops::RangeBounds<f32>,
    ) -> std::collections::HashMap<K, f32> {
        let mut seen = std::collections::HashMap::new();
        for _ in 0..20000 {
            let uv = uv();
            let v = t.eval(uv);
            assert!(range.contains(&v), "{v}");
            assert_eq!(*seen.entry(key(uv)).or_insert(v), v);
        }
        seen
    }

    #[test]
    fn values_fill_the_range_uniformly_and_follow_the_cells() {
        let cells = Scales {
            irregularity: 0.5,
            ..Scales::default()
        };
        let (cells, t) = per_scale(cells, 840.0, 960.0, 0.0);
        let mut rng = Pcg32::new(1, 2);
        let key = |uv| cells.sample(uv).cell;
        let seen = values_by_cell(&t, || rng.next_vec2(), key, 840.0..960.0);
        // 400 cells: the mean of uniform values on [840, 960) is 900 with σ = 120/√12/√n.
        let n = seen.len() as f32;
        assert!(n > 350.0);
        let mean = seen.values().sum::<f32>() / n;
        let sigma = 120.0 / 12f32.sqrt() / n.sqrt();
        assert!((mean - 900.0).abs() < 4.0 * sigma, "mean {mean}, σ {sigma}");
    }

    #[test]
    fn bands_are_constant_per_cell_bounded_and_shared_by_neighbours() {
        let cells = Scales {
            scale_u: 15.0,
            scale_v: 15.0,
            ..Scales::default()
        };
        let (cells, t) = per_scale(cells, 315.0, 345.0, 140.0);
        let mut rng = Pcg32::new(3, 4);
        let uv = || Vec2::new(rng.next_f32(), 8.0 * rng.next_f32());
        // Keyed by the cell's centre: lattice indices wrap every unit of v here.
        let key = |uv| {
            let c = cells.nearest_center(uv).2;
            (c.x.to_bits(), c.y.to_bits())
        };
        let seen = values_by_cell(&t, uv, key, 175.0..=485.0);
        // The band moves by at most 1.5·2·band_spread per band_length (smoothstep's steepest
        // slope), so scales a row apart (1/15 of it) differ by ≤ 28 nm + the per-cell 30 nm.
        for k in 0..2000 {
            let uv = Vec2::new(0.5, k as f32 * 0.004);
            let step = Vec2::new(0.0, 1.0 / 15.0);
            assert!((t.eval(uv) - t.eval(uv + step)).abs() <= 28.0 + 30.0 + 1e-3);
        }
        // Across the body, values cover most of the band's range.
        let (lo, hi) = seen
            .values()
            .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        assert!(lo < 250.0 && hi > 410.0, "{lo} {hi}");
    }

    #[test]
    fn smooth_noise_is_continuous_and_in_range() {
        for i in 0..4000 {
            let x = i as f32 * 0.01 - 20.0;
            let (a, b) = (smooth_noise(x, 7), smooth_noise(x + 1e-3, 7));
            assert!((-1.0..=1.0).contains(&a));
            assert!((a - b).abs() < 4e-3, "jump at {x}");
        }
    }
}
