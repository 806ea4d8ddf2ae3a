//! Stanford PLY reader (Mitsuba's `ply` shape; options in [`super::MeshOptions`]).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `filename` | string | required | — | the mesh file, relative to the scene file |
//! | `face_normals` | boolean | false | — | flat shading: ignore the file's normals and do not smooth |
//! | `flip_tex_coords` | boolean | false | — | v ↦ 1 − v (Mitsuba 3 flips OBJ's, not PLY's) |
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |
//!
//! Formats `ascii`, `binary_little_endian` and `binary_big_endian`. The `vertex` element must
//! have `x y z`; `nx ny nz` and a UV pair (`u v`, `s t`, `texture_u texture_v` or
//! `texture_s texture_t`) are read when present. Property types: `char uchar short ushort int
//! uint float double` and the aliases `int8 uint8 int16 uint16 int32 uint32 float32 float64`.
//! The `face` element's `vertex_indices` (or `vertex_index`) list, of any integer types, gives
//! polygons, triangulated as fans. Other elements and properties are skipped.
//!
//! Bad input gives a [`LoadError`]: header errors name the header line, ASCII data errors the
//! line, binary data errors the byte offset. Element counts are checked against the bytes left
//! before anything is allocated, so a garbage count cannot trigger a huge allocation.
//!
//! Limits: faces with fewer than 3 corners are skipped; `tristrips` and other connectivity
//! elements are ignored.
use super::load::{read_file, LoadError, MeshData};
use crate::math::{Vec2, Vec3};
use crate::plugin::{declare, Args, SceneError};
use std::path::{Path, PathBuf};

declare!(PLUGIN: super::Parts, crate::math::Transform = Shape "ply" []
    "Stanford PLY triangle mesh (ASCII or binary)"
    [super::load::MESH_FILE, &[super::load::flip_tex_coords(false)], super::PLACEMENT] load);

fn load(a: &mut Args, parent: crate::math::Transform) -> Result<super::Parts, SceneError> {
    super::load::mesh_file(a, &parent, super::load::MeshFile::Ply)
}

/// Reads a PLY file.
pub fn read_ply(path: &Path) -> Result<MeshData, LoadError> {
    let bytes = read_file(path)?;
    parse_ply(&bytes, path)
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Ty {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Ty {
    fn parse(s: &str) -> Option<Ty> {
        Some(match s {
            "char" | "int8" => Ty::I8,
            "uchar" | "uint8" => Ty::U8,
            "short" | "int16" => Ty::I16,
            "ushort" | "uint16" => Ty::U16,
            "int" | "int32" => Ty::I32,
            "uint" | "uint32" => Ty::U32,
            "float" | "float32" => Ty::F32,
            "double" | "float64" => Ty::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Ty::I8 | Ty::U8 => 1,
            Ty::I16 | Ty::U16 => 2,
            Ty::I32 | Ty::U32 | Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }
    fn is_int(self) -> bool {
        !matches!(self, Ty::F32 | Ty::F64)
    }
}

#[derive(Debug)]
struct Prop {
    name: String,
    /// `Some(count type)` for a list property.
    list: Option<Ty>,
    ty: Ty,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Prop>,
    line: usize,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Format {
    Ascii,
    Little,
    Big,
}

/// Sequential access to the body, in either encoding.
struct Body<'a> {
    data: &'a [u8],
    /// Offset of `data` in the file (for messages).
    base: usize,
    pos: usize,
    line: usize,
    format: Format,
    path: &'a Path,
}

impl Body<'_> {
    fn error(&self, message: String) -> LoadError {
        let path = self.path.to_path_buf();
        match self.format {
            Format::Ascii => LoadError::Syntax {
                path,
                line: self.line,
                message,
            },
            _ => LoadError::Binary {
                path,
                offset: self.base + self.pos,
                message,
            },
        }
    }

    fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    fn value(&mut self, ty: Ty) -> Result<f64, LoadError> {
        if self.format == Format::Ascii {
            return self.ascii_value(ty);
        }
        let n = ty.size();
        if self.remaining() < n {
            return Err(self.error(format!(
                "file is truncated: expected a {n}-byte value, {} bytes left",
                self.remaining()
            )));
        }
        let v = fast::decode(ty, &self.data[self.pos..], self.format == Format::Big);
        self.pos += n;
        Ok(v)
    }

    fn ascii_value(&mut self, ty: Ty) -> Result<f64, LoadError> {
        while self.pos < self.data.len() && self.data[self.pos].is_ascii_whitespace() {
            if self.data[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < self.data.len() && !self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let tok = &self.data[start..self.pos];
        if tok.is_empty() {
            return Err(self.error("file is truncated: expected a number".into()));
        }
        let v = std::str::from_utf8(tok)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|v| !ty.is_int() || v.fract() == 0.0)
            .ok_or_else(|| {
                let shown = String::from_utf8_lossy(&tok[..tok.len().min(40)]).into_owned();
                self.error(format!("expected a {ty:?} value, found `{shown}`"))
            })?;
        Ok(v)
    }

    /// A list length: a non-negative integer.
    fn count(&mut self, ty: Ty) -> Result<usize, LoadError> {
        let v = self.value(ty)?;
        if v < 0.0 {
            return Err(self.error(format!("negative list length {v}")));
        }
        Ok(v as usize)
    }
}

/// Parses PLY bytes; `path` only names the source in errors.
pub(crate) fn parse_ply(bytes: &[u8], path: &Path) -> Result<MeshData, LoadError> {
    let (format, elements, body_start, header_lines) = parse_header(bytes, path)?;
    let mut body = Body {
        data: &bytes[body_start..],
        base: body_start,
        pos: 0,
        line: header_lines + 1,
        format,
        path,
    };
    let n_vertices = elements
        .iter()
        .find(|e| e.name == "vertex")
        .map_or(0, |e| e.count);
    let mut out = MeshData::default();
    let mut polygon: Vec<u32> = Vec::new();
    let mut saw_face = false;
    for el in &elements {
        check_room(&body, el)?;
        let find = |n: &str| {
            el.props
                .iter()
                .position(|p| p.name == n && p.list.is_none())
        };
        if el.name == "vertex" {
            let xyz = ["x", "y", "z"].map(find);
            if xyz.iter().any(Option::is_none) {
                return Err(syntax(
                    path,
                    el.line,
                    "element `vertex` needs properties x, y and z",
                ));
            }
            let nxyz = ["nx", "ny", "nz"].map(find);
            let has_n = nxyz.iter().all(Option::is_some);
            let uv_names = [
                ["u", "v"],
                ["s", "t"],
                ["texture_u", "texture_v"],
                ["texture_s", "texture_t"],
            ];
            let uv = uv_names
                .iter()
                .map(|pair| pair.map(find))
                .find(|pair| pair.iter().all(Option::is_some));
            // Slot of each property in the per-vertex record: 0..3 position, 3..6 normal, 6..8 uv.
            let mut slot = vec![usize::MAX; el.props.len()];
            for (k, i) in xyz.iter().enumerate() {
                slot[i.unwrap()] = k;
            }
            if has_n {
                for (k, i) in nxyz.iter().enumerate() {
                    slot[i.unwrap()] = 3 + k;
                }
            }
            if let Some(pair) = uv {
                for (k, i) in pair.iter().enumerate() {
                    slot[i.unwrap()] = 6 + k;
                }
            }
            if let Some(v) = fast::vertices(&body, el, &slot, has_n, uv.is_some()) {
                body.pos += v.bytes;
                match out.positions.is_empty() {
                    true => out.positions = v.positions,
                    false => out.positions.extend(v.positions),
                }
                out.normals = v.normals;
                out.uvs = v.uvs;
                continue;
            }
            out.positions.reserve_exact(el.count);
            let mut normals = Vec::with_capacity(if has_n { el.count } else { 0 });
            let mut uvs = Vec::with_capacity(if uv.is_some() { el.count } else { 0 });
            let mut rec = [0.0f32; 8];
            for _ in 0..el.count {
                for (p, &s) in el.props.iter().zip(&slot) {
                    if let Some(ct) = p.list {
                        let n = body.count(ct)?;
                        for _ in 0..n {
                            body.value(p.ty)?;
                        }
                    } else {
                        let v = body.value(p.ty)?;
                        if s != usize::MAX {
                            rec[s] = v as f32;
                        }
                    }
                }
                out.positions.push(Vec3::new(rec[0], rec[1], rec[2]));
                if has_n {
                    normals.push(Vec3::new(rec[3], rec[4], rec[5]));
                }
                if uv.is_some() {
                    uvs.push(Vec2::new(rec[6], rec[7]));
                }
            }
            out.normals = has_n.then_some(normals);
            out.uvs = uv.map(|_| uvs);
        } else if el.name == "face" {
            saw_face = true;
            let list = el.props.iter().position(|p| {
                p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index")
            });
            let Some(list) = list else {
                return Err(syntax(
                    path,
                    el.line,
                    "element `face` needs a list property vertex_indices",
                ));
            };
            if !el.props[list].ty.is_int() {
                return Err(syntax(
                    path,
                    el.line,
                    "vertex_indices must be a list of integers",
                ));
            }
            if let Some((tris, bytes)) = fast::triangles(&body, el, n_vertices) {
                body.pos += bytes;
                out.indices.extend(tris);
                continue;
            }
            out.indices.reserve(el.count.min(body.remaining()));
            for _ in 0..el.count {
                for (k, p) in el.props.iter().enumerate() {
                    match p.list {
                        Some(ct) => {
                            let n = body.count(ct)?;
                            if k == list {
                                polygon.clear();
                            }
                            for _ in 0..n {
                                let v = body.value(p.ty)?;
                                if k == list {
                                    if !(v >= 0.0 && (v as usize) < n_vertices) {
                                        return Err(body.error(format!(
                                            "vertex index {v} is out of range (the file has {n_vertices} vertices)"
                                        )));
                                    }
                                    polygon.push(v as u32);
                                }
                            }
                        }
                        None => {
                            body.value(p.ty)?;
                        }
                    }
                }
                for j in 1..polygon.len().saturating_sub(1) {
                    out.indices.push([polygon[0], polygon[j], polygon[j + 1]]);
                }
                polygon.clear();
            }
        } else {
            for _ in 0..el.count {
                for p in &el.props {
                    if let Some(ct) = p.list {
                        let n = body.count(ct)?;
                        for _ in 0..n {
                            body.value(p.ty)?;
                        }
                    } else {
                        body.value(p.ty)?;
                    }
                }
            }
        }
    }
    if !saw_face || out.indices.is_empty() {
        return Err(LoadError::Empty {
            path: path.to_path_buf(),
        });
    }
    Ok(out)
}

/// Rejects element counts that cannot fit in the bytes left (before allocating for them).
fn check_room(body: &Body, el: &Element) -> Result<(), LoadError> {
    let per = if body.format == Format::Ascii {
        // Every value takes at least one character and one separator.
        2 * el.props.len()
    } else {
        el.props.iter().map(|p| p.list.unwrap_or(p.ty).size()).sum()
    };
    let need = el.count.saturating_mul(per);
    // The last ASCII value may lack its trailing separator.
    if need > body.remaining() + 1 {
        return Err(body.error(format!(
            "file is truncated: element `{}` declares {} entries (at least {need} bytes) but {} bytes remain",
            el.name,
            el.count,
            body.remaining()
        )));
    }
    Ok(())
}

fn syntax(path: &Path, line: usize, message: &str) -> LoadError {
    LoadError::Syntax {
        path: PathBuf::from(path),
        line,
        message: message.to_string(),
    }
}

type Header = (Format, Vec<Element>, usize, usize);

/// Parses the header; returns the format, the elements, the offset of the body and the number
/// of header lines.
fn parse_header(bytes: &[u8], path: &Path) -> Result<Header, LoadError> {
    if !bytes.starts_with(b"ply") {
        return Err(syntax(
            path,
            1,
            "not a PLY file: expected `ply` on the first line",
        ));
    }
    let mut pos = 0;
    let mut line_no = 0;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some(len) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            return Err(syntax(
                path,
                line_no + 1,
                "header is truncated: expected `end_header`",
            ));
        };
        let raw = &bytes[pos..pos + len];
        pos += len + 1;
        line_no += 1;
        let text = String::from_utf8_lossy(raw);
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        let bad = |what: &str| syntax(path, line_no, &format!("{what}, found `{}`", text.trim()));
        match words.as_slice() {
            ["ply"] if line_no == 1 => {}
            ["end_header"] => break,
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", f, _version] => {
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Little,
                    "binary_big_endian" => Format::Big,
                    _ => {
                        return Err(bad(
                            "expected format ascii, binary_little_endian or binary_big_endian",
                        ))
                    }
                });
            }
            ["element", name, count] => {
                let count = count
                    .parse::<usize>()
                    .map_err(|_| bad("expected `element <name> <count>`"))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                    line: line_no,
                });
            }
            ["property", "list", ct, it, name] => {
                let (Some(ct), Some(it)) = (Ty::parse(ct), Ty::parse(it)) else {
                    return Err(bad(
                        "expected `property list <count type> <item type> <name>`",
                    ));
                };
                if !ct.is_int() {
                    return Err(bad("a list's count type must be an integer type"));
                }
                let el = elements
                    .last_mut()
                    .ok_or_else(|| bad("property before any element"))?;
                el.props.push(Prop {
                    name: name.to_string(),
                    list: Some(ct),
                    ty: it,
                });
            }
            ["property", ty, name] => {
                let ty = Ty::parse(ty).ok_or_else(|| bad("unknown property type"))?;
                let el = elements
                    .last_mut()
                    .ok_or_else(|| bad("property before any element"))?;
                el.props.push(Prop {
                    name: name.to_string(),
                    list: None,
                    ty,
                });
            }
            _ => return Err(bad("unrecognised header line")),
        }
    }
    let format = format.ok_or_else(|| syntax(path, line_no, "header has no `format` line"))?;
    Ok((format, elements, pos, line_no))
}

#[path = "ply_fast.rs"]
mod fast;

#[cfg(test)]
#[path = "ply_tests.rs"]
mod tests;
