//! `checkerboard`: Mitsuba's checkerboard texture — the unit UV square split 2×2, `color0` on
//! two opposite squares and `color1` on the others, repeating (after `to_uv`).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `color0` | spectrum | 0.4 | — | colour of one set of squares |
//! | `color1` | spectrum | 0.2 | — | colour of the other |
//! | `to_uv` | transform | identity | — | applied to the surface UV first |
//!
//! As a float texture it reads each colour's largest value. Known limits: no filtering (the
//! edges alias at a distance).

use super::{uv_transform, FloatTexture, SpectrumTexture, Texture, Want};
use crate::math::{Mat3, Vec2};
use crate::plugin::{declare, Args, DefaultValue, Param, SceneError, SpectrumKind, Ty};

declare!(PLUGIN: Texture, Want = Texture "checkerboard" []
    "two colours in a checkerboard over UV"
    [&[
            Param::colour("color0", 0.4)
            .doc("colour of one set of squares"),
            Param::colour("color1", 0.2)
            .doc("colour of the other"),
            Param::new("to_uv", Ty::Transform, DefaultValue::Derived("identity"))
                .doc("applied to the surface UV first"),
        ]] load);

/// Whether `uv` falls on a `color0` square.
#[inline]
pub(crate) fn is_color0(to_uv: Mat3, uv: Vec2) -> bool {
    let t = to_uv.transform_point2(uv);
    let fx = t.x - t.x.floor();
    let fy = t.y - t.y.floor();
    (fx > 0.5) == (fy > 0.5)
}

fn load(a: &mut Args, want: Want) -> Result<Texture, SceneError> {
    let to_uv = uv_transform(&a.transform("to_uv")?);
    Ok(match want {
        Want::Spectrum(kind) => Texture::Spectrum(SpectrumTexture::Checkerboard {
            color0: a.spectrum_as("color0", kind)?,
            color1: a.spectrum_as("color1", kind)?,
            to_uv,
        }),
        Want::Float => Texture::Float(FloatTexture::Checkerboard {
            color0: a
                .spectrum_as("color0", SpectrumKind::Unbounded)?
                .max_value(),
            color1: a
                .spectrum_as("color1", SpectrumKind::Unbounded)?
                .max_value(),
            to_uv,
        }),
        Want::Normals => {
            return Err(SceneError::at(
                &a.node().loc,
                "a checkerboard cannot supply normals (use a 'bitmap' or a 'scales' texture)",
            ))
        }
    })
}
