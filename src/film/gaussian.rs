//! `gaussian`: the Gaussian reconstruction filter (Mitsuba's default), of standard deviation
//! `stddev` pixels, truncated at 4σ and shifted down to reach zero there.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `stddev` | float | 0.5 | pixels | standard deviation; in (0, 4] |
//!
//! The film samples offsets from it through a 1025-entry inverse-CDF table built here from
//! an 8192-cell CDF (see `film.rs` for filter importance sampling).
//!
//! Known limits: none.

use super::{Filter, GAUSS_TABLE};
use crate::plugin::{declare, Args, Param, SceneError};

/// Mitsuba's default standard deviation, in pixels.
pub(crate) const DEFAULT_STDDEV: f32 = 0.5;

declare!(PLUGIN: Filter = Rfilter "gaussian" []
    "Gaussian reconstruction filter (the default), truncated at 4σ"
    [&[Param::up_to("stddev", DEFAULT_STDDEV, 4.0, "pixels")
        .doc("standard deviation")]] load);

fn load(a: &mut Args, _: ()) -> Result<Filter, SceneError> {
    Ok(Filter::gaussian(a.float("stddev")?))
}

impl Filter {
    /// A Gaussian filter with a tabulated inverse CDF for sampling.
    pub fn gaussian(stddev: f32) -> Filter {
        let r = 4.0 * stddev;
        let f = |x: f32| {
            ((-x * x / (2.0 * stddev * stddev)).exp() - (-r * r / (2.0 * stddev * stddev)).exp())
                .max(0.0)
        };
        // CDF on a fine grid over [−r, r], inverted at GAUSS_TABLE + 1 evenly spaced levels.
        let m = 8192;
        let h = 2.0 * r / m as f32;
        let mut cdf = vec![0.0f64; m + 1];
        for i in 0..m {
            let x = -r + (i as f32 + 0.5) * h;
            cdf[i + 1] = cdf[i] + f(x) as f64;
        }
        let total = cdf[m];
        let mut inv = Vec::with_capacity(GAUSS_TABLE + 1);
        let mut j = 0;
        for k in 0..=GAUSS_TABLE {
            let target = total * k as f64 / GAUSS_TABLE as f64;
            while j < m && cdf[j + 1] < target {
                j += 1;
            }
            let seg = (cdf[(j + 1).min(m)] - cdf[j]).max(1e-300);
            let t = ((target - cdf[j]) / seg).clamp(0.0, 1.0);
            inv.push(-r + (j as f32 + t as f32) * h);
        }
        Filter::Gaussian {
            stddev,
            inv_cdf: inv,
        }
    }
}
