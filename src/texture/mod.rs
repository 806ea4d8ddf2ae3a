//! Textures: spatially varying spectra and scalars looked up by surface UV. A texture plugin
//! is asked for what its user needs ([`Want`]: a colour, a number or tangent-space normals) and
//! answers with a [`Texture`] of that kind.

use crate::math::{Mat3, Vec2, Vec3};
use crate::plugin::SpectrumKind;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use std::sync::Arc;

pub mod bitmap;
pub mod checkerboard;
pub(crate) mod head_shields;
pub mod per_scale;
pub mod scales;

pub(crate) use bitmap::Bitmap;
pub(crate) use per_scale::PerScale;
pub(crate) use scales::Scales;

/// What a texture is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Want {
    /// A colour, uplifted as this kind of spectrum.
    Spectrum(SpectrumKind),
    /// A number.
    Float,
    /// Tangent-space normals (for `normalmap`).
    Normals,
}

/// A texture of the kind asked for.
#[derive(Clone, Debug)]
pub enum Texture {
    Spectrum(SpectrumTexture),
    Float(FloatTexture),
    Normals(NormalSource),
}

/// Where a `normalmap` takes its tangent-space normals from.
#[derive(Clone, Debug)]
pub enum NormalSource {
    /// The slope of a `scales` relief.
    Scales(Arc<Scales>),
    /// An image (`bitmap`, usually with `raw="true"`): n = 2·rgb − 1.
    Bitmap(Arc<Bitmap>),
}

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
                if checkerboard::is_color0(*to_uv, tc.uv) {
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
                if checkerboard::is_color0(*to_uv, tc.uv) {
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

    /// Gradient with respect to (u, v), for bump mapping. Piecewise-constant textures
    /// (checkerboard, per-scale values) have none.
    pub(crate) fn gradient(&self, tc: &TexCoord, footprint: Vec2) -> Vec2 {
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

/// The 2D affine part of a `to_uv` transform, acting on (u, v, 1) as in Mitsuba.
pub(crate) fn uv_transform(t: &crate::math::Transform) -> Mat3 {
    let m = t.m;
    Mat3::from_cols(
        Vec3::new(m.x_axis.x, m.x_axis.y, 0.0),
        Vec3::new(m.y_axis.x, m.y_axis.y, 0.0),
        Vec3::new(m.w_axis.x, m.w_axis.y, 1.0),
    )
}
