//! `bitmap`: an image texture (Mitsuba's `bitmap` plugin).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `filename` | string | required | — | the image (PNG and JPEG are sRGB-decoded) |
//! | `raw` | boolean | false | — | keep the stored values: no sRGB decoding, no uplift clamp (normal maps, data) |
//! | `filter_type` | string | `bilinear` | — | texel interpolation; one of 'bilinear', 'nearest' |
//! | `wrap_mode` | string | `repeat` | — | lookups outside [0, 1); one of 'repeat', 'mirror', 'clamp' |
//! | `to_uv` | transform | identity | — | applied to the surface UV before the lookup |
//!
//! UV convention (Mitsuba 3): u runs left to right and v top to bottom over the image, so
//! (0, 0) is the top-left texel corner; OBJ texture coordinates are flipped on load
//! (`flip_tex_coords`) to match, PLY and serialized ones are used as stored (as in Mitsuba 3).
//! Colours are linear sRGB; as a spectrum each texel is uplifted
//! once at load (Jakob & Hanika 2019) and the four neighbours' spectra are blended, which is
//! the same as blending reflectances. As a float texture the texture reads the mean of the
//! three channels. Known limits: no MIP-mapping (distant textures alias), no alpha.

use super::{uv_transform, FloatTexture, NormalSource, SpectrumTexture, Texture, Want};
use crate::image_io::{read_image, RgbImage};
use crate::math::{Mat3, Vec2};
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Ty};
use crate::spectrum::rgb2spec::{rgb_to_sigmoid, SigmoidPolynomial};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use std::sync::Arc;

declare!(PLUGIN: Texture, Want = Texture "bitmap" []
    "an image: EXR, Radiance HDR, PNG or JPEG"
    [&[
            Param::new("filename", Ty::String, DefaultValue::Required)
                .doc("the image (PNG and JPEG are sRGB-decoded)"),
            Param::bool("raw", false).doc(
                "keep the stored values: no sRGB decoding, no uplift clamp (normal maps, data)",
            ),
            Param::string("filter_type", "bilinear")
                .check(Check::OneOf(&["bilinear", "nearest"]))
                .doc("texel interpolation"),
            Param::string("wrap_mode", "repeat")
                .check(Check::OneOf(&["repeat", "mirror", "clamp"]))
                .doc("lookups outside [0, 1)"),
            Param::new("to_uv", Ty::Transform, DefaultValue::Derived("identity"))
                .doc("applied to the surface UV before the lookup"),
        ]] load);

fn load(a: &mut Args, want: Want) -> Result<Texture, SceneError> {
    let path = a
        .path("filename")?
        .ok_or_else(|| a.error("filename", "missing"))?;
    let mut image = read_image(&path).map_err(|e| a.error("filename", format!("bitmap: {e}")))?;
    let raw = a.bool("raw")?;
    let is_8bit = path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        ["png", "jpg", "jpeg"]
            .iter()
            .any(|x| e.eq_ignore_ascii_case(x))
    });
    if raw && is_8bit {
        // PNG and JPEG are read as sRGB-encoded colour; raw data (normal maps) keeps the
        // stored values.
        for c in &mut image.data {
            *c = c.map(crate::spectrum::cie::srgb_encode);
        }
    }
    let bilinear = a.string("filter_type")? == "bilinear";
    let wrap = match a.string("wrap_mode")?.as_str() {
        "mirror" => Wrap::Mirror,
        "clamp" => Wrap::Clamp,
        _ => Wrap::Repeat,
    };
    let b = Arc::new(Bitmap::new(
        image,
        bilinear,
        wrap,
        uv_transform(&a.transform("to_uv")?),
    ));
    Ok(match want {
        Want::Spectrum(_) => Texture::Spectrum(SpectrumTexture::Bitmap(b)),
        Want::Float => Texture::Float(FloatTexture::Bitmap(b)),
        Want::Normals => Texture::Normals(NormalSource::Bitmap(b)),
    })
}

/// How lookups outside [0, 1) are folded back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    Repeat,
    Mirror,
    Clamp,
}

/// An image ready for lookups.
#[derive(Clone, Debug)]
pub struct Bitmap {
    pub width: usize,
    pub height: usize,
    /// Linear RGB per texel, row-major, top row first.
    pub rgb: Vec<[f32; 3]>,
    /// Per texel: reflectance spectrum (for colour lookups).
    spectra: Vec<SigmoidPolynomial>,
    pub bilinear: bool,
    pub wrap: Wrap,
    pub to_uv: Mat3,
}

impl Bitmap {
    /// A texture from an image (already linear).
    pub fn new(image: RgbImage, bilinear: bool, wrap: Wrap, to_uv: Mat3) -> Bitmap {
        let spectra = image
            .data
            .iter()
            .map(|c| rgb_to_sigmoid(c.map(|v| v.clamp(0.0, 1.0))))
            .collect();
        Bitmap {
            width: image.width,
            height: image.height,
            rgb: image.data,
            spectra,
            bilinear,
            wrap,
            to_uv,
        }
    }

    fn wrap_index(&self, i: i64, n: usize) -> usize {
        let n = n as i64;
        let j = match self.wrap {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m < n {
                    m
                } else {
                    2 * n - 1 - m
                }
            }
        };
        j as usize
    }

    /// The (texel index, weight) pairs a lookup at `uv` blends.
    fn taps(&self, uv: Vec2) -> [(usize, f32); 4] {
        let t = self.to_uv.transform_point2(uv);
        let x = t.x * self.width as f32;
        let y = t.y * self.height as f32;
        if !self.bilinear || !x.is_finite() || !y.is_finite() {
            let (xi, yi) = (
                if x.is_finite() { x.floor() as i64 } else { 0 },
                if y.is_finite() { y.floor() as i64 } else { 0 },
            );
            let k = self.wrap_index(yi, self.height) * self.width + self.wrap_index(xi, self.width);
            return [(k, 1.0), (k, 0.0), (k, 0.0), (k, 0.0)];
        }
        // Texel centres sit at half-integers.
        let (fx, fy) = (x - 0.5, y - 0.5);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (ax, ay) = (fx - x0, fy - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let idx = |xx: i64, yy: i64| {
            self.wrap_index(yy, self.height) * self.width + self.wrap_index(xx, self.width)
        };
        [
            (idx(x0, y0), (1.0 - ax) * (1.0 - ay)),
            (idx(x0 + 1, y0), ax * (1.0 - ay)),
            (idx(x0, y0 + 1), (1.0 - ax) * ay),
            (idx(x0 + 1, y0 + 1), ax * ay),
        ]
    }

    /// Linear RGB at `uv`.
    pub fn rgb(&self, uv: Vec2) -> [f32; 3] {
        let mut c = [0.0f32; 3];
        for (k, w) in self.taps(uv) {
            if w != 0.0 {
                for (ci, v) in c.iter_mut().zip(self.rgb[k]) {
                    *ci += w * v;
                }
            }
        }
        c
    }

    /// Reflectance spectrum at `uv` for the path's wavelengths.
    pub fn spectrum(&self, uv: Vec2, wl: &SampledWavelengths) -> SampledSpectrum {
        let mut s = SampledSpectrum::ZERO;
        for (k, w) in self.taps(uv) {
            if w != 0.0 {
                let p = &self.spectra[k];
                s += SampledSpectrum::from_fn(|i| p.eval(wl.lambda[i])) * w;
            }
        }
        s
    }

    /// Mean of the channels at `uv` (float lookups: roughness, height).
    pub fn value(&self, uv: Vec2) -> f32 {
        let c = self.rgb(uv);
        (c[0] + c[1] + c[2]) / 3.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image() -> RgbImage {
        // 2×2: top row red, green; bottom row blue, white.
        RgbImage {
            width: 2,
            height: 2,
            data: vec![
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
            ],
        }
    }

    #[test]
    fn texel_centres_return_texels_and_v_runs_down() {
        let b = Bitmap::new(image(), true, Wrap::Repeat, Mat3::IDENTITY);
        assert_eq!(b.rgb(Vec2::new(0.25, 0.25)), [1.0, 0.0, 0.0]);
        assert_eq!(b.rgb(Vec2::new(0.75, 0.25)), [0.0, 1.0, 0.0]);
        assert_eq!(b.rgb(Vec2::new(0.25, 0.75)), [0.0, 0.0, 1.0]);
        // Halfway between the top two texels: their mean.
        let m = b.rgb(Vec2::new(0.5, 0.25));
        assert!((m[0] - 0.5).abs() < 1e-6 && (m[1] - 0.5).abs() < 1e-6 && m[2].abs() < 1e-6);
    }

    #[test]
    fn wrap_modes_fold_coordinates() {
        let r = Bitmap::new(image(), false, Wrap::Repeat, Mat3::IDENTITY);
        assert_eq!(r.rgb(Vec2::new(1.25, 0.25)), [1.0, 0.0, 0.0]);
        let c = Bitmap::new(image(), false, Wrap::Clamp, Mat3::IDENTITY);
        assert_eq!(c.rgb(Vec2::new(1.25, 0.25)), [0.0, 1.0, 0.0]);
        let m = Bitmap::new(image(), false, Wrap::Mirror, Mat3::IDENTITY);
        assert_eq!(m.rgb(Vec2::new(1.25, 0.25)), [0.0, 1.0, 0.0]);
        assert_eq!(m.rgb(Vec2::new(-0.25, 0.25)), [1.0, 0.0, 0.0]);
        // Non-finite coordinates never panic.
        let _ = r.rgb(Vec2::new(f32::NAN, f32::INFINITY));
    }

    #[test]
    fn spectra_are_the_uplifted_texels() {
        let b = Bitmap::new(image(), true, Wrap::Repeat, Mat3::IDENTITY);
        let wl = SampledWavelengths::fixed([450.0, 550.0, 610.0, 700.0]);
        let white = b.spectrum(Vec2::new(0.75, 0.75), &wl);
        assert!(white.0.iter().all(|&v| (v - 1.0).abs() < 1e-6), "{white:?}");
        let red = b.spectrum(Vec2::new(0.25, 0.25), &wl);
        assert!(red[3] > 0.8 && red[0] < 0.2, "{red:?}");
    }
}
