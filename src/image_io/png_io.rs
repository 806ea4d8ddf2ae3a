//! PNG reading (8/16-bit, grey/RGB/RGBA/palette, sRGB-decoded to linear) and writing (8-bit
//! sRGB), through the `png` crate.

use super::{
    check_size, check_writable, linear_to_srgb, srgb_to_linear, write_atomically, ImageError,
    RgbImage, MAX_PIXELS,
};
use std::io::Cursor;
use std::path::Path;

fn png_error(path: &Path, e: png::DecodingError) -> ImageError {
    let path = path.to_path_buf();
    let format = "PNG";
    match e {
        png::DecodingError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            ImageError::Truncated {
                path,
                format,
                what: io.to_string(),
            }
        }
        png::DecodingError::IoError(source) => ImageError::Io { path, source },
        png::DecodingError::LimitsExceeded => ImageError::Unsupported {
            path,
            format,
            what: "decoder memory limit exceeded".into(),
        },
        other => ImageError::Malformed {
            path,
            format,
            what: other.to_string(),
        },
    }
}

pub(super) fn read_png_bytes(path: &Path, bytes: &[u8]) -> Result<RgbImage, ImageError> {
    let mut decoder = png::Decoder::new_with_limits(
        Cursor::new(bytes),
        png::Limits {
            bytes: MAX_PIXELS * 8,
        },
    );
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(|e| png_error(path, e))?;
    let (w, h) = (reader.info().width as usize, reader.info().height as usize);
    check_size(path, w, h)?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| ImageError::TooLarge {
            path: path.to_path_buf(),
            width: w,
            height: h,
        })?;
    let mut buf = vec![0u8; size];
    let info = reader
        .next_frame(&mut buf)
        .map_err(|e| png_error(path, e))?;
    let channels = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => {
            return Err(ImageError::Unsupported {
                path: path.to_path_buf(),
                format: "PNG",
                what: "palette was not expanded".into(),
            })
        }
    };
    let sixteen = info.bit_depth == png::BitDepth::Sixteen;
    let lut: Vec<f32> = (0..256).map(|i| srgb_to_linear(i as f32 / 255.0)).collect();
    let sample = |row: &[u8], i: usize| -> f32 {
        if sixteen {
            srgb_to_linear(u16::from_be_bytes([row[2 * i], row[2 * i + 1]]) as f32 / 65535.0)
        } else {
            lut[row[i] as usize]
        }
    };
    let mut out = RgbImage::new(w, h);
    for y in 0..h {
        let row = &buf[y * info.line_size..(y + 1) * info.line_size];
        for x in 0..w {
            let base = x * channels;
            out.data[y * w + x] = if channels < 3 {
                [sample(row, base); 3]
            } else {
                [
                    sample(row, base),
                    sample(row, base + 1),
                    sample(row, base + 2),
                ]
            };
        }
    }
    Ok(out)
}

/// Writes to a temporary file beside `path`, then renames it over `path`, so that readers never
/// see a half-written image.
/// Writes an 8-bit sRGB-encoded PNG (linear values clamped to [0, 1], then encoded and rounded).
pub fn write_png(path: impl AsRef<Path>, image: &RgbImage) -> Result<(), ImageError> {
    let path = path.as_ref();
    check_writable(path, image)?;
    let (w, h) = (image.width as u32, image.height as u32);
    let bytes: Vec<u8> = image
        .data
        .iter()
        .flat_map(|px| px.map(|v| (linear_to_srgb(v) * 255.0).round() as u8))
        .collect();
    write_atomically(path, |tmp| {
        let file = std::fs::File::create(tmp).map_err(|e| e.to_string())?;
        let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = enc.write_header().map_err(|e| e.to_string())?;
        writer.write_image_data(&bytes).map_err(|e| e.to_string())?;
        writer.finish().map_err(|e| e.to_string())
    })
}
