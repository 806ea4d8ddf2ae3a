//! `hdrfilm`: the film. It accumulates spectral samples as CIE XYZ and develops them into
//! linear sRGB (written as EXR, or PNG when the output name asks for it; `ldrfilm` loads as the
//! same film).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `width` | integer | 768 | pixels | image width; between 1 and 32768 |
//! | `height` | integer | 576 | pixels | image height; between 1 and 32768 |
//! | `(nested)` | rfilter | `gaussian` | — | the reconstruction filter: `box`, `tent` or `gaussian` (the last one given) |
//!
//! Reconstruction uses filter importance sampling (Ernst et al. 2006, "Filter Importance
//! Sampling"): each camera sample is placed at an offset drawn from the pixel filter and
//! contributes with weight 1 to its own pixel only. For the non-negative filters Mitsuba offers
//! (`box`, `tent`, `gaussian`, each in its own file beside this one) this converges to the same
//! image as splatting, keeps pixels independent (bit-identical results whatever the thread
//! count), and costs one write per sample.
//!
//! Known limits: Mitsuba's `file_format`, `pixel_format`, `component_format`, crop window and
//! `sample_border` are not read (ophis writes RGB EXR or sRGB PNG of the whole image); the
//! command line's `--resolution` replaces `width` and `height`.

use crate::math::Vec2;
use crate::simd::{Float, Int};
use crate::spectrum::{cie, SampledSpectrum, SampledWavelengths, N};

pub(crate) mod box_filter;
pub(crate) mod gaussian;
pub(crate) mod tent;

// The `hdrfilm` plugin: its declaration and loader.
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Tag, Ty};

/// Largest image side accepted; beyond this a film is almost certainly a typo, and its buffers
/// would not fit in memory.
pub(crate) const MAX_RESOLUTION: i64 = 1 << 15;

/// Mitsuba's default image size, also used without a `<film>`.
const DEFAULT_SIZE: (i64, i64) = (768, 576);

declare!(PLUGIN: FilmSettings = Film "hdrfilm" ["ldrfilm"]
    "the image: XYZ accumulation developed to linear sRGB (EXR) or sRGB (PNG)"
    [&[
        Param::int("width", DEFAULT_SIZE.0)
            .check(Check::Range(1.0, MAX_RESOLUTION as f64))
            .unit("pixels")
            .doc("image width"),
        Param::int("height", DEFAULT_SIZE.1)
            .check(Check::Range(1.0, MAX_RESOLUTION as f64))
            .unit("pixels")
            .doc("image height"),
        Param::new("(nested)", Ty::Object(Tag::Rfilter), DefaultValue::Derived("`gaussian`"))
            .doc("the reconstruction filter: `box`, `tent` or `gaussian` (the last one given)"),
    ]] load);

/// What a `<film>` sets: the image size and the reconstruction filter.
#[derive(Clone, Debug)]
pub struct FilmSettings {
    pub width: u32,
    pub height: u32,
    pub filter: Filter,
}

impl Default for FilmSettings {
    /// Mitsuba's film without parameters.
    fn default() -> Self {
        FilmSettings {
            width: DEFAULT_SIZE.0 as u32,
            height: DEFAULT_SIZE.1 as u32,
            filter: Filter::gaussian(gaussian::DEFAULT_STDDEV),
        }
    }
}

fn load(a: &mut Args, _: ()) -> Result<FilmSettings, SceneError> {
    let mut film = FilmSettings {
        width: a.u32("width")?,
        height: a.u32("height")?,
        ..FilmSettings::default()
    };
    for f in a.children(Tag::Rfilter) {
        film.filter = crate::plugin::registry::rfilter(f, a.warnings())?;
    }
    Ok(film)
}

/// A separable pixel reconstruction filter.
#[derive(Clone, Debug)]
pub enum Filter {
    /// Uniform over the pixel (radius 0.5).
    Box,
    /// Triangle of the given radius (Mitsuba default 1).
    Tent { radius: f32 },
    /// Gaussian of standard deviation `stddev`, truncated at 4σ and shifted to reach zero there.
    Gaussian { stddev: f32, inv_cdf: Vec<f32> },
}

/// Entries of the Gaussian's inverse-CDF table (built in `gaussian.rs`).
const GAUSS_TABLE: usize = 1024;

impl Filter {
    /// Filter radius in pixels.
    pub fn radius(&self) -> f32 {
        match self {
            Filter::Box => 0.5,
            Filter::Tent { radius } => *radius,
            Filter::Gaussian { stddev, .. } => 4.0 * stddev,
        }
    }

    /// Samples a 1D offset from the filter's normalised profile.
    #[inline]
    fn sample_1d(&self, u: f32) -> f32 {
        self.sample_1d_lanes(u)
    }

    /// [`Filter::sample`]'s 1D offset on lanes.
    #[inline(always)]
    pub fn sample_1d_lanes<F: Float>(&self, u: F) -> F {
        let one = F::splat(1.0);
        let two = F::splat(2.0);
        match self {
            Filter::Box => u - F::splat(0.5),
            Filter::Tent { radius } => {
                // Inverse CDF of the triangle on [−r, r].
                let r = F::splat(*radius);
                let lo = r * ((two * u).sqrt() - one);
                let hi = r * (one - (two - two * u).max(F::splat(0.0)).sqrt());
                F::select(u.lt(F::splat(0.5)), lo, hi)
            }
            Filter::Gaussian { inv_cdf, .. } => {
                let x = u * F::splat(GAUSS_TABLE as f32);
                let last = F::I::splat(GAUSS_TABLE as i32 - 1);
                let i = x.to_int();
                let i = F::I::select(i.gt(last), last, i);
                let t = x - F::from_int(i);
                let a = F::gather(inv_cdf, i);
                let b = F::gather(inv_cdf, i + F::I::splat(1));
                a + t * (b - a)
            }
        }
    }

    /// Samples a 2D offset (pixels) from the separable filter.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Vec2 {
        Vec2::new(self.sample_1d(u.x), self.sample_1d(u.y))
    }
}

/// Converts a radiance sample at the path's wavelengths into CIE XYZ (Monte Carlo estimate of
/// ∫ L(λ) x̄(λ) dλ / ∫ ȳ, averaging the hero and secondary wavelengths).
#[inline]
pub(crate) fn spectrum_to_xyz(l: &SampledSpectrum, wl: &SampledWavelengths) -> [f32; 3] {
    spectrum_to_xyz_lanes(&l.0, &wl.lambda, &wl.pdf)
}

/// [`spectrum_to_xyz`] on lanes.
#[inline(always)]
pub fn spectrum_to_xyz_lanes<F: Float>(l: &[F; N], lambda: &[F; N], pdf: &[F; N]) -> [F; 3] {
    let zero = F::splat(0.0);
    let mut xyz = [zero; 3];
    for i in 0..N {
        let used = !pdf[i].le(zero);
        let b = cie::xyz_bar_lanes(lambda[i]);
        let w = l[i] / pdf[i];
        for (v, b) in xyz.iter_mut().zip(b) {
            *v = F::select(used, *v + b * w, *v);
        }
    }
    let s = F::splat(1.0 / (N as f32 * cie::CIE_Y_INTEGRAL));
    [xyz[0] * s, xyz[1] * s, xyz[2] * s]
}

/// Per-pixel sums of XYZ and sample weights, in f64 so that long renders lose nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    /// X, Y, Z, weight per pixel, row-major, top row first.
    pub pixels: Vec<[f64; 4]>,
    /// Names of the AOV channels (the `aov` integrator's), empty without one.
    pub aov_names: Vec<String>,
    /// Per-pixel sums of the AOV channels, `aov_names.len()` values per pixel, row-major; the
    /// sample count is the pixel's weight in `pixels`.
    pub aov: Vec<f64>,
    /// An adaptive render's allocation and progress ([`crate::render::adaptive`]); `None` for
    /// a uniform render.
    pub adaptive: Option<crate::render::adaptive::Adaptive>,
}

impl Film {
    /// An empty film.
    pub fn new(width: u32, height: u32) -> Film {
        Film {
            width,
            height,
            pixels: vec![[0.0; 4]; width as usize * height as usize],
            aov_names: Vec::new(),
            aov: Vec::new(),
            adaptive: None,
        }
    }

    /// An empty film with AOV channels.
    pub fn with_aovs(width: u32, height: u32, names: Vec<String>) -> Film {
        let mut f = Film::new(width, height);
        f.aov = vec![0.0; names.len() * f.pixels.len()];
        f.aov_names = names;
        f
    }

    /// The AOV channels averaged per pixel (0 where a pixel has no samples), one image per name.
    pub fn aov_images(&self) -> Vec<(String, Vec<f32>)> {
        let n = self.aov_names.len();
        self.aov_names
            .iter()
            .enumerate()
            .map(|(c, name)| {
                let data = self
                    .pixels
                    .iter()
                    .enumerate()
                    .map(|(i, p)| {
                        if p[3] > 0.0 {
                            (self.aov[i * n + c] / p[3]) as f32
                        } else {
                            0.0
                        }
                    })
                    .collect();
                (name.clone(), data)
            })
            .collect()
    }

    /// Adds one sample (XYZ already weighted) to pixel (x, y).
    #[inline]
    pub fn add(&mut self, x: u32, y: u32, xyz: [f32; 3]) {
        let p = &mut self.pixels[y as usize * self.width as usize + x as usize];
        p[0] += xyz[0] as f64;
        p[1] += xyz[1] as f64;
        p[2] += xyz[2] as f64;
        p[3] += 1.0;
    }

    /// Adds another film's sums (same size) — used to merge independent renders. The result
    /// is a finished image, not a render to continue: an adaptive render's state is dropped.
    pub fn merge(&mut self, other: &Film) {
        self.adaptive = None;
        for (a, b) in self.pixels.iter_mut().zip(&other.pixels) {
            for c in 0..4 {
                a[c] += b[c];
            }
        }
        for (a, b) in self.aov.iter_mut().zip(&other.aov) {
            *a += b;
        }
    }

    /// Total number of samples taken.
    pub fn total_weight(&self) -> f64 {
        self.pixels.iter().map(|p| p[3]).sum()
    }

    /// The developed image in linear sRGB (D65), row-major; unsampled pixels are black.
    pub fn to_linear_srgb(&self) -> Vec<[f32; 3]> {
        self.pixels
            .iter()
            .map(|p| {
                if p[3] <= 0.0 {
                    return [0.0; 3];
                }
                let xyz = [
                    (p[0] / p[3]) as f32,
                    (p[1] / p[3]) as f32,
                    (p[2] / p[3]) as f32,
                ];
                cie::xyz_to_linear_srgb(xyz)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;

    #[test]
    fn filter_samples_stay_within_radius_and_are_centred() {
        let filters = [
            Filter::Box,
            Filter::Tent { radius: 1.0 },
            Filter::gaussian(0.5),
        ];
        let mut rng = Pcg32::new(11, 0);
        for f in &filters {
            let n = 50_000;
            let mut sum = 0.0f64;
            let mut sum2 = 0.0f64;
            for _ in 0..n {
                let o = f.sample(rng.next_vec2());
                assert!(o.x.abs() <= f.radius() + 1e-4 && o.y.abs() <= f.radius() + 1e-4);
                sum += o.x as f64;
                sum2 += (o.x * o.x) as f64;
            }
            let mean = sum / n as f64;
            let var = sum2 / n as f64 - mean * mean;
            assert!(
                mean.abs() < 4.0 * (var / n as f64).sqrt(),
                "{f:?} mean {mean}"
            );
        }
    }

    #[test]
    fn tent_variance_matches_theory() {
        // Var of a triangle on [−r, r] is r²/6.
        let f = Filter::Tent { radius: 1.0 };
        let mut rng = Pcg32::new(2, 0);
        let n = 100_000;
        let v: f64 = (0..n)
            .map(|_| (f.sample(rng.next_vec2()).x as f64).powi(2))
            .sum::<f64>()
            / n as f64;
        // σ of the sample variance ≈ sqrt((μ4 − σ⁴)/n); μ4 = r⁴/15 for the triangle.
        let sd = ((1.0 / 15.0 - 1.0 / 36.0) / n as f64).sqrt();
        assert!((v - 1.0 / 6.0).abs() < 4.0 * sd, "{v}");
    }
}
