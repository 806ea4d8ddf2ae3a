use super::*;
use crate::shape::obj::tests::temp_dir;

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let p = temp_dir("ply").join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// The unit square as a quad plus a triangle, in every variant below.
const POS: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.5, 0.5, 1.0],
];

fn check(d: &MeshData, with_attrs: bool) {
    assert_eq!(d.positions.len(), 5);
    assert_eq!(d.positions[2], Vec3::new(1.0, 1.0, 0.0));
    assert_eq!(d.indices, vec![[0, 1, 2], [0, 2, 3], [0, 1, 4]]);
    if with_attrs {
        let n = d.normals.as_ref().unwrap();
        assert_eq!(n[4], Vec3::new(0.0, 0.0, 1.0));
        let uv = d.uvs.as_ref().unwrap();
        assert_eq!(uv[2], Vec2::new(1.0, 1.0));
    }
}

#[test]
fn reads_ascii_with_normals_uvs_and_skipped_elements() {
    let mut s = String::from(
        "ply\nformat ascii 1.0\ncomment made by a test\nelement vertex 5\nproperty float x\n\
         property float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property float u\nproperty float v\nproperty list uchar int extra\n\
         element material 1\nproperty uchar r\nelement face 2\nproperty uchar flags\n\
         property list uchar int vertex_indices\nend_header\n",
    );
    for p in POS {
        s.push_str(&format!(
            "{} {} {} 0 0 1 {} {} 2 7 8\n",
            p[0], p[1], p[2], p[0], p[1]
        ));
    }
    s.push_str("255\n3 4 0 1 2 3\n0 3 0 1 4\n");
    check(&parse_ply(s.as_bytes(), Path::new("a.ply")).unwrap(), true);
}

/// A binary file: vertices as (x y z) of `pos_ty`, optional (nx ny nz s t) floats, faces with
/// an int flag before a `count_ty`/`index_ty` list.
fn binary(big: bool, pos_ty: &str, count_ty: &str, index_ty: &str, attrs: bool) -> Vec<u8> {
    let fmt = if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut h = format!("ply\nformat {fmt} 1.0\nelement vertex 5\n");
    for c in ["x", "y", "z"] {
        h.push_str(&format!("property {pos_ty} {c}\n"));
    }
    if attrs {
        for c in ["nx", "ny", "nz", "s", "t"] {
            h.push_str(&format!("property float32 {c}\n"));
        }
    }
    h.push_str(&format!(
        "element face 2\nproperty int flags\nproperty list {count_ty} {index_ty} vertex_index\nend_header\n"
    ));
    let mut b = h.into_bytes();
    let put = |b: &mut Vec<u8>, v: f64, ty: &str| {
        let mut bytes: Vec<u8> = match ty {
            "float" | "float32" => (v as f32).to_le_bytes().to_vec(),
            "double" => v.to_le_bytes().to_vec(),
            "uchar" | "uint8" => vec![v as u8],
            "ushort" => (v as u16).to_le_bytes().to_vec(),
            "short" => (v as i16).to_le_bytes().to_vec(),
            "int" => (v as i32).to_le_bytes().to_vec(),
            "uint" => (v as u32).to_le_bytes().to_vec(),
            _ => unreachable!("{ty}"),
        };
        if big {
            bytes.reverse();
        }
        b.extend(bytes);
    };
    for p in POS {
        for c in p {
            put(&mut b, c, pos_ty);
        }
        if attrs {
            for c in [0.0, 0.0, 1.0, p[0], p[1]] {
                put(&mut b, c, "float32");
            }
        }
    }
    for face in [&[0.0, 1.0, 2.0, 3.0][..], &[0.0, 1.0, 4.0]] {
        put(&mut b, -1.0, "int");
        put(&mut b, face.len() as f64, count_ty);
        for &i in face {
            put(&mut b, i, index_ty);
        }
    }
    b
}

#[test]
fn reads_binary_little_and_big_endian_with_any_types() {
    for big in [false, true] {
        for (pos_ty, ct, it, attrs) in [
            ("float", "uchar", "int", true),
            ("double", "ushort", "uint", false),
            ("float32", "uint8", "short", true),
        ] {
            let b = binary(big, pos_ty, ct, it, attrs);
            let d = parse_ply(&b, Path::new("b.ply")).unwrap_or_else(|e| panic!("{e}"));
            check(&d, attrs);
        }
    }
}

#[test]
fn loads_through_the_mesh_constructor() {
    let p = write("c.ply", &binary(false, "float", "uchar", "int", true));
    let opts = crate::shape::MeshOptions::default();
    let t = crate::math::Transform::IDENTITY;
    let m = crate::shape::TriangleMesh::from_data(read_ply(&p).unwrap(), &p, &t, &opts).unwrap();
    assert_eq!(m.triangle_count(), 3);
    assert!(m.has_vertex_normals() && m.has_uvs());
}

fn err(name: &str, bytes: &[u8]) -> String {
    read_ply(&write(name, bytes)).unwrap_err().to_string()
}

#[test]
fn truncated_and_garbage_binary_give_errors() {
    let full = binary(false, "float", "uchar", "int", false);
    // Cut at every length inside the body: always an error naming the file, never a panic.
    let body = full.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    for cut in body..full.len() {
        let e = err("cut.ply", &full[..cut]);
        assert!(
            e.contains("cut.ply") && e.contains("truncated"),
            "{cut}: {e}"
        );
    }
    // A huge declared count is rejected before allocating.
    let huge =
        String::from_utf8_lossy(&full).replace("element vertex 5", "element vertex 4000000000");
    let e = err("huge.ply", huge.as_bytes());
    assert!(e.contains("huge.ply") && e.contains("4000000000"), "{e}");
    // Flipping bytes of the body yields an error or a mesh, never a panic.
    let mut rng = crate::math::Pcg32::new(3, 3);
    for _ in 0..500 {
        let mut g = full.clone();
        let k = body + (rng.next_u32() as usize) % (full.len() - body);
        g[k] = rng.next_u32() as u8;
        let _ = parse_ply(&g, Path::new("g.ply"));
    }
}

#[test]
fn header_and_data_errors_name_file_and_line() {
    let head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let typo = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty flot x\nend_header\n";
    let no_end = b"ply\nformat ascii 1.0\nelement vertex 1\n";
    let nan = format!("{head}0 0 0\n1 0 0\n0 1 zero\n3 0 1 2\n");
    let index = format!("{head}0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n");
    let no_face = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                    property float z\nend_header\n0 0 0\n";
    let no_xyz = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n";
    // The file, its bytes, and what the error must contain: where and what.
    let cases: [(&str, &[u8], &str, &str); 7] = [
        (
            "garbage.ply",
            b"\x00\x01binary junk",
            "garbage.ply:1:",
            "not a PLY",
        ),
        ("type.ply", typo, "type.ply:4:", "unknown property type"),
        ("nohdr.ply", no_end, "nohdr.ply", "end_header"),
        ("num.ply", nan.as_bytes(), "num.ply:12:", "`zero`"),
        ("idx.ply", index.as_bytes(), "idx.ply:13:", "out of range"),
        ("noface.ply", no_face, "noface.ply", "no faces"),
        ("noxyz.ply", no_xyz, "noxyz.ply:3:", "x, y and z"),
    ];
    for (name, bytes, at, says) in cases {
        let e = err(name, bytes);
        assert!(e.contains(at) && e.contains(says), "{e}");
    }
    let dir = temp_dir("ply");
    assert!(read_ply(&dir)
        .unwrap_err()
        .to_string()
        .contains("is a directory"));
    let e = read_ply(&dir.join("missing.ply")).unwrap_err().to_string();
    assert!(
        e.contains("missing.ply") && e.contains("cannot read"),
        "{e}"
    );
}

/// A random triangle mesh written as binary (vertex x y z nx ny nz u v as floats; faces as a
/// uchar-counted list of `index_ty`) and as ASCII, which only the general reader reads.
fn random_mesh(
    nv: usize,
    nf: usize,
    big: bool,
    index_ty: &str,
    quad_at: Option<usize>,
) -> (Vec<u8>, String) {
    let mut rng = crate::math::Pcg32::new(nv as u64, nf as u64);
    let fmt = if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let head = |f: &str, it: &str| {
        format!(
            "ply\nformat {f} 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\n\
             property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
             property float u\nproperty float v\nelement face {nf}\n\
             property list uchar {it} vertex_indices\nend_header\n"
        )
    };
    // Floats and indices are both 4 bytes wide.
    let word = |w: u32| {
        if big {
            w.to_be_bytes()
        } else {
            w.to_le_bytes()
        }
    };
    let mut b = head(fmt, index_ty).into_bytes();
    let mut a = head("ascii", index_ty);
    for _ in 0..nv {
        for _ in 0..8 {
            let x = rng.next_f32() * 4.0 - 2.0;
            b.extend(word(x.to_bits()));
            a.push_str(&format!("{x:?} "));
        }
        a.push('\n');
    }
    for f in 0..nf {
        let n = if quad_at == Some(f) { 4 } else { 3 };
        b.push(n);
        a.push_str(&format!("{n}"));
        for _ in 0..n {
            let i = rng.next_u32() % nv as u32;
            b.extend(word(i));
            a.push_str(&format!(" {i}"));
        }
        a.push('\n');
    }
    (b, a)
}

#[test]
fn binary_fast_paths_match_the_general_reader() {
    // Large enough for the parallel decoding; a quad sends the faces to the general reader.
    for (nv, nf, big, it, quad) in [
        (40_000, 70_000, false, "int", None),
        (1_000, 3_000, true, "uint", None),
        (50_000, 40_000, false, "uint", Some(39_999)),
        (200, 300, false, "int", Some(0)),
    ] {
        let (b, a) = random_mesh(nv, nf, big, it, quad);
        let fast = parse_ply(&b, Path::new("f.ply")).unwrap();
        let general = parse_ply(a.as_bytes(), Path::new("a.ply")).unwrap();
        assert_eq!(fast.indices.len(), nf + quad.is_some() as usize);
        assert!(fast == general, "{nv} {nf} {big} {it} {quad:?}");
    }
    // A bad index in a triangle table is reported by the general reader, at its byte.
    let (mut b, _) = random_mesh(100, 40_000, false, "int", None);
    let at = b.len() - 4;
    b[at..].copy_from_slice(&100i32.to_le_bytes());
    let e = parse_ply(&b, Path::new("bad.ply")).unwrap_err().to_string();
    assert!(
        e.contains("bad.ply") && e.contains("vertex index 100 is out of range"),
        "{e}"
    );
    assert!(e.contains(&format!("byte {}", b.len())), "{e}");
}
