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

use std::path::{Path, PathBuf};

/// An ordered list of folders to look relative file names up in.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FileResolver {
    dirs: Vec<PathBuf>,
}

impl FileResolver {
    /// A resolver searching `dirs` in order.
    pub fn new(dirs: Vec<PathBuf>) -> FileResolver {
        FileResolver { dirs }
    }

    /// The resolver a scene file starts with: its folder, then the working directory.
    pub fn for_scene(file: &Path) -> FileResolver {
        let mut dirs = vec![file.parent().map(PathBuf::from).unwrap_or_default()];
        if let Ok(cwd) = std::env::current_dir() {
            dirs.push(cwd);
        }
        FileResolver { dirs }
    }

    /// Puts `dir` first, ahead of every folder already listed.
    pub fn prepend(&mut self, dir: PathBuf) {
        self.dirs.insert(0, dir);
    }

    /// The folders, searched first to last.
    pub fn dirs(&self) -> &[PathBuf] {
        &self.dirs
    }

    /// The first `dir/name` that exists; an absolute `name` if it exists; `None` otherwise.
    pub fn find(&self, name: &Path) -> Option<PathBuf> {
        if name.is_absolute() {
            return name.exists().then(|| name.to_path_buf());
        }
        self.dirs.iter().map(|d| d.join(name)).find(|p| p.exists())
    }
}

/// Reads a scene file as text: UTF-8 (a byte-order mark is dropped) or UTF-16 with a
/// byte-order mark. A directory is an error (on some systems reading one succeeds).
pub fn read_text(path: &Path) -> std::io::Result<String> {
    if path.is_dir() {
        return Err(std::io::Error::other("it is a directory, not a file"));
    }
    decode_text(std::fs::read(path)?)
}

/// Decodes the bytes of a scene file (see [`read_text`]).
pub fn decode_text(bytes: Vec<u8>) -> std::io::Result<String> {
    let invalid = |what: String| std::io::Error::new(std::io::ErrorKind::InvalidData, what);
    let utf16 = |body: &[u8], big_endian: bool| {
        if body.len() % 2 != 0 {
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

    #[test]
    fn first_folder_holding_the_name_wins() {
        let base = std::env::temp_dir().join(format!("ophis-resolver-{}", std::process::id()));
        let (a, b) = (base.join("a"), base.join("b"));
        std::fs::create_dir_all(&a).unwrap();
        std::fs::create_dir_all(&b).unwrap();
        std::fs::write(b.join("m.ply"), "x").unwrap();
        std::fs::write(a.join("both.ply"), "x").unwrap();
        std::fs::write(b.join("both.ply"), "x").unwrap();
        let mut r = FileResolver::new(vec![b.clone()]);
        r.prepend(a.clone());
        assert_eq!(r.find(Path::new("m.ply")), Some(b.join("m.ply")));
        assert_eq!(r.find(Path::new("both.ply")), Some(a.join("both.ply")));
        assert_eq!(r.find(Path::new("none.ply")), None);
        let abs = b.join("m.ply");
        assert_eq!(r.find(&abs), Some(abs.clone()));
        let _ = std::fs::remove_dir_all(&base);
    }
}
