//! Textures: spatially varying spectra and scalars looked up by surface UV.

use crate::math::{Mat3, Vec2, Vec3};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use std::sync::Arc;

pub mod bitmap;
pub mod head_shields;
pub mod per_scale;
pub mod scales;

pub use bitmap::Bitmap;
pub use per_scale::PerScale;
pub use scales::{Layout, Scales};

/// Where a texture is looked up.
#[derive(Clone, Copy, Debug, Default)]
pub struct TexCoord {
    pub uv: Vec2,
    pub p: Vec3,
}

/// A spectrum-valued texture.
#[derive(Clone, Debug)]
pub enum SpectrumTexture {
    /// The same spectrum everywhere.
    Constant(Spectrum),
    /// Mitsuba's `checkerboard`: `color0` on even squares of the unit UV square split 2×2.
    Checkerboard {
        color0: Spectrum,
        color1: Spectrum,
        to_uv: Mat3,
    },
    /// `bitmap`: an image.
    Bitmap(Arc<Bitmap>),
    /// `scales` read as a colour: `color0` on the scales, `color1` in the grooves.
    Scales {
        cells: Arc<Scales>,
        color0: Spectrum,
        color1: Spectrum,
    },
}

impl SpectrumTexture {
    /// A constant texture.
    pub fn constant(s: Spectrum) -> Self {
        SpectrumTexture::Constant(s)
    }

    /// Values at the path's wavelengths.
    #[inline]
    pub fn eval(&self, tc: &TexCoord, wl: &SampledWavelengths) -> SampledSpectrum {
        match self {
            SpectrumTexture::Constant(s) => s.sample(wl),
            SpectrumTexture::Checkerboard {
                color0,
                color1,
                to_uv,
            } => {
                if checker(*to_uv, tc.uv) {
                    color0.sample(wl)
                } else {
                    color1.sample(wl)
                }
            }
            SpectrumTexture::Bitmap(b) => b.spectrum(tc.uv, wl),
            SpectrumTexture::Scales {
                cells,
                color0,
                color1,
            } => {
                let m = cells.sample(tc.uv).groove;
                color0.sample(wl) * (1.0 - m) + color1.sample(wl) * m
            }
        }
    }

    /// Largest value anywhere (for bounds and power estimates).
    pub fn max_value(&self) -> f32 {
        match self {
            SpectrumTexture::Constant(s) => s.max_value(),
            SpectrumTexture::Bitmap(b) => b.max_value(),
            SpectrumTexture::Checkerboard { color0, color1, .. }
            | SpectrumTexture::Scales { color0, color1, .. } => {
                color0.max_value().max(color1.max_value())
            }
        }
    }
}

/// A scalar texture.
#[derive(Clone, Debug)]
pub enum FloatTexture {
    /// The same value everywhere.
    Constant(f32),
    /// Mitsuba's `checkerboard` read as a float.
    Checkerboard {
        color0: f32,
        color1: f32,
        to_uv: Mat3,
    },
    /// `bitmap` read as a float (mean of the channels).
    Bitmap(Arc<Bitmap>),
    /// `scales` read as a float: the height of the relief in [0, 1].
    Scales(Arc<Scales>),
    /// `per_scale`: a value per scale.
    PerScale(PerScale),
}

impl FloatTexture {
    /// Value at a point.
    #[inline]
    pub fn eval(&self, tc: &TexCoord) -> f32 {
        match self {
            FloatTexture::Constant(v) => *v,
            FloatTexture::Checkerboard {
                color0,
                color1,
                to_uv,
            } => {
                if checker(*to_uv, tc.uv) {
                    *color0
                } else {
                    *color1
                }
            }
            FloatTexture::Bitmap(b) => b.value(tc.uv),
            FloatTexture::Scales(s) => s.height(tc.uv, 0.0),
            FloatTexture::PerScale(p) => p.eval(tc.uv),
        }
    }

    /// Value seen through a footprint `footprint` UV units wide along u and v (detail finer
    /// than that fades).
    pub fn eval_filtered(&self, tc: &TexCoord, footprint: Vec2) -> f32 {
        match self {
            FloatTexture::Scales(s) => s.height(tc.uv, s.cells_across(footprint)),
            _ => self.eval(tc),
        }
    }

    /// Gradient with respect to (u, v), for bump mapping. Piecewise-constant textures
    /// (checkerboard, per-scale values) have none.
    pub fn gradient(&self, tc: &TexCoord, footprint: Vec2) -> Vec2 {
        match self {
            FloatTexture::Scales(s) => s.gradient(tc.uv, s.cells_across(footprint)),
            FloatTexture::Bitmap(b) => {
                // Central differences over one texel.
                let (du, dv) = (1.0 / b.width as f32, 1.0 / b.height as f32);
                let f = |d: Vec2| b.value(tc.uv + d);
                Vec2::new(
                    (f(Vec2::new(du, 0.0)) - f(Vec2::new(-du, 0.0))) / (2.0 * du),
                    (f(Vec2::new(0.0, dv)) - f(Vec2::new(0.0, -dv))) / (2.0 * dv),
                )
            }
            _ => Vec2::ZERO,
        }
    }

    /// The cell pattern behind this texture, if it has one (for per-scale normal tilts).
    pub fn cells(&self) -> Option<&Scales> {
        match self {
            FloatTexture::Scales(s) => Some(s),
            FloatTexture::PerScale(p) => Some(&p.cells),
            _ => None,
        }
    }
}

#[inline]
fn checker(to_uv: Mat3, uv: Vec2) -> bool {
    let t = to_uv.transform_point2(uv);
    let fx = t.x - t.x.floor();
    let fy = t.y - t.y.floor();
    (fx > 0.5) == (fy > 0.5)
}
