//! Wavefront OBJ reader (Mitsuba's `obj` shape; options in [`super::MeshOptions`]).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `filename` | string | required | — | the mesh file, relative to the scene file |
//! | `face_normals` | boolean | false | — | flat shading: ignore the file's normals and do not smooth |
//! | `flip_tex_coords` | boolean | true | — | v ↦ 1 − v (Mitsuba 3 flips OBJ's, not PLY's) |
//! | `to_world` | transform | — | — | object-to-world transform (after an `instance`'s own) |
//! | `flip_normals` | boolean | false | — | turn the normals the other way (an area light then emits from the other side) |
//!
//! Reads `v x y z`, `vt u [v]`, `vn x y z` and `f` with corners `v`, `v/vt`, `v//vn` or
//! `v/vt/vn`; indices are 1-based, negative indices count back from the latest element.
//! Polygons are triangulated as fans around their first corner. `o`, `g`, `s`, `usemtl`,
//! `mtllib`, other keywords and `#` comments are ignored. A vertex is emitted once per distinct
//! (position, uv, normal) combination.
//!
//! Limits: one mesh per file (groups and materials are not split out); line continuations
//! (`\` at the end of a line) are not supported; if only some corners carry normals, normals are
//! dropped for the whole mesh (flat shading), and corners without a `vt` get uv (0, 0).
use super::load::{read_file, LoadError, MeshData};
use crate::math::{Vec2, Vec3};
use crate::plugin::{declare, Args, SceneError};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::path::Path;

declare!(PLUGIN: super::Parts, crate::math::Transform = Shape "obj" []
    "Wavefront OBJ triangle mesh"
    [super::load::MESH_FILE, &[super::load::flip_tex_coords(true)], super::PLACEMENT] load);

fn load(a: &mut Args, parent: crate::math::Transform) -> Result<super::Parts, SceneError> {
    super::load::mesh_file(a, &parent, super::load::MeshFile::Obj)
}

/// Reads an OBJ file.
pub(crate) fn read_obj(path: &Path) -> Result<MeshData, LoadError> {
    let bytes = read_file(path)?;
    parse_obj(&bytes, path)
}

/// A fast multiplicative hasher for the (v, vt, vn) keys; they are not attacker-chosen.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    fn write_u32(&mut self, x: u32) {
        self.write_u64(x as u64);
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

const NONE: u32 = u32::MAX;

/// Parses OBJ text; `path` only names the source in errors.
pub(crate) fn parse_obj(bytes: &[u8], path: &Path) -> Result<MeshData, LoadError> {
    let err = |line: usize, message: String| LoadError::Syntax {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut pos: Vec<Vec3> = Vec::new();
    let mut tex: Vec<Vec2> = Vec::new();
    let mut nrm: Vec<Vec3> = Vec::new();
    let mut out = MeshData::default();
    let mut out_uv: Vec<Vec2> = Vec::new();
    let mut out_n: Vec<Vec3> = Vec::new();
    let (mut any_uv, mut any_n, mut all_n) = (false, false, true);
    let mut map: HashMap<[u32; 3], u32, BuildHasherDefault<KeyHasher>> = HashMap::default();
    let mut face: Vec<u32> = Vec::with_capacity(8);

    for (li, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line_no = li + 1;
        let line = match raw.iter().position(|&b| b == b'#') {
            Some(k) => &raw[..k],
            None => raw,
        };
        let mut toks = line
            .split(|&b| b == b' ' || b == b'\t' || b == b'\r')
            .filter(|t| !t.is_empty());
        let Some(key) = toks.next() else { continue };
        match key {
            b"v" | b"vn" => {
                let mut c = [0.0f32; 3];
                for (k, slot) in c.iter_mut().enumerate() {
                    let t = toks.next().ok_or_else(|| {
                        err(
                            line_no,
                            format!("`{}` needs 3 coordinates, found {k}", show(key)),
                        )
                    })?;
                    *slot = parse_f32(t).ok_or_else(|| {
                        err(line_no, format!("expected a number, found `{}`", show(t)))
                    })?;
                }
                if key == b"v" {
                    pos.push(Vec3::from(c));
                } else {
                    nrm.push(Vec3::from(c));
                }
            }
            b"vt" => {
                let mut c = [0.0f32; 2];
                for (k, slot) in c.iter_mut().enumerate() {
                    match toks.next() {
                        Some(t) => {
                            *slot = parse_f32(t).ok_or_else(|| {
                                err(line_no, format!("expected a number, found `{}`", show(t)))
                            })?
                        }
                        None if k == 1 => break,
                        None => return Err(err(line_no, "`vt` needs a coordinate".into())),
                    }
                }
                tex.push(Vec2::from(c));
            }
            b"f" => {
                face.clear();
                for t in toks {
                    let mut parts = t.split(|&b| b == b'/');
                    let mut idx = [NONE; 3];
                    let counts = [pos.len(), tex.len(), nrm.len()];
                    let names = ["vertex", "texture coordinate", "normal"];
                    for (k, slot) in idx.iter_mut().enumerate() {
                        let Some(p) = parts.next() else { break };
                        if p.is_empty() && k > 0 {
                            continue;
                        }
                        let i = parse_i64(p).ok_or_else(|| {
                            err(
                                line_no,
                                format!("expected a face index, found `{}`", show(t)),
                            )
                        })?;
                        let n = counts[k] as i64;
                        let r = if i > 0 { i - 1 } else { n + i };
                        if i == 0 || r < 0 || r >= n {
                            return Err(err(
                                line_no,
                                format!(
                                    "{} index {i} is out of range (1..={n} defined so far)",
                                    names[k]
                                ),
                            ));
                        }
                        *slot = r as u32;
                    }
                    if parts.next().is_some() {
                        return Err(err(line_no, format!("malformed face corner `{}`", show(t))));
                    }
                    any_uv |= idx[1] != NONE;
                    any_n |= idx[2] != NONE;
                    all_n &= idx[2] != NONE;
                    let next = out.positions.len() as u32;
                    let v = *map.entry(idx).or_insert(next);
                    if v == next {
                        out.positions.push(pos[idx[0] as usize]);
                        out_uv.push(if idx[1] == NONE {
                            Vec2::ZERO
                        } else {
                            tex[idx[1] as usize]
                        });
                        out_n.push(if idx[2] == NONE {
                            Vec3::ZERO
                        } else {
                            nrm[idx[2] as usize]
                        });
                    }
                    face.push(v);
                }
                if face.len() < 3 {
                    return Err(err(
                        line_no,
                        format!("a face needs at least 3 corners, found {}", face.len()),
                    ));
                }
                for k in 1..face.len() - 1 {
                    out.indices.push([face[0], face[k], face[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if out.indices.is_empty() {
        return Err(LoadError::Empty {
            path: path.to_path_buf(),
        });
    }
    if any_uv {
        out.uvs = Some(out_uv);
    }
    if any_n && all_n {
        out.normals = Some(out_n);
    }
    Ok(out)
}

fn show(t: &[u8]) -> String {
    String::from_utf8_lossy(&t[..t.len().min(40)]).into_owned()
}

/// Parses a float token (Rust's parser is correctly rounded and fast).
pub(crate) fn parse_f32(t: &[u8]) -> Option<f32> {
    std::str::from_utf8(t).ok()?.parse::<f32>().ok()
}

/// Parses a signed decimal integer without allocating.
fn parse_i64(t: &[u8]) -> Option<i64> {
    let (neg, digits) = match t.first()? {
        b'-' => (true, &t[1..]),
        b'+' => (false, &t[1..]),
        _ => (false, t),
    };
    if digits.is_empty() || digits.len() > 18 {
        return None;
    }
    let mut v: i64 = 0;
    for &b in digits {
        if !b.is_ascii_digit() {
            return None;
        }
        v = v * 10 + (b - b'0') as i64;
    }
    Some(if neg { -v } else { v })
}

#[cfg(test)]
#[path = "obj_tests.rs"]
pub(crate) mod tests;
