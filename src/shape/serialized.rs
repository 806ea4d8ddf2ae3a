//! Mitsuba's compressed mesh format (`serialized` shape), versions 3 and 4 (Mitsuba 0.4–3.9).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `filename` | string | required | — | the mesh file, relative to the scene file |
//! | `face_normals` | boolean | false | — | flat shading: ignore the file's normals and do not smooth |
//! | `shape_index` | integer | 0 | — | which mesh of the file; between 0 and 4294967295 |
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |
//!
//! Layout (from Mitsuba's documentation and its `serialized.cpp`; everything little-endian):
//! a file holds one or more meshes back to back, each a 2-byte magic `0x041C`, a 2-byte
//! version (3 or 4), then one zlib stream holding: a `u32` flag word (`0x1` normals, `0x2`
//! texture coordinates, `0x8` vertex colours, `0x2000` double precision), the mesh's name as a
//! NUL-terminated string (version 4 only), `u64` vertex and triangle counts, then the arrays —
//! positions (3 per vertex), normals, UVs (2), colours (3), in `f32` or `f64` — and 3 `u32`
//! indices per triangle. The file ends with the byte offset of every mesh (`u64` each in
//! version 4, `u32` in version 3) and a `u32` mesh count, which is how `shape_index` finds its
//! mesh.
//!
//! As in Mitsuba 3, texture coordinates are used as stored (not flipped), colours are skipped,
//! and a mesh without normals gets smooth vertex normals (see `load.rs`).
//!
//! Bad input gives a [`LoadError`] naming the file and the byte (of the file for the header
//! and the offset table, of the mesh's decompressed stream for its contents). Arrays grow with
//! the data actually decompressed, so a header announcing huge counts cannot trigger a huge
//! allocation.
//!
//! Limits: version 5 (Mitsuba after 3.9: surface-point and normal-group maps) is refused.

use super::load::{read_file, LoadError, MeshData};
use crate::math::{Vec2, Vec3};
use crate::plugin::{declare, Args, Param, SceneError};
use flate2::read::ZlibDecoder;
use std::io::Read;
use std::path::Path;

declare!(PLUGIN: super::Parts, crate::math::Transform = Shape "serialized" []
    "a mesh of Mitsuba's compressed format (versions 3 and 4)"
    [super::load::MESH_FILE, &[Param::u32("shape_index", 0).doc("which mesh of the file")], super::PLACEMENT] load);

fn load(a: &mut Args, parent: crate::math::Transform) -> Result<super::Parts, SceneError> {
    super::load::mesh_file(a, &parent, super::load::MeshFile::Serialized)
}

const MAGIC: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const DOUBLE_PRECISION: u32 = 0x2000;
/// Longest mesh name read (names are labels; a longer one is garbage).
const MAX_NAME: usize = 1 << 16;
/// Bytes decompressed per step while filling an array.
const CHUNK: usize = 1 << 20;

/// Reads mesh `shape_index` of a `.serialized` file.
pub(crate) fn read_serialized(path: &Path, shape_index: u32) -> Result<MeshData, LoadError> {
    let bytes = read_file(path)?;
    parse_serialized(&bytes, path, shape_index)
}

fn binary(path: &Path, offset: usize, message: impl Into<String>) -> LoadError {
    LoadError::Binary {
        path: path.to_path_buf(),
        offset,
        message: message.into(),
    }
}

fn u16_at(bytes: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(bytes.get(at..at + 2)?.try_into().ok()?))
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

fn u64_at(bytes: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(bytes.get(at..at + 8)?.try_into().ok()?))
}

/// The mesh header at `at`: its version.
fn header(bytes: &[u8], path: &Path, at: usize) -> Result<u16, LoadError> {
    let (Some(magic), Some(version)) = (u16_at(bytes, at), u16_at(bytes, at + 2)) else {
        return Err(binary(
            path,
            at,
            "the file ends inside a mesh header; expected a 4-byte header",
        ));
    };
    if magic != MAGIC {
        return Err(binary(
            path,
            at,
            format!(
                "found the identifier 0x{magic:04X}; expected 0x041C (a Mitsuba serialized mesh)"
            ),
        ));
    }
    match version {
        3 | 4 => Ok(version),
        5 => Err(binary(
            path,
            at + 2,
            "found format version 5 (Mitsuba after 3.9), which ophis does not read; expected 3 or 4",
        )),
        v => Err(binary(path, at + 2, format!("found format version {v}; expected 3 or 4"))),
    }
}

/// The byte offset of mesh `index`, from the table at the end of the file.
fn mesh_offset(bytes: &[u8], path: &Path, version: u16, index: u32) -> Result<usize, LoadError> {
    let n = bytes.len();
    let count = n
        .checked_sub(4)
        .and_then(|at| u32_at(bytes, at))
        .ok_or_else(|| binary(path, 0, "the file is too short for its mesh table"))?;
    if index >= count {
        return Err(binary(
            path,
            n - 4,
            format!("shape_index {index} is out of range: the file holds {count} meshes"),
        ));
    }
    let entry = if version >= 4 { 8 } else { 4 };
    let table = (count as usize)
        .checked_mul(entry)
        .and_then(|t| n.checked_sub(4 + t))
        .ok_or_else(|| {
            binary(
                path,
                n - 4,
                format!("the mesh table of {count} entries is longer than the file"),
            )
        })?;
    let at = table + index as usize * entry;
    let off = if version >= 4 {
        u64_at(bytes, at).unwrap_or(u64::MAX)
    } else {
        u32_at(bytes, at).map_or(u64::MAX, u64::from)
    };
    if off >= table as u64 {
        return Err(binary(
            path,
            at,
            format!("mesh {index} starts at byte {off}, beyond the meshes' data ({table} bytes)"),
        ));
    }
    Ok(off as usize)
}

/// The decompressed stream of one mesh, read in order.
struct Stream<'a> {
    z: ZlibDecoder<&'a [u8]>,
    path: &'a Path,
    /// Bytes decompressed so far.
    pos: usize,
}

impl Stream<'_> {
    fn fill(&mut self, buf: &mut [u8], what: &str) -> Result<(), LoadError> {
        let mut done = 0;
        while done < buf.len() {
            match self.z.read(&mut buf[done..]) {
                Ok(0) => {
                    return Err(binary(
                        self.path,
                        self.pos + done,
                        format!("the compressed data ends inside {what}"),
                    ))
                }
                Ok(k) => done += k,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    return Err(binary(
                        self.path,
                        self.pos + done,
                        format!("corrupt compressed data in {what}: {e}"),
                    ))
                }
            }
        }
        self.pos += done;
        Ok(())
    }

    fn u32(&mut self, what: &str) -> Result<u32, LoadError> {
        let mut b = [0; 4];
        self.fill(&mut b, what)?;
        Ok(u32::from_le_bytes(b))
    }

    fn u64(&mut self, what: &str) -> Result<u64, LoadError> {
        let mut b = [0; 8];
        self.fill(&mut b, what)?;
        Ok(u64::from_le_bytes(b))
    }

    /// `count` little-endian values of `size` bytes, decompressed chunk by chunk.
    fn bytes(&mut self, count: u64, size: usize, what: &str) -> Result<Vec<u8>, LoadError> {
        let total = count
            .checked_mul(size as u64)
            .and_then(|t| usize::try_from(t).ok())
            .ok_or_else(|| {
                binary(
                    self.path,
                    self.pos,
                    format!("{what}: {count} entries are too many"),
                )
            })?;
        let mut out = Vec::new();
        while out.len() < total {
            let step = CHUNK.min(total - out.len());
            let start = out.len();
            out.try_reserve(step)
                .map_err(|_| binary(self.path, self.pos, format!("{what}: out of memory")))?;
            out.resize(start + step, 0);
            self.fill(&mut out[start..], what)?;
        }
        Ok(out)
    }

    /// `count` vectors of `DIM` reals (`f32` or `f64` as stored).
    fn reals<const DIM: usize>(
        &mut self,
        count: u64,
        double: bool,
        what: &str,
    ) -> Result<Vec<[f32; DIM]>, LoadError> {
        let size = if double { 8 } else { 4 };
        let raw = self.bytes(count, DIM * size, what)?;
        Ok(raw
            .chunks_exact(DIM * size)
            .map(|v| {
                std::array::from_fn(|k| {
                    let b = &v[k * size..(k + 1) * size];
                    if double {
                        f64::from_le_bytes(b.try_into().expect("8 bytes")) as f32
                    } else {
                        f32::from_le_bytes(b.try_into().expect("4 bytes"))
                    }
                })
            })
            .collect())
    }
}

/// Parses mesh `shape_index` of the bytes of a `.serialized` file (`path` names it in errors).
pub(crate) fn parse_serialized(
    bytes: &[u8],
    path: &Path,
    shape_index: u32,
) -> Result<MeshData, LoadError> {
    let version = header(bytes, path, 0)?;
    let start = if shape_index == 0 {
        0
    } else {
        let at = mesh_offset(bytes, path, version, shape_index)?;
        if header(bytes, path, at)? != version {
            return Err(binary(
                path,
                at + 2,
                "meshes of different format versions in one file",
            ));
        }
        at
    };
    let mut s = Stream {
        z: ZlibDecoder::new(&bytes[start + 4..]),
        path,
        pos: 0,
    };
    let flags = s.u32("the flag word")?;
    if version == 4 {
        let mut name = Vec::new();
        loop {
            let mut c = [0u8];
            s.fill(&mut c, "the mesh name")?;
            if c[0] == 0 {
                break;
            }
            if name.len() >= MAX_NAME {
                return Err(binary(
                    path,
                    s.pos,
                    "the mesh name has no end (no NUL byte within 64 KiB)",
                ));
            }
            name.push(c[0]);
        }
    }
    let vertices = s.u64("the vertex count")?;
    let triangles = s.u64("the triangle count")?;
    if triangles == 0 {
        return Err(LoadError::Empty {
            path: path.to_path_buf(),
        });
    }
    if vertices > u32::MAX as u64 {
        return Err(binary(
            path,
            s.pos,
            format!("{vertices} vertices; expected at most 2^32 (32-bit indices)"),
        ));
    }
    let double = flags & DOUBLE_PRECISION != 0;
    let positions = s.reals::<3>(vertices, double, "the positions")?;
    let normals = if flags & HAS_NORMALS != 0 {
        Some(s.reals::<3>(vertices, double, "the normals")?)
    } else {
        None
    };
    let uvs = if flags & HAS_TEXCOORDS != 0 {
        Some(s.reals::<2>(vertices, double, "the texture coordinates")?)
    } else {
        None
    };
    if flags & HAS_COLORS != 0 {
        s.bytes(
            vertices,
            3 * if double { 8 } else { 4 },
            "the vertex colours",
        )?;
    }
    let raw = s.bytes(triangles, 12, "the triangles")?;
    let indices = raw
        .chunks_exact(12)
        .map(|t| {
            std::array::from_fn(|k| {
                u32::from_le_bytes(t[4 * k..4 * k + 4].try_into().expect("4 bytes"))
            })
        })
        .collect();
    Ok(MeshData {
        positions: positions.into_iter().map(Vec3::from).collect(),
        normals: normals.map(|n| n.into_iter().map(Vec3::from).collect()),
        uvs: uvs.map(|u| u.into_iter().map(Vec2::from).collect()),
        indices,
    })
}

#[cfg(test)]
#[path = "serialized_tests.rs"]
mod tests;
