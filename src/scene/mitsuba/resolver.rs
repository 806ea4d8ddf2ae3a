//! Where relative file names are looked up, and how scene files are decoded into text.
//!
//! File names follow Mitsuba 3's file resolver (`src/core/fresolver.cpp`, `src/core/parser.cpp`):
//! a list of folders, searched in order, the first folder holding the name winning; an absolute
//! name is taken as it is.
//!
//! - Loading a scene starts the list with the scene file's folder, then the working directory.
//! - `<path value="dir"/>` (only directly inside a `<scene>`) puts `dir` in front of the list;
//!   a relative `dir` is taken relative to the file that declares it if it exists there,
//!   otherwise looked up in the list. The folder must exist.
//! - `<include filename="…"/>` is looked up with the including file's folder in front. Inside
//!   the included file, lookups made while reading it (nested includes, `<spectrum filename>`)
//!   see that folder and the file's own `<path>`s; none of it outlives the include.
//! - Plugin file names (`filename` of meshes, bitmaps, environment maps) are resolved after the
//!   whole scene was read, with the root file's list: so a mesh named in an included file is
//!   looked up in the scene's folder and its `<path>` entries, not next to the included file.
//!   (ophis then tries the declaring file's folder as a last resort; Mitsuba would stop.)
//!
//! Text: UTF-8, with or without a byte-order mark, and UTF-16 (either byte order) with its
//! byte-order mark, as the XML specification requires of UTF-16 documents.

use std::path::Path;

pub(crate) use crate::plugin::FileResolver;

/// Reads a scene file as text: UTF-8 (a byte-order mark is dropped) or UTF-16 with a
/// byte-order mark. A directory is an error (on some systems reading one succeeds).
pub(crate) fn read_text(path: &Path) -> std::io::Result<String> {
    if path.is_dir() {
        return Err(std::io::Error::other("it is a directory, not a file"));
    }
    decode_text(std::fs::read(path)?)
}

/// Decodes the bytes of a scene file (see [`read_text`]).
pub(crate) fn decode_text(bytes: Vec<u8>) -> std::io::Result<String> {
    let invalid = |what: String| std::io::Error::new(std::io::ErrorKind::InvalidData, what);
    let utf16 = |body: &[u8], big_endian: bool| {
        if !body.len().is_multiple_of(2) {
            return Err(invalid(
                "UTF-16 text with an odd number of bytes; expected whole 16-bit units".into(),
            ));
        }
        let units = body.chunks_exact(2).map(|c| {
            if big_endian {
                u16::from_be_bytes([c[0], c[1]])
            } else {
                u16::from_le_bytes([c[0], c[1]])
            }
        });
        char::decode_utf16(units)
            .enumerate()
            .map(|(i, c)| {
                c.map_err(|_| {
                    invalid(format!(
                        "invalid UTF-16 (an unpaired surrogate at byte {}); expected text",
                        2 + 2 * i
                    ))
                })
            })
            .collect::<std::io::Result<String>>()
    };
    match bytes.as_slice() {
        [0xFF, 0xFE, body @ ..] => utf16(body, false),
        [0xFE, 0xFF, body @ ..] => utf16(body, true),
        [0xEF, 0xBB, 0xBF, body @ ..] => String::from_utf8(body.to_vec()).map_err(|e| {
            invalid(format!(
                "invalid UTF-8 at byte {}; expected UTF-8 or UTF-16 text",
                3 + e.utf8_error().valid_up_to()
            ))
        }),
        _ => String::from_utf8(bytes).map_err(|e| {
            invalid(format!(
                "invalid UTF-8 at byte {}; expected UTF-8 text, or UTF-16 with a byte-order mark",
                e.utf8_error().valid_up_to()
            ))
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_both_orders_and_utf8_bom_decode() {
        let text = "<scene version=\"3.0.0\"/>é€𝄞";
        let le: Vec<u8> = [0xFF, 0xFE]
            .into_iter()
            .chain(text.encode_utf16().flat_map(u16::to_le_bytes))
            .collect();
        let be: Vec<u8> = [0xFE, 0xFF]
            .into_iter()
            .chain(text.encode_utf16().flat_map(u16::to_be_bytes))
            .collect();
        let bom8: Vec<u8> = [0xEF, 0xBB, 0xBF].into_iter().chain(text.bytes()).collect();
        for bytes in [le, be, bom8, text.as_bytes().to_vec()] {
            assert_eq!(decode_text(bytes).unwrap(), text);
        }
    }

    #[test]
    fn bad_text_is_an_error_not_a_panic() {
        for bytes in [
            vec![0xFF, 0xFE, 0x3C],       // odd length
            vec![0xFF, 0xFE, 0x00, 0xD8], // lone high surrogate
            vec![b'<', 0xC3],             // truncated UTF-8
            vec![0xEF, 0xBB, 0xBF, 0xFF], // bad UTF-8 after the mark
        ] {
            let e = decode_text(bytes).unwrap_err();
            assert_eq!(e.kind(), std::io::ErrorKind::InvalidData, "{e}");
        }
    }
}
