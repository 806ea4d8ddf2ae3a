use super::*;
use flate2::write::ZlibEncoder;
use flate2::Compression;
use std::io::Write;

/// One mesh to write.
#[derive(Clone)]
struct Mesh {
    name: &'static str,
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    uvs: Option<Vec<[f32; 2]>>,
    colours: bool,
    indices: Vec<[u32; 3]>,
}

fn quad(z: f32) -> Mesh {
    Mesh {
        name: "quad",
        positions: vec![[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]],
        normals: Some(vec![[0.0, 0.0, 1.0]; 4]),
        uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.25], [0.0, 0.25]]),
        colours: false,
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}

fn tri() -> Mesh {
    Mesh {
        name: "",
        positions: vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 3.0, 0.5]],
        normals: None,
        uvs: None,
        colours: true,
        indices: vec![[2, 1, 0]],
    }
}

/// Writes meshes in Mitsuba's serialized layout (see the module header).
fn encode(meshes: &[Mesh], version: u16, double: bool) -> Vec<u8> {
    let mut out = Vec::new();
    let mut offsets = Vec::new();
    for m in meshes {
        offsets.push(out.len() as u64);
        out.extend(MAGIC.to_le_bytes());
        out.extend(version.to_le_bytes());
        let mut raw = Vec::new();
        let mut flags = if double { DOUBLE_PRECISION } else { 0x1000 };
        flags |= m.normals.as_ref().map_or(0, |_| HAS_NORMALS);
        flags |= m.uvs.as_ref().map_or(0, |_| HAS_TEXCOORDS);
        flags |= if m.colours { HAS_COLORS } else { 0 };
        raw.extend(flags.to_le_bytes());
        if version == 4 {
            raw.extend(m.name.bytes());
            raw.push(0);
        }
        raw.extend((m.positions.len() as u64).to_le_bytes());
        raw.extend((m.indices.len() as u64).to_le_bytes());
        let mut reals = |vals: &mut dyn Iterator<Item = f32>| {
            for v in vals {
                if double {
                    raw.extend((v as f64).to_le_bytes());
                } else {
                    raw.extend(v.to_le_bytes());
                }
            }
        };
        reals(&mut m.positions.iter().flatten().copied());
        if let Some(n) = &m.normals {
            reals(&mut n.iter().flatten().copied());
        }
        if let Some(uv) = &m.uvs {
            reals(&mut uv.iter().flatten().copied());
        }
        if m.colours {
            reals(&mut std::iter::repeat_n(0.5, 3 * m.positions.len()));
        }
        for t in &m.indices {
            for i in t {
                raw.extend(i.to_le_bytes());
            }
        }
        let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
        z.write_all(&raw).unwrap();
        out.extend(z.finish().unwrap());
    }
    for o in &offsets {
        if version == 4 {
            out.extend(o.to_le_bytes());
        } else {
            out.extend((*o as u32).to_le_bytes());
        }
    }
    out.extend((meshes.len() as u32).to_le_bytes());
    out
}

fn same(d: &MeshData, m: &Mesh) {
    let v3 = |v: &[[f32; 3]]| v.iter().map(|&a| Vec3::from(a)).collect::<Vec<_>>();
    assert_eq!(d.positions, v3(&m.positions));
    assert_eq!(d.normals, m.normals.as_deref().map(v3));
    assert_eq!(
        d.uvs,
        m.uvs
            .as_ref()
            .map(|u| u.iter().map(|&a| Vec2::from(a)).collect())
    );
    assert_eq!(d.indices, m.indices);
}

const P: &str = "m.serialized";

#[test]
fn every_mesh_of_a_file_reads_back_exactly() {
    let meshes = [quad(0.0), tri(), quad(2.0)];
    for version in [3, 4] {
        for double in [false, true] {
            let bytes = encode(&meshes, version, double);
            for (i, m) in meshes.iter().enumerate() {
                let d = parse_serialized(&bytes, Path::new(P), i as u32)
                    .unwrap_or_else(|e| panic!("v{version} double={double} #{i}: {e}"));
                same(&d, m);
            }
        }
    }
}

#[test]
fn bad_headers_and_indices_are_located_errors() {
    let good = encode(&[quad(0.0), tri()], 4, false);
    let err = |bytes: &[u8], i: u32| {
        parse_serialized(bytes, Path::new(P), i)
            .unwrap_err()
            .to_string()
    };
    let mut magic = good.clone();
    magic[0] = 0x1D;
    assert!(err(&magic, 0).contains("0x041D"), "{}", err(&magic, 0));
    let mut v5 = good.clone();
    v5[2] = 5;
    assert!(err(&v5, 0).contains("version 5"));
    let mut v9 = good.clone();
    v9[2] = 9;
    assert!(err(&v9, 0).contains("version 9"));
    let e = err(&good, 2);
    assert!(
        e.contains("shape_index 2") && e.contains("2 meshes") && e.starts_with(P),
        "{e}"
    );
    let mut table = good.clone();
    let n = table.len();
    table[n - 4..].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(err(&table, 1).contains("longer than the file"));
}

#[test]
fn truncated_or_corrupt_files_never_panic() {
    let good = encode(&[quad(0.0), tri()], 4, false);
    for cut in 0..good.len() {
        let _ = parse_serialized(&good[..cut], Path::new(P), 0);
        let _ = parse_serialized(&good[..cut], Path::new(P), 1);
    }
    let mut rng = crate::math::Pcg32::new(4, 2);
    for _ in 0..2000 {
        let mut b = good.clone();
        let i = (rng.next_f32() * b.len() as f32) as usize % b.len();
        b[i] ^= 1 << (rng.next_f32() * 8.0) as u32;
        let _ = parse_serialized(&b, Path::new(P), 0);
        let _ = parse_serialized(&b, Path::new(P), 1);
    }
}

#[test]
fn huge_counts_fail_without_a_huge_allocation() {
    let mut m = tri();
    m.colours = false;
    let mut bytes = Vec::new();
    bytes.extend(MAGIC.to_le_bytes());
    bytes.extend(3u16.to_le_bytes());
    let mut raw = Vec::new();
    raw.extend(0x1000u32.to_le_bytes());
    raw.extend((1u64 << 31).to_le_bytes());
    raw.extend((1u64 << 40).to_le_bytes());
    raw.extend([0u8; 64]);
    let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
    z.write_all(&raw).unwrap();
    bytes.extend(z.finish().unwrap());
    let e = parse_serialized(&bytes, Path::new(P), 0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("ends inside the positions"), "{e}");
}
