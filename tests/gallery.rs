//! `ophis gallery` end to end in CI size (`--quick`: 8×8-pixel renders at 1 spp): every sheet
//! is rendered and written to the `--out` folder as a PNG of the expected grid.

use ophis::image_io::read_image;
use std::process::Command;

/// A sheet as `ophis gallery --list` prints it: name, rows and columns.
struct Listed {
    name: String,
    rows: usize,
    cols: usize,
}

/// The sheets, from `ophis gallery --list` ("name  title (R x C)").
fn sheets() -> Vec<Listed> {
    let run = Command::new(env!("CARGO_BIN_EXE_ophis"))
        .args(["gallery", "--list"])
        .output()
        .expect("runs ophis");
    let text = String::from_utf8(run.stdout).unwrap();
    text.lines()
        .map(|l| {
            let name = l.split_whitespace().next().unwrap().to_string();
            let grid = &l[l.rfind('(').unwrap() + 1..l.rfind(')').unwrap()];
            let (r, c) = grid.split_once(" x ").unwrap();
            Listed {
                name,
                rows: r.trim().parse().unwrap(),
                cols: c.trim().parse().unwrap(),
            }
        })
        .collect()
}

#[test]
fn gallery_quick_writes_every_sheet() {
    let out = std::env::temp_dir().join(format!("ophis-gallery-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let run = Command::new(env!("CARGO_BIN_EXE_ophis"))
        .args(["gallery", "--quick", "--out"])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("runs ophis");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "ophis gallery failed:\n{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
    for s in sheets() {
        let path = out.join(format!("{}.png", s.name));
        let img = read_image(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        // 24-pixel cells with 6-pixel gaps: at least the grid, plus captions.
        assert!(img.width >= s.cols * 30, "{}: {} wide", s.name, img.width);
        assert!(img.height >= s.rows * 30, "{}: {} high", s.name, img.height);
        // Progress names each sheet.
        assert!(stderr.contains(&s.name), "no progress line for {}", s.name);
        // The cells hold renders, not the grey of a missing image: some pixel is neither
        // white background nor 50 % grey.
        let rendered = img.data.iter().any(|p| {
            p.iter()
                .any(|&v| v > 0.02 && v < 0.9 && (v - 0.5).abs() > 0.05)
        });
        assert!(rendered, "{}: no rendered pixels", s.name);
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn gallery_rejects_an_unknown_sheet() {
    let run = Command::new(env!("CARGO_BIN_EXE_ophis"))
        .args(["gallery", "--quick", "--only", "no-such-sheet", "--out"])
        .arg(std::env::temp_dir().join("ophis-gallery-unused"))
        .output()
        .expect("runs ophis");
    assert!(!run.status.success());
    assert!(String::from_utf8_lossy(&run.stderr).contains("no-such-sheet"));
}
