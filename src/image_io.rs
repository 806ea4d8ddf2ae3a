//! Image reading and writing: OpenEXR (via the `exr` crate), Radiance HDR (RGBE, own reader:
//! `hdr.rs` says why), PNG (via the `png` crate) and, for reading only, JPEG (via `zune-jpeg`).
//!
//! Every image is held as linear RGB in `f32`, row-major with the top row first. Readers pick the
//! format from the file's magic bytes (`v/1\x01` OpenEXR, `#?` Radiance, `\x89PNG` PNG,
//! `FF D8 FF` JPEG); the
//! extension is only used to word the error when the magic matches nothing.
//!
//! Known limits:
//! - OpenEXR: the first layer, its largest resolution level; channels `R`,`G`,`B` (or a `Y`
//!   luminance channel, copied to all three), with or without a layer prefix; alpha and other
//!   channels are ignored; sub-sampled (chroma) channels and deep data are refused. The data
//!   window is read, the display window ignored.
//! - Radiance HDR: `FORMAT=32-bit_rle_rgbe` only (XYZE is refused), resolution lines `-Y h +X w`
//!   and `+Y h +X w`; `EXPOSURE` is ignored (as most renderers do).
//! - PNG: gAMA/iCCP chunks are ignored; 8- and 16-bit samples are always decoded with the sRGB
//!   transfer function. Alpha is dropped.
//! - JPEG: 8-bit, decoded with the sRGB transfer function; EXIF orientation and ICC profiles are
//!   ignored.
//! - Images of more than [`MAX_PIXELS`] pixels are refused before any pixel storage is allocated.

use std::path::{Path, PathBuf};

mod exr_io;
mod exr_order;
mod hdr;
mod jpeg_io;
mod png_io;

use self::exr_io::read_exr_bytes;
pub use self::exr_io::{read_exr_channel_names, read_exr_metadata, write_exr, write_exr_channels};
use self::png_io::read_png_bytes;
pub use self::png_io::write_png;

/// Largest accepted image, in pixels (2^28, i.e. 16384 × 16384).
pub const MAX_PIXELS: usize = 1 << 28;

/// A linear RGB image, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    pub width: usize,
    pub height: usize,
    pub data: Vec<[f32; 3]>,
}

impl RgbImage {
    /// A black image.
    pub fn new(width: usize, height: usize) -> RgbImage {
        RgbImage {
            width,
            height,
            data: vec![[0.0; 3]; width * height],
        }
    }

    /// The pixel at column `x`, row `y` (row 0 at the top).
    #[inline]
    pub fn get(&self, x: usize, y: usize) -> [f32; 3] {
        self.data[y * self.width + x]
    }
}

/// What went wrong reading or writing an image; each variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("{path}: no such file")]
    Missing { path: PathBuf },
    #[error("{path}: is a directory, not an image")]
    IsDirectory { path: PathBuf },
    #[error("{path}: cannot read: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: file is empty")]
    Empty { path: PathBuf },
    #[error("{path}: not a {expected} file (unrecognised signature)")]
    NotTheFormat {
        path: PathBuf,
        expected: &'static str,
    },
    #[error("{path}: truncated {format} file: {what}")]
    Truncated {
        path: PathBuf,
        format: &'static str,
        what: String,
    },
    #[error("{path}: malformed {format} file: {what}")]
    Malformed {
        path: PathBuf,
        format: &'static str,
        what: String,
    },
    #[error("{path}: unsupported {format} file: {what}")]
    Unsupported {
        path: PathBuf,
        format: &'static str,
        what: String,
    },
    #[error("{path}: image of {width} × {height} pixels is too large (limit {MAX_PIXELS} pixels)")]
    TooLarge {
        path: PathBuf,
        width: usize,
        height: usize,
    },
    #[error("{path}: cannot write image: {what}")]
    Write { path: PathBuf, what: String },
}

/// Checks dimensions before pixel storage is allocated.
fn check_size(path: &Path, width: usize, height: usize) -> Result<(), ImageError> {
    let too_large = ImageError::TooLarge {
        path: path.to_path_buf(),
        width,
        height,
    };
    match width.checked_mul(height) {
        Some(n) if n <= MAX_PIXELS => Ok(()),
        _ => Err(too_large),
    }
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, ImageError> {
    let p = || path.to_path_buf();
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => ImageError::Missing { path: p() },
        _ => ImageError::Io {
            path: p(),
            source: e,
        },
    })?;
    if meta.is_dir() {
        return Err(ImageError::IsDirectory { path: p() });
    }
    let bytes = std::fs::read(path).map_err(|e| ImageError::Io {
        path: p(),
        source: e,
    })?;
    if bytes.is_empty() {
        return Err(ImageError::Empty { path: p() });
    }
    Ok(bytes)
}

const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
const PNG_MAGIC: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Reads an OpenEXR, Radiance HDR, PNG or JPEG image as linear RGB.
pub fn read_image(path: impl AsRef<Path>) -> Result<RgbImage, ImageError> {
    let path = path.as_ref();
    decode_image(path, &read_bytes(path)?)
}

/// [`read_image`] of a file's bytes already in memory: the format from its signature, `path`
/// only for messages (and, when no signature matches, for the format the error expects).
pub fn decode_image(path: &Path, bytes: &[u8]) -> Result<RgbImage, ImageError> {
    if bytes.starts_with(&EXR_MAGIC) {
        read_exr_bytes(path, bytes)
    } else if bytes.starts_with(&PNG_MAGIC) {
        read_png_bytes(path, bytes)
    } else if bytes.starts_with(b"#?") {
        hdr::read_hdr_bytes(path, bytes)
    } else if bytes.starts_with(&jpeg_io::JPEG_MAGIC) {
        jpeg_io::read_jpeg_bytes(path, bytes)
    } else {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        let expected = match ext.as_deref() {
            Some("exr") => "OpenEXR",
            Some("hdr") | Some("rgbe") | Some("pic") => "Radiance HDR",
            Some("png") => "PNG",
            Some("jpg") | Some("jpeg") => "JPEG",
            _ => "OpenEXR, Radiance HDR, PNG or JPEG",
        };
        Err(ImageError::NotTheFormat {
            path: path.to_path_buf(),
            expected,
        })
    }
}

/// sRGB transfer function: encoded value in [0, 1] → linear.
#[inline]
pub(crate) fn srgb_to_linear(v: f32) -> f32 {
    crate::spectrum::cie::srgb_decode(v)
}

/// Inverse sRGB transfer function: linear → encoded, clamped to [0, 1] (NaN → 0).
#[inline]
pub(crate) fn linear_to_srgb(v: f32) -> f32 {
    crate::spectrum::cie::srgb_encode(v).min(1.0)
}

fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), ImageError> {
    let err = |what: String| ImageError::Write {
        path: path.to_path_buf(),
        what,
    };
    let name = path.file_name().ok_or_else(|| err("no file name".into()))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    if let Err(e) = write(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        return Err(err(e));
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        err(e.to_string())
    })
}

fn check_writable(path: &Path, image: &RgbImage) -> Result<(), ImageError> {
    if image.width == 0 || image.height == 0 || image.data.len() != image.width * image.height {
        return Err(ImageError::Write {
            path: path.to_path_buf(),
            what: format!(
                "inconsistent image: {} × {} with {} pixels",
                image.width,
                image.height,
                image.data.len()
            ),
        });
    }
    check_size(path, image.width, image.height)
}

#[cfg(test)]
mod tests;
