//! JPEG reading through `zune-jpeg` (pure Rust, maintained, the decoder the `image` crate
//! uses; `jpeg-decoder` is in maintenance mode). Baseline and progressive JPEG, greyscale, YCbCr
//! and CMYK/YCCK are decoded to 8-bit RGB, then from sRGB to linear, like PNG. EXIF
//! orientation and ICC profiles are ignored (as Mitsuba does).

use super::{check_size, srgb_to_linear, ImageError, RgbImage};
use std::path::Path;
use zune_jpeg::zune_core::bytestream::ZCursor;
use zune_jpeg::zune_core::colorspace::ColorSpace;
use zune_jpeg::zune_core::options::DecoderOptions;
use zune_jpeg::JpegDecoder;

/// The start-of-image marker and the first byte of the next marker.
pub(super) const JPEG_MAGIC: [u8; 3] = [0xFF, 0xD8, 0xFF];

pub(super) fn read_jpeg_bytes(path: &Path, bytes: &[u8]) -> Result<RgbImage, ImageError> {
    let malformed = |what: String| ImageError::Malformed {
        path: path.to_path_buf(),
        format: "JPEG",
        what,
    };
    let options = DecoderOptions::default()
        .jpeg_set_out_colorspace(ColorSpace::RGB)
        .set_max_width(1 << 16)
        .set_max_height(1 << 16);
    let mut decoder = JpegDecoder::new_with_options(ZCursor::new(bytes), options);
    decoder
        .decode_headers()
        .map_err(|e| malformed(e.to_string()))?;
    let info = decoder
        .info()
        .ok_or_else(|| malformed("no image header".into()))?;
    let (w, h) = (info.width as usize, info.height as usize);
    check_size(path, w, h)?;
    let pixels = decoder.decode().map_err(|e| malformed(e.to_string()))?;
    if pixels.len() < w * h * 3 {
        return Err(ImageError::Truncated {
            path: path.to_path_buf(),
            format: "JPEG",
            what: format!("{} bytes of pixels for {w} × {h}", pixels.len()),
        });
    }
    let lut: Vec<f32> = (0..256).map(|i| srgb_to_linear(i as f32 / 255.0)).collect();
    Ok(RgbImage {
        width: w,
        height: h,
        data: pixels
            .chunks_exact(3)
            .take(w * h)
            .map(|p| [lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]])
            .collect(),
    })
}
