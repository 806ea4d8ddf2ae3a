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

use std::io::Cursor;
use std::path::{Path, PathBuf};

mod exr_order;
mod hdr;
mod jpeg_io;
mod png_io;

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

fn exr_error(path: &Path, e: exr::error::Error) -> ImageError {
    let path = path.to_path_buf();
    let format = "OpenEXR";
    match e {
        exr::error::Error::NotSupported(w) => ImageError::Unsupported {
            path,
            format,
            what: w.into_owned(),
        },
        // The exr crate reports an unexpected end of file as this `Invalid` message.
        exr::error::Error::Invalid(w) if w.contains("missing bytes") => ImageError::Truncated {
            path,
            format,
            what: w.into_owned(),
        },
        exr::error::Error::Io(source) => ImageError::Io { path, source },
        other => ImageError::Malformed {
            path,
            format,
            what: other.to_string(),
        },
    }
}

fn read_exr_bytes(path: &Path, bytes: &[u8]) -> Result<RgbImage, ImageError> {
    use exr::prelude::*;
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(|e| exr_error(path, e))?;
    let header = meta.headers.first().ok_or_else(|| ImageError::Malformed {
        path: path.to_path_buf(),
        format: "OpenEXR",
        what: "no layers".into(),
    })?;
    for h in &meta.headers {
        check_size(path, h.layer_size.0, h.layer_size.1)?;
    }
    if header.deep {
        return Err(ImageError::Unsupported {
            path: path.to_path_buf(),
            format: "OpenEXR",
            what: "deep data".into(),
        });
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| exr_error(path, e))?;
    let layer = &image.layer_data;
    let (w, h) = (layer.size.0, layer.size.1);
    let channels = &layer.channel_data.list;
    // Prefer an exact channel name, then one with a layer prefix ("diffuse.R").
    let find = |name: &str| {
        let base = |c: &AnyChannel<FlatSamples>| c.name.to_string();
        channels.iter().position(|c| base(c) == name).or_else(|| {
            channels
                .iter()
                .position(|c| base(c).rsplit('.').next() == Some(name))
        })
    };
    let picked: Vec<usize> = match (find("R"), find("G"), find("B"), find("Y")) {
        (Some(r), Some(g), Some(b), _) => vec![r, g, b],
        (_, _, _, Some(y)) => vec![y, y, y],
        _ => {
            return Err(ImageError::Unsupported {
                path: path.to_path_buf(),
                format: "OpenEXR",
                what: "no R, G, B or Y channels in the first layer".into(),
            })
        }
    };
    for &c in &picked {
        let ch = &channels[c];
        if ch.sampling.0 != 1 || ch.sampling.1 != 1 || ch.sample_data.len() != w * h {
            return Err(ImageError::Unsupported {
                path: path.to_path_buf(),
                format: "OpenEXR",
                what: format!("sub-sampled channel {}", ch.name),
            });
        }
    }
    let mut out = RgbImage::new(w, h);
    for (i, px) in out.data.iter_mut().enumerate() {
        for k in 0..3 {
            px[k] = channels[picked[k]]
                .sample_data
                .value_by_flat_index(i)
                .to_f32();
        }
    }
    Ok(out)
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

/// Header attribute names the EXR format reserves; metadata may not overwrite them.
const EXR_RESERVED: &[&str] = &[
    "channels",
    "compression",
    "dataWindow",
    "displayWindow",
    "lineOrder",
    "pixelAspectRatio",
    "screenWindowCenter",
    "screenWindowWidth",
    "tiles",
    "type",
    "name",
    "version",
    "chunkCount",
];

/// The header attributes for `metadata` (string attributes; reserved names refused).
fn exr_attributes(
    path: &Path,
    metadata: &[(String, String)],
) -> Result<exr::meta::header::LayerAttributes, ImageError> {
    use exr::prelude::*;
    let mut attrs = LayerAttributes::default();
    for (k, v) in metadata {
        let bad = |what: &str| ImageError::Write {
            path: path.to_path_buf(),
            what: format!("metadata {k:?}: {what}"),
        };
        if EXR_RESERVED.contains(&k.as_str()) || k.is_empty() {
            return Err(bad("reserved or empty attribute name"));
        }
        let key = Text::new_or_none(k).ok_or_else(|| bad("name is not Latin-1"))?;
        let val = Text::new_or_none(v).ok_or_else(|| bad("value is not Latin-1"))?;
        // The exr crate keeps these standard names in dedicated fields.
        match k.as_str() {
            "owner" => attrs.owner = Some(val),
            "comments" => attrs.comments = Some(val),
            "capDate" => attrs.capture_date = Some(val),
            "software" => attrs.software_name = Some(val),
            _ => {
                attrs.other.insert(key, AttributeValue::Text(val));
            }
        }
    }
    Ok(attrs)
}

/// Puts the header attributes of an encoded EXR in a fixed order (the same image and metadata
/// then give the same bytes) and writes the file atomically.
fn finish_exr(path: &Path, encoded: Result<Vec<u8>, exr::error::Error>) -> Result<(), ImageError> {
    let mut bytes = encoded.map_err(|e| ImageError::Write {
        path: path.to_path_buf(),
        what: e.to_string(),
    })?;
    exr_order::sort_header_attributes(&mut bytes);
    write_atomically(path, |tmp| {
        std::fs::write(tmp, &bytes).map_err(|e| e.to_string())
    })
}

/// Encodes an image into memory.
macro_rules! encode_exr {
    ($image:expr) => {{
        let mut bytes = Vec::new();
        $image
            .write()
            .to_buffered(Cursor::new(&mut bytes))
            .map(|()| bytes)
    }};
}

/// Writes a float32 RGB OpenEXR file with `metadata` as string attributes in its header.
pub fn write_exr(
    path: impl AsRef<Path>,
    image: &RgbImage,
    metadata: &[(String, String)],
) -> Result<(), ImageError> {
    use exr::prelude::*;
    let path = path.as_ref();
    check_writable(path, image)?;
    let attrs = exr_attributes(path, metadata)?;
    let w = image.width;
    let pixels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let [r, g, b] = image.data[p.1 * w + p.0];
        (r, g, b)
    });
    let layer = Layer::new(
        (image.width, image.height),
        attrs,
        Encoding::FAST_LOSSLESS,
        pixels,
    );
    finish_exr(path, encode_exr!(Image::from_layer(layer)))
}

/// Writes a float32 OpenEXR file with channels R, G, B from `image` and the named `extra`
/// channels (e.g. AOVs such as `nn.X`), each a row-major image of the same size.
pub fn write_exr_channels(
    path: impl AsRef<Path>,
    image: &RgbImage,
    extra: &[(String, Vec<f32>)],
    metadata: &[(String, String)],
) -> Result<(), ImageError> {
    use exr::prelude::*;
    let path = path.as_ref();
    check_writable(path, image)?;
    let n = image.width * image.height;
    let bad = |what: String| ImageError::Write {
        path: path.to_path_buf(),
        what,
    };
    let mut list: exr::prelude::SmallVec<[AnyChannel<FlatSamples>; 4]> =
        exr::prelude::SmallVec::new();
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let data = image.data.iter().map(|p| p[c]).collect();
        list.push(AnyChannel::new(*name, FlatSamples::F32(data)));
    }
    for (name, data) in extra {
        if data.len() != n {
            return Err(bad(format!(
                "channel {name} has {} values for {n} pixels",
                data.len()
            )));
        }
        if ["R", "G", "B"].contains(&name.as_str())
            || list.iter().any(|c| c.name.to_string() == *name)
        {
            return Err(bad(format!("channel name {name:?} is used twice")));
        }
        let text =
            Text::new_or_none(name).ok_or_else(|| bad(format!("{name:?} is not Latin-1")))?;
        list.push(AnyChannel::new(text, FlatSamples::F32(data.clone())));
    }
    let layer = Layer::new(
        (image.width, image.height),
        exr_attributes(path, metadata)?,
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(list),
    );
    finish_exr(path, encode_exr!(Image::from_layer(layer)))
}

/// The headers of an OpenEXR file, without its pixels.
fn read_exr_meta(path: &Path) -> Result<exr::meta::MetaData, ImageError> {
    let bytes = read_bytes(path)?;
    if !bytes.starts_with(&EXR_MAGIC) {
        return Err(ImageError::NotTheFormat {
            path: path.to_path_buf(),
            expected: "OpenEXR",
        });
    }
    exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(|e| exr_error(path, e))
}

/// The names of the channels in an OpenEXR file's first layer, sorted as stored.
pub fn read_exr_channel_names(path: impl AsRef<Path>) -> Result<Vec<String>, ImageError> {
    let meta = read_exr_meta(path.as_ref())?;
    Ok(meta
        .headers
        .first()
        .map(|h| h.channels.list.iter().map(|c| c.name.to_string()).collect())
        .unwrap_or_default())
}

/// The string attributes in an OpenEXR file's first header, sorted by name.
pub fn read_exr_metadata(path: impl AsRef<Path>) -> Result<Vec<(String, String)>, ImageError> {
    use exr::meta::attribute::AttributeValue;
    let meta = read_exr_meta(path.as_ref())?;
    let mut out = Vec::new();
    if let Some(h) = meta.headers.first() {
        let others = h
            .shared_attributes
            .other
            .iter()
            .chain(&h.own_attributes.other);
        for (k, v) in others {
            if let AttributeValue::Text(t) = v {
                out.push((k.to_string(), t.to_string()));
            }
        }
        // The exr crate lifts these standard names out of the generic map.
        let a = &h.own_attributes;
        let named = [
            ("owner", &a.owner),
            ("comments", &a.comments),
            ("capDate", &a.capture_date),
            ("software", &a.software_name),
        ];
        for (k, v) in named {
            if let Some(t) = v {
                out.push((k.to_string(), t.to_string()));
            }
        }
    }
    out.sort();
    Ok(out)
}

#[cfg(test)]
mod tests;
