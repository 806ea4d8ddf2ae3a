use super::*;
use crate::math::Transform;
use crate::shape::{MeshOptions, TriangleMesh};
use std::path::PathBuf;

/// A fresh directory under the system temp dir, unique per test.
pub(crate) fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ophis-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(tag: &str, name: &str, text: &str) -> PathBuf {
    let p = temp_dir(tag).join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn err_text(path: &Path) -> String {
    read_obj(path).unwrap_err().to_string()
}

#[test]
fn reads_all_corner_forms_quads_and_negative_indices() {
    let text =
        "# a quad and a triangle\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\r\n\
                vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\ng grp\ns off\nusemtl m\n\
                f 1/1/1 2/2/1 3/3/1 4/4/1\nf -4//-1 -3//-1 -1//-1\n";
    let p = write("obj-forms", "a.obj", text);
    let d = read_obj(&p).unwrap();
    assert_eq!(d.indices.len(), 3);
    // The quad's four corners plus three (v, vn)-only corners are distinct vertices.
    assert_eq!(d.positions.len(), 7);
    assert_eq!(d.indices[0], [0, 1, 2]);
    assert_eq!(d.indices[1], [0, 2, 3]);
    assert_eq!(
        d.positions[d.indices[2][2] as usize],
        Vec3::new(0.0, 1.0, 0.0)
    );
    assert!(d.normals.is_some());
    let uvs = d.uvs.as_ref().unwrap();
    assert_eq!(uvs[2], Vec2::new(1.0, 1.0));
    // Through the mesh constructor with Mitsuba's default v flip.
    let opts = MeshOptions::default();
    let m =
        TriangleMesh::from_data(read_obj(&p).unwrap(), &p, &Transform::IDENTITY, &opts).unwrap();
    assert_eq!(m.triangle_count(), 3);
}

#[test]
fn shared_corners_are_deduplicated() {
    let p = write(
        "obj-dedup",
        "b.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
    );
    let d = read_obj(&p).unwrap();
    assert_eq!(d.positions.len(), 4);
    assert!(d.uvs.is_none() && d.normals.is_none());
    assert_eq!(d.indices, vec![[0, 1, 2], [1, 3, 2]]);
}

#[test]
fn errors_name_the_file_and_line() {
    let cases = [
        (
            "bad-number.obj",
            "v 0 0 0\nv 1 x 0\n",
            ":2:",
            "expected a number",
        ),
        (
            "range.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 7\n",
            ":5:",
            "out of range",
        ),
        (
            "zero.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
            ":4:",
            "out of range",
        ),
        (
            "neg.obj",
            "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n",
            ":3:",
            "out of range",
        ),
        ("short.obj", "v 0 0\n", ":1:", "3 coordinates"),
        ("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", ":3:", "at least 3"),
        (
            "vt.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n",
            ":4:",
            "texture coordinate",
        ),
    ];
    for (name, text, line, what) in cases {
        let p = write("obj-errors", name, text);
        let e = err_text(&p);
        assert!(
            e.contains(name) && e.contains(line) && e.contains(what),
            "{e}"
        );
    }
    let empty = write("obj-errors", "empty.obj", "# nothing\nv 0 0 0\n");
    let e = err_text(&empty);
    assert!(e.contains("empty.obj") && e.contains("no faces"), "{e}");
    let dir = temp_dir("obj-errors");
    let e = err_text(&dir);
    assert!(e.contains("is a directory"), "{e}");
    let missing = dir.join("missing.obj");
    let e = err_text(&missing);
    assert!(
        e.contains("missing.obj") && e.contains("cannot read"),
        "{e}"
    );
    let garbage = dir.join("garbage.obj");
    std::fs::write(&garbage, [0xffu8, 0x00, 0x13, b'\n', b'f', b' ', 0xfe]).unwrap();
    let e = err_text(&garbage);
    assert!(e.contains("garbage.obj:2:"), "{e}");
}

#[test]
fn a_large_grid_parses_quickly() {
    // 2·200² triangles; catches accidental quadratic behaviour, not absolute speed.
    let n = 200;
    let mut s = String::new();
    for j in 0..=n {
        for i in 0..=n {
            s.push_str(&format!("v {i} {j} 0.5\n"));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            s.push_str(&format!("f {} {} {} {}\n", a, a + 1, a + n + 2, a + n + 1));
        }
    }
    let d = parse_obj(s.as_bytes(), Path::new("grid.obj")).unwrap();
    assert_eq!(d.indices.len(), 2 * n * n);
    assert_eq!(d.positions.len(), (n + 1) * (n + 1));
}

/// Load time for a one-million-triangle file: `cargo test --lib obj_load_time -- --ignored
/// --nocapture`.
#[test]
#[ignore]
fn obj_load_time_1m() {
    use std::fmt::Write;
    let n = 708;
    let mut s = String::with_capacity(60 << 20);
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            writeln!(s, "v {x} {y} {}", (7.0 * x).sin() * 0.1).unwrap();
            writeln!(s, "vt {x} {y}").unwrap();
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let (b, c, d) = (a + 1, a + n + 2, a + n + 1);
            writeln!(s, "f {a}/{a} {b}/{b} {c}/{c}\nf {a}/{a} {c}/{c} {d}/{d}").unwrap();
        }
    }
    let p = temp_dir("obj-time").join("grid.obj");
    std::fs::write(&p, &s).unwrap();
    let t0 = std::time::Instant::now();
    let d = read_obj(&p).unwrap();
    println!(
        "{} triangles, {} MB: {:?}",
        d.indices.len(),
        s.len() >> 20,
        t0.elapsed()
    );
    assert_eq!(d.indices.len(), 2 * n * n);
}
