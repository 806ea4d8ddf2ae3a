//! Fast paths of the PLY reader for binary files (load speed only; results are those of the
//! general reader in `ply.rs`, which handles everything else and reports all errors).
//!
//! - A `vertex` element whose properties all have fixed sizes is a table of fixed-size records:
//!   the used properties are decoded at their offsets, records in parallel.
//! - A `face` element whose only property is a `uchar`-counted list of `int`/`uint` indices is,
//!   when every face is a triangle, a table of 13-byte records: decoded in parallel, each record
//!   checked (count 3, indices in range). Any other record sends the whole element back to the
//!   general reader, which triangulates polygons and words the error for a bad index.
use super::{Body, Element, Format, Ty};
use crate::math::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Below this many records an element is decoded on the current thread.
const PARALLEL_MIN: usize = 1 << 15;

/// The value of type `ty` at the start of `b` (big-endian if `big`), as an f64: how both the
/// general reader and the fast paths convert a binary value.
#[inline(always)]
pub(super) fn decode(ty: Ty, b: &[u8], big: bool) -> f64 {
    let n = ty.size();
    let mut a = [0u8; 8];
    a[..n].copy_from_slice(&b[..n]);
    if big {
        a[..n].reverse();
    }
    match ty {
        Ty::I8 => a[0] as i8 as f64,
        Ty::U8 => a[0] as f64,
        Ty::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
        Ty::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
        Ty::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
        Ty::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
        Ty::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
        Ty::F64 => f64::from_le_bytes(a),
    }
}

/// Maps `f` over the `count` records of `size` bytes at the start of `data`, in parallel when
/// there are many.
fn records<T: Send>(
    data: &[u8],
    size: usize,
    count: usize,
    f: impl Fn(&[u8]) -> T + Sync + Send,
) -> Vec<T> {
    let data = &data[..size * count];
    if count >= PARALLEL_MIN {
        data.par_chunks_exact(size).map(f).collect()
    } else {
        data.chunks_exact(size).map(f).collect()
    }
}

/// Decoded vertex arrays and the bytes they took.
pub(super) struct Vertices {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
    pub bytes: usize,
}

/// The `vertex` element `el` at the body's position, if its records have a fixed size;
/// `slot[k]` is the record slot of property k (0..3 position, 3..6 normal, 6..8 uv, or
/// `usize::MAX` for an unused property).
pub(super) fn vertices(
    body: &Body,
    el: &Element,
    slot: &[usize],
    has_n: bool,
    has_uv: bool,
) -> Option<Vertices> {
    if body.format == Format::Ascii || el.props.iter().any(|p| p.list.is_some()) {
        return None;
    }
    let size: usize = el.props.iter().map(|p| p.ty.size()).sum();
    let bytes = size.checked_mul(el.count)?;
    if size == 0 || bytes > body.remaining() {
        return None;
    }
    // (offset, type) of each record slot.
    let mut at = [(0usize, Ty::F32); 8];
    let mut off = 0;
    for (p, &s) in el.props.iter().zip(slot) {
        if s != usize::MAX {
            at[s] = (off, p.ty);
        }
        off += p.ty.size();
    }
    let big = body.format == Format::Big;
    let data = &body.data[body.pos..];
    let get = |r: &[u8], s: usize| decode(at[s].1, &r[at[s].0..], big) as f32;
    let v3 = |r: &[u8], s: usize| Vec3::new(get(r, s), get(r, s + 1), get(r, s + 2));
    Some(Vertices {
        positions: records(data, size, el.count, |r| v3(r, 0)),
        normals: has_n.then(|| records(data, size, el.count, |r| v3(r, 3))),
        uvs: has_uv.then(|| records(data, size, el.count, |r| Vec2::new(get(r, 6), get(r, 7)))),
        bytes,
    })
}

/// The `face` element `el` at the body's position, if it is a table of triangles with valid
/// indices (see the module header); the triangles and the bytes they took.
pub(super) fn triangles(
    body: &Body,
    el: &Element,
    n_vertices: usize,
) -> Option<(Vec<[u32; 3]>, usize)> {
    let [p] = el.props.as_slice() else {
        return None;
    };
    let named = p.name == "vertex_indices" || p.name == "vertex_index";
    if body.format == Format::Ascii
        || !named
        || p.list != Some(Ty::U8)
        || !matches!(p.ty, Ty::I32 | Ty::U32)
    {
        return None;
    }
    let bytes = 13usize.checked_mul(el.count)?;
    if bytes > body.remaining() {
        return None;
    }
    let (big, ty) = (body.format == Format::Big, p.ty);
    let ok = AtomicBool::new(true);
    let tris = records(&body.data[body.pos..], 13, el.count, |r| {
        let index = |k: usize| {
            let v = decode(ty, &r[1 + 4 * k..], big);
            (v >= 0.0 && (v as usize) < n_vertices).then_some(v as u32)
        };
        match (r[0], index(0), index(1), index(2)) {
            (3, Some(a), Some(b), Some(c)) => [a, b, c],
            _ => {
                ok.store(false, Ordering::Relaxed);
                [0; 3]
            }
        }
    });
    ok.into_inner().then_some((tris, bytes))
}
