//! Image-based environment light (Mitsuba `envmap`): radiance at infinity from a
//! latitude–longitude (equirectangular) image, importance-sampled by a piecewise-constant 2D
//! distribution over the texels (Pharr, Jakob & Humphreys, "Physically Based Rendering", 3rd ed.,
//! §14.2.4).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `filename` | string | required | — | OpenEXR, Radiance HDR, PNG or JPEG image of linear RGB radiance |
//! | `scale` | float | 1.0 | — | multiplies every texel; non-negative |
//! | `to_world` | transform | — | — | rotation from the map's frame to the world |
//!
//! Mapping (Mitsuba 3's convention, y up): a unit direction d in the map's frame has
//! u = atan2(d.x, −d.z) / 2π (mod 1) and v = acos(d.y) / π, with (u, v) = (0, 0) at the left of
//! the top row; conversely d = (sin φ sin θ, cos θ, −cos φ sin θ) with φ = 2πu, θ = πv. So the top
//! row is the +y pole, the left edge and the centre column face −z and +z, and a quarter of the
//! width in faces +x.
//!
//! Each texel's RGB is uplifted as an emission (Jakob & Hanika 2019 sigmoid times D65, the same
//! semantics as [`Spectrum::rgb_illuminant`]). Radiance is interpolated bilinearly between texel
//! centres, as in Mitsuba 3 (3.9, measured through its Python API): texel (i, j) sits at
//! u = (i + ½)/W, wrapping around, and at v = j/(H − 1), so the first and last rows lie on the
//! poles. Each texel's colour is stored as Mitsuba stores it, a scale 2·max(r, g, b) and the
//! sigmoid spectrum of the colour divided by it; the four texels' spectra and their scales are
//! blended separately and multiplied, as Mitsuba 3.9 does (measured through its Python API:
//! halfway between a texel and a black one, a quarter of the texel's radiance). Blending the
//! radiance itself would be the linear choice; the two agree between texels of one hue and one
//! brightness, differ by ~10 % across a horizon, and an isolated bright texel among black ones
//! (a sun) emits 4/9 of what linear blending would give it.
//!
//! Sampling: a piecewise-constant density over the bilinear patches — W cells between texel
//! centres in u (the grid shifted by half a texel) and H − 1 cells between rows in v. A cell's
//! weight is the mean of its bilinear luminance (the mean of its four corners) times sin θ at
//! its centre. A patch's corners are the only texels its radiance reads, so the density is
//! positive wherever the radiance is: light sampling alone is unbiased. The solid-angle pdf is
//! p(u, v) / (2π² sin θ). Mitsuba samples the bilinear luminance itself; the two densities
//! differ only within cells (noise, not the mean).
//!
//! Known limits: `to_world` should be a rotation (scale or shear would change the density
//! without being accounted for).

use super::distribution::Distribution2D;
use super::infinite::{latlong_pdf, InfiniteLight};
use super::Light;
use crate::image_io::{read_image, RgbImage};
use crate::math::{Transform, Vec2, Vec3, PI};
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Ty};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

declare!(PLUGIN: Vec<Light>, Option<u32> = Emitter "envmap" []
    "environment light from a latitude–longitude image"
    [&[
        Param::new("filename", Ty::String, DefaultValue::Required)
            .doc("OpenEXR, Radiance HDR, PNG or JPEG image of linear RGB radiance"),
        Param::float("scale", 1.0)
            .check(Check::NonNegative)
            .doc("multiplies every texel"),
        Param::new("to_world", Ty::Transform, DefaultValue::None)
            .doc("rotation from the map's frame to the world"),
    ]] load);

fn load(a: &mut Args, _: Option<u32>) -> Result<Vec<Light>, SceneError> {
    let path = a
        .path("filename")?
        .ok_or_else(|| a.error("filename", "is required"))?;
    let image = read_image(&path).map_err(|e| a.error("filename", e))?;
    let scale = a.float("scale")?;
    let to_world = a.transform("to_world")?;
    let light = EnvMapLight::new(image, scale, to_world).map_err(|e| a.error("filename", e))?;
    Ok(vec![Light::EnvMap(light.into())])
}

/// Why an environment map cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum EnvMapError {
    #[error("environment map is empty ({width} × {height})")]
    Empty { width: usize, height: usize },
    #[error("environment map has {got} texels, expected {width} × {height}")]
    SizeMismatch {
        width: usize,
        height: usize,
        got: usize,
    },
}

/// An importance-sampled lat–long environment map.
#[derive(Clone, Debug)]
pub struct EnvMapLight {
    width: usize,
    height: usize,
    /// Per-texel emitted spectrum (before `scale`).
    texels: Vec<Spectrum>,
    dist: Distribution2D,
    scale: f32,
    to_world: Transform,
    to_local: Transform,
    /// ∫ luminance dω over the sphere (times `scale`), for the power estimate.
    luminance_integral: f32,
}

/// Rec. 709 luminance of linear sRGB.
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Direction in the map's frame → (u, v) ∈ [0, 1]².
pub(crate) fn direction_to_uv(d: Vec3) -> Vec2 {
    let mut u = d.x.atan2(-d.z) * (0.5 / PI);
    if u < 0.0 {
        u += 1.0;
    }
    Vec2::new(u.min(1.0), crate::math::safe_acos(d.y) / PI)
}

/// (u, v) → unit direction in the map's frame.
pub(crate) fn uv_to_direction(uv: Vec2) -> Vec3 {
    let (sin_phi, cos_phi) = (2.0 * PI * uv.x).sin_cos();
    let (sin_theta, cos_theta) = (PI * uv.y).sin_cos();
    Vec3::new(sin_phi * sin_theta, cos_theta, -cos_phi * sin_theta)
}

impl EnvMapLight {
    /// An environment light from a linear-RGB lat–long image; texels are uplifted to spectra.
    pub fn new(
        image: RgbImage,
        scale: f32,
        to_world: Transform,
    ) -> Result<EnvMapLight, EnvMapError> {
        Self::check(image.width, image.height, image.data.len())?;
        let clean = |c: [f32; 3]| c.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
        let weights: Vec<f32> = image.data.iter().map(|&c| luminance(clean(c))).collect();
        let texels = image
            .data
            .iter()
            .map(|&c| Spectrum::rgb_illuminant(clean(c)))
            .collect();
        Ok(Self::from_texels(
            image.width,
            image.height,
            texels,
            &weights,
            scale,
            to_world,
        ))
    }

    fn check(width: usize, height: usize, got: usize) -> Result<(), EnvMapError> {
        if width == 0 || height == 0 {
            return Err(EnvMapError::Empty { width, height });
        }
        if got != width * height {
            return Err(EnvMapError::SizeMismatch { width, height, got });
        }
        Ok(())
    }

    /// Builds from per-texel spectra and their sampling weights (luminance), row-major, top row
    /// first.
    fn from_texels(
        width: usize,
        height: usize,
        texels: Vec<Spectrum>,
        luminance: &[f32],
        scale: f32,
        to_world: Transform,
    ) -> EnvMapLight {
        let scale = if scale.is_finite() {
            scale.max(0.0)
        } else {
            0.0
        };
        // Sampling cells: between texel centres in u (W cells, wrapping), between rows in v
        // (H − 1 cells; one when the map has a single row). See the module header.
        let rows = (height - 1).max(1);
        let mut weights = vec![0.0; width * rows];
        let mut integral = 0.0f64;
        let d_phi = 2.0 * std::f64::consts::PI / width as f64;
        let lum = |x: usize, y: usize| luminance[y.min(height - 1) * width + x % width] as f64;
        for y in 0..rows {
            let t0 = std::f64::consts::PI * y as f64 / rows as f64;
            let t1 = std::f64::consts::PI * (y + 1) as f64 / rows as f64;
            let sin_theta = (0.5 * (t0 + t1)).sin();
            let solid_angle = d_phi * (t0.cos() - t1.cos());
            let below = if height > 1 { y + 1 } else { y };
            for x in 0..width {
                // The mean of a bilinear patch is the mean of its corners.
                let mean = 0.25 * (lum(x, y) + lum(x + 1, y) + lum(x, below) + lum(x + 1, below));
                weights[y * width + x] = (mean * sin_theta) as f32;
                integral += mean * solid_angle;
            }
        }
        EnvMapLight {
            width,
            height,
            texels,
            dist: Distribution2D::new(&weights, width, rows),
            scale,
            to_world,
            to_local: to_world.inverse(),
            luminance_integral: (integral * scale as f64) as f32,
        }
    }

    /// Half a texel in u: the sampling grid's offset from the texel grid.
    #[inline]
    fn half_texel(&self) -> f32 {
        0.5 / self.width as f32
    }

    fn local(&self, dir: Vec3) -> Vec3 {
        self.to_local.vector(dir).normalize_or_zero()
    }

    /// Bilinear interpolation between texel centres: (i + ½)/W in u, wrapping; j/(H − 1) in v.
    /// As in Mitsuba, an uplifted texel's normalised spectrum and its scale are interpolated
    /// separately and then multiplied (see the module header).
    fn radiance_uv(&self, uv: Vec2, wl: &SampledWavelengths) -> SampledSpectrum {
        let (w, h) = (self.width as isize, self.height as isize);
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y.clamp(0.0, 1.0) * (self.height - 1) as f32;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as isize, y0 as isize);
        let mut shape = SampledSpectrum::ZERO;
        let mut scale = 0.0f32;
        for (i, j, weight) in [
            (x0, y0, (1.0 - fx) * (1.0 - fy)),
            (x0 + 1, y0, fx * (1.0 - fy)),
            (x0, y0 + 1, (1.0 - fx) * fy),
            (x0 + 1, y0 + 1, fx * fy),
        ] {
            if weight == 0.0 {
                continue;
            }
            let texel =
                &self.texels[j.clamp(0, h - 1) as usize * self.width + i.rem_euclid(w) as usize];
            let (s, f) = match texel {
                Spectrum::RgbIlluminant { scale, poly } => (
                    SampledSpectrum::from_fn(|k| poly.eval(wl.lambda[k]) * wl.d65[k]),
                    *scale,
                ),
                other => (other.sample(wl), 1.0),
            };
            shape += s * weight;
            scale += f * weight;
        }
        shape * (scale * self.scale)
    }
}

impl InfiniteLight for EnvMapLight {
    fn sample_wi(&self, _: Vec3, u: Vec2) -> Option<Vec3> {
        let (cell, _, _) = self.dist.sample(u);
        let uv = Vec2::new((cell.x + self.half_texel()).rem_euclid(1.0), cell.y);
        Some(
            self.to_world
                .vector(uv_to_direction(uv))
                .normalize_or_zero(),
        )
    }

    fn pdf_li(&self, _: Vec3, wi: Vec3) -> f32 {
        latlong_pdf(self.local(wi), |uv| {
            let u = (uv.x - self.half_texel())
                .rem_euclid(1.0)
                .min(crate::math::ONE_MINUS_EPSILON);
            self.dist.pdf(Vec2::new(u, uv.y))
        })
    }

    fn le(&self, dir: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        let d = self.local(dir);
        if d == Vec3::ZERO {
            return SampledSpectrum::ZERO;
        }
        self.radiance_uv(direction_to_uv(d), wl)
    }

    /// Power falling on the scene's bounding sphere: π r² ∫ luminance dω.
    fn power(&self, r: f32) -> f32 {
        PI * r * r * self.luminance_integral
    }
}

#[cfg(test)]
mod tests;
