//! Long-render robustness through the `ophis` binary: interruption by SIGINT/SIGTERM writes a
//! correctly counted image, checkpoints resume to the uninterrupted result, `merge` combines
//! seeds by their sample counts.

use ophis::image_io::{read_exr_metadata, read_image, RgbImage};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn ophis() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ophis"))
}

fn reference() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/reference.xml")
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ophis-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn ok(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "ophis failed: {err}");
    err
}

fn meta(path: &Path, key: &str) -> String {
    read_exr_metadata(path)
        .unwrap()
        .into_iter()
        .find(|(k, _)| k == key)
        .unwrap_or_else(|| panic!("{} lacks {key}", path.display()))
        .1
}

/// Sends `signal` to a running render once its first checkpoint exists (so its handler is
/// installed and it has samples), and checks what it leaves behind.
fn interrupt_with(signal: &str) {
    let dir = temp(signal);
    let out = dir.join("slow");
    let child = ophis()
        .arg("render")
        .arg(reference())
        .args(["-Dspp=1000000", "--checkpoint", "0.05", "-q", "-o"])
        .arg(&out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let state = dir.join("slow.ophis-state");
    let t0 = Instant::now();
    while !state.exists() {
        assert!(t0.elapsed() < Duration::from_secs(60), "no checkpoint");
        std::thread::sleep(Duration::from_millis(20));
    }
    let st = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(st.success());
    let t1 = Instant::now();
    let res = child.wait_with_output().unwrap();
    assert!(t1.elapsed() < Duration::from_secs(30), "slow to stop");
    let err = String::from_utf8_lossy(&res.stderr);
    assert!(
        !res.status.success(),
        "interrupted render must exit non-zero"
    );
    assert_eq!(res.status.code(), Some(1), "{err}");
    let exr = dir.join("slow.exr");
    assert!(exr.exists() && dir.join("slow.png").exists(), "{err}");
    // "render interrupted; kept N samples (...)"
    let kept: u64 = err
        .split("kept ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no sample count in: {err}"));
    assert!(kept > 0);
    assert_eq!(meta(&exr, "ophis.samples"), kept.to_string(), "{err}");
    // Normalised per pixel: every pixel is a finite, plausible mean (not a sum).
    let img = read_image(&exr).unwrap();
    let mean: f64 = img.data.iter().map(|p| p[1] as f64).sum::<f64>() / img.data.len() as f64;
    assert!(mean > 0.01 && mean < 10.0, "mean {mean}");
    // The state written on interruption holds the same samples.
    let st = ophis::checkpoint::RenderState::read(&state).unwrap();
    assert_eq!(st.film.total_weight() as u64, kept);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sigint_writes_the_samples_so_far_and_exits_non_zero() {
    interrupt_with("INT");
}

#[test]
fn sigterm_writes_the_samples_so_far_and_exits_non_zero() {
    interrupt_with("TERM");
}

#[test]
fn time_budget_then_resume_equals_one_uninterrupted_render() {
    let dir = temp("resume");
    let whole = dir.join("whole.exr");
    ok(&ophis()
        .arg("render")
        .arg(reference())
        .args(["-Dspp=64", "--seed", "3", "-q", "--threads", "2", "-o"])
        .arg(&whole)
        .output()
        .unwrap());
    let part = dir.join("part.exr");
    let err = ok(&ophis()
        .arg("render")
        .arg(reference())
        .args(["-Dspp=64", "--seed", "3", "-q", "--time", "0.001", "-o"])
        .arg(&part)
        .output()
        .unwrap());
    assert!(err.contains("--resume"), "{err}");
    let done: u64 = meta(&part, "ophis.samples").parse().unwrap();
    assert!(
        done < 64 * 48 * 64,
        "the time budget should stop the render early"
    );
    let state = dir.join("part.ophis-state");
    // Changing the seed on resume is refused, naming both values.
    let bad = ophis()
        .args(["render", "--seed", "4", "-q", "--resume"])
        .arg(&state)
        .output()
        .unwrap();
    let msg = String::from_utf8_lossy(&bad.stderr);
    assert!(
        !bad.status.success() && msg.contains("--seed 4 differs from the 3"),
        "{msg}"
    );
    // A different scene is refused.
    let other = dir.join("other.xml");
    std::fs::write(&other, "<scene version=\"3.0.0\"/>").unwrap();
    let bad = ophis()
        .arg("render")
        .arg(&other)
        .args(["-q", "--resume"])
        .arg(&state)
        .output()
        .unwrap();
    let msg = String::from_utf8_lossy(&bad.stderr);
    assert!(
        !bad.status.success() && msg.contains("not the file it was started from"),
        "{msg}"
    );
    ok(&ophis()
        .args(["render", "-q", "--threads", "1", "--resume"])
        .arg(&state)
        .arg("-o")
        .arg(&part)
        .output()
        .unwrap());
    let a = std::fs::read(&whole).unwrap();
    let b = std::fs::read(&part).unwrap();
    assert!(a == b, "resumed EXR differs from the uninterrupted one");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn exr_is_bit_identical_with_one_or_two_threads_and_any_tile_order() {
    let dir = temp("threads");
    let mut files = Vec::new();
    for (i, (threads, order)) in [("1", "row"), ("2", "reversed"), ("2", "shuffled")]
        .iter()
        .enumerate()
    {
        let p = dir.join(format!("t{i}.exr"));
        ok(&ophis()
            .arg("render")
            .arg(reference())
            .args([
                "-Dspp=4",
                "-q",
                "--threads",
                threads,
                "--tile-order",
                order,
                "-o",
            ])
            .arg(&p)
            .output()
            .unwrap());
        files.push(std::fs::read(&p).unwrap());
    }
    assert!(files[0] == files[1] && files[0] == files[2]);
    let _ = std::fs::remove_dir_all(&dir);
}

fn mse(a: &RgbImage, b: &RgbImage) -> f64 {
    let n = a.data.len() as f64 * 3.0;
    a.data
        .iter()
        .zip(&b.data)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] as f64 - q[c] as f64).powi(2)))
        .sum::<f64>()
        / n
}

#[test]
fn merge_weights_seeds_by_samples_and_reduces_error() {
    let dir = temp("merge");
    let render = |seed: &str, spp: &str, name: &str| {
        let p = dir.join(name);
        ok(&ophis()
            .arg("render")
            .arg(reference())
            .args([&format!("-Dspp={spp}"), "--seed", seed, "-q", "-o"])
            .arg(&p)
            .output()
            .unwrap());
        p
    };
    let a = render("1", "8", "a.exr");
    let b = render("2", "24", "b.exr");
    let truth = read_image(render("100", "512", "ref.exr")).unwrap();
    let m = dir.join("m.exr");
    ok(&ophis()
        .arg("merge")
        .arg(&m)
        .arg(&a)
        .arg(&b)
        .output()
        .unwrap());
    let (ia, ib, im) = (
        read_image(&a).unwrap(),
        read_image(&b).unwrap(),
        read_image(&m).unwrap(),
    );
    for i in 0..im.data.len() {
        for c in 0..3 {
            let want = (8.0 * ia.data[i][c] as f64 + 24.0 * ib.data[i][c] as f64) / 32.0;
            let got = im.data[i][c] as f64;
            assert!(
                (got - want).abs() <= 1e-6 * want.abs().max(1e-3),
                "{i} {got} {want}"
            );
        }
    }
    assert_eq!(meta(&m, "ophis.samples"), (64 * 48 * 32).to_string());
    let (ea, eb, em) = (mse(&ia, &truth), mse(&ib, &truth), mse(&im, &truth));
    assert!(em < ea && em < eb, "merged {em} vs inputs {ea}, {eb}");

    // Files without counts, or of another resolution, are refused by name.
    let png = dir.join("a.png");
    std::fs::write(&png, b"not an exr").unwrap();
    let out = ophis()
        .arg("merge")
        .arg(dir.join("x.exr"))
        .arg(&a)
        .arg(&png)
        .output()
        .unwrap();
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && msg.contains("a.png"), "{msg}");
    let small = dir.join("small.exr");
    let tiny = RgbImage {
        width: 2,
        height: 2,
        data: vec![[0.5; 3]; 4],
    };
    ophis::image_io::write_exr(&small, &tiny, &[("ophis.samples".into(), "4".into())]).unwrap();
    let out = ophis()
        .arg("merge")
        .arg(dir.join("x.exr"))
        .arg(&a)
        .arg(&small)
        .output()
        .unwrap();
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && msg.contains("same resolution"),
        "{msg}"
    );
    let meta_less = dir.join("plain.exr");
    ophis::image_io::write_exr(&meta_less, &ia, &[]).unwrap();
    let out = ophis()
        .arg("merge")
        .arg(dir.join("x.exr"))
        .arg(&a)
        .arg(&meta_less)
        .output()
        .unwrap();
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && msg.contains("no 'ophis.samples'"),
        "{msg}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--stats` reports the wavefront stages' shares (summing to 100 %) and at least the camera
/// ray per sample, changes nothing in the image, and says so when the scalar engine rendered.
#[test]
fn stats_report_the_wavefront_stages_and_leave_the_image_alone() {
    let dir = temp("stats");
    let render = |extra: &[&str], name: &str| {
        let p = dir.join(name);
        let err = ok(&ophis()
            .arg("render")
            .arg(reference())
            .args(["-Dspp=4", "-q", "-o"])
            .arg(&p)
            .args(extra)
            .output()
            .unwrap());
        (err, std::fs::read(&p).unwrap())
    };
    let (plain, image) = render(&[], "plain.exr");
    assert!(!plain.contains("stats:"), "{plain}");
    let (err, with_stats) = render(&["--stats"], "stats.exr");
    assert!(image == with_stats, "--stats changed the image");
    let shares = err
        .lines()
        .find(|l| l.starts_with("stats: wavefront stages"))
        .unwrap_or_else(|| panic!("no stage line in: {err}"));
    let names = ["refill", "trace", "group", "shade", "shadow rays", "retire"];
    let sum: f64 = names
        .iter()
        .map(|n| {
            let at = shares
                .find(&format!(" {n} "))
                .unwrap_or_else(|| panic!("{n}: {shares}"));
            let rest = &shares[at + n.len() + 2..];
            rest[..rest.find(' ').unwrap()].parse::<f64>().unwrap()
        })
        .sum();
    assert!((sum - 100.0).abs() < 0.5, "shares sum to {sum}: {shares}");
    let rays = err
        .split("per sample ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|r| r.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("no rays per sample in: {err}"));
    assert!(rays >= 1.0, "{rays} rays per sample: {err}");
    let (scalar, _) = render(&["--stats", "--engine", "scalar"], "scalar.exr");
    assert!(scalar.contains("scalar engine"), "{scalar}");
    let _ = std::fs::remove_dir_all(&dir);
}
