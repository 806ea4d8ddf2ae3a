//! OpenEXR reading and writing for [`super`], through the `exr` crate: the first layer's `R`,
//! `G`, `B` (or `Y`) channels read as linear RGB, images written as 32-bit float RGB with extra
//! named channels (AOVs) and string attributes (ophis's metadata), atomically, with the header's
//! attributes in a fixed order ([`super::exr_order`]) so that equal images give equal files.
//! The known limits are in [`super`]'s header.
use super::{
    check_size, check_writable, exr_order, read_bytes, write_atomically, ImageError, RgbImage,
    EXR_MAGIC,
};
use std::io::Cursor;
use std::path::Path;

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

pub(super) fn read_exr_bytes(path: &Path, bytes: &[u8]) -> Result<RgbImage, ImageError> {
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
