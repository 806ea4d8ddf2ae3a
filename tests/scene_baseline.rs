//! Before/after check for refactors: every scene of `scenes/` (with each `-Dshape`/`-Dstage`
//! value) renders to the same image as the code that wrote `tests/data/scene_baseline.csv`,
//! within noise.
//!
//! The baseline holds, per scene variant, the mean and standard error over [`SEEDS`]
//! independent renders (32×32 pixels, [`SPP`] spp each) of each channel of each 8×8 block, and
//! a hash of the exact pixels of the first seed. The test renders the same variants with the
//! current code and
//!
//! - counts the variants whose pixels are bit-identical (printed: expected where the
//!   arithmetic did not change),
//! - compares every block mean with z = (new − old) / √(se_old² + se_new²) and fails when any
//!   |z| exceeds the two-sided Šidák threshold at level 0.001 over all blocks, channels and
//!   variants, taken from Student's t (the standard errors are estimates), so a spurious
//!   failure is rarer than 1 in 1000 runs (the threshold is about 5.5 standard errors), while a
//!   bias larger than that in any single block fails.
//!
//! Variants whose scene file (or an included part) changed since the baseline was written are
//! skipped and listed: their image is meant to change. Write a new baseline with the code you
//! trust (`OPHIS_WRITE_BASELINE=1 cargo test --release --test scene_baseline -- --ignored`).

use ophis::film::Film;
use ophis::integrator::PathStrategy;
use ophis::render::{render, NoProgress, RenderOptions};
use ophis::scene::build::{load_scene, LoadOptions};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

mod common;
use common::scenes::{scene_files, tiny_mesh, variants};
use std::sync::atomic::AtomicBool;

const RES: u32 = 32;
const BLOCK: u32 = 8;
const SPP: u32 = 2;
const SEEDS: u64 = 32;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn baseline_path() -> PathBuf {
    root().join("tests/data/scene_baseline.csv")
}

/// FNV-1a over bytes.
fn fnv(bytes: &[u8], mut h: u64) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x100_0000_01b3);
    }
    h
}

/// A hash of the scene file and every part it may include (parts are shared, so all of them).
fn scene_hash(rel: &str) -> u64 {
    let mut h = fnv(
        &std::fs::read(root().join("scenes").join(rel)).unwrap(),
        0xcbf2_9ce4_8422_2325,
    );
    if std::fs::read_to_string(root().join("scenes").join(rel))
        .unwrap()
        .contains("<include")
    {
        let mut parts: Vec<PathBuf> = std::fs::read_dir(root().join("scenes/parts"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        parts.sort();
        for p in parts {
            h = fnv(&std::fs::read(p).unwrap(), h);
        }
    }
    h
}

/// One variant's statistics: per block and channel, (mean, standard error) over the seeds,
/// and the hash of the first seed's pixels.
struct Stats {
    blocks: Vec<(f64, f64)>,
    pixels_hash: u64,
}

fn render_stats(rel: &str, defines: &[(String, String)]) -> Stats {
    let mut defines = defines.to_vec();
    let text = std::fs::read_to_string(root().join("scenes").join(rel)).unwrap();
    if text.contains("<default name=\"mesh\"") {
        defines.push(("mesh".into(), tiny_mesh().display().to_string()));
    }
    let opts = LoadOptions {
        defines,
        spp: Some(SPP),
        seed: Some(0),
        resolution: Some((RES, RES)),
    };
    let (mut scene, _) = load_scene(&root().join("scenes").join(rel), &opts)
        .unwrap_or_else(|e| panic!("{rel}: {e}"));
    let nb = (RES / BLOCK) as usize;
    let mut sums = vec![(0.0f64, 0.0f64); nb * nb * 3];
    let mut pixels_hash = 0;
    for seed in 0..SEEDS {
        scene.sampler.seed = seed;
        let mut film = Film::new(scene.width, scene.height);
        let ropts = RenderOptions {
            spp: SPP,
            time_limit: None,
            strategy: PathStrategy::Mis,
            engine: ophis::render::Engine::Auto,
        };
        render(
            &scene,
            &mut film,
            0,
            &ropts,
            &AtomicBool::new(false),
            &NoProgress,
        );
        let px = film.to_linear_srgb();
        if seed == 0 {
            let bytes: Vec<u8> = px
                .iter()
                .flatten()
                .flat_map(|v| v.to_bits().to_le_bytes())
                .collect();
            pixels_hash = fnv(&bytes, 0xcbf2_9ce4_8422_2325);
        }
        let mut block = vec![0.0f64; nb * nb * 3];
        for (i, p) in px.iter().enumerate() {
            let (x, y) = (i as u32 % RES, i as u32 / RES);
            let b = ((y / BLOCK) as usize * nb + (x / BLOCK) as usize) * 3;
            for c in 0..3 {
                block[b + c] += p[c] as f64 / (BLOCK * BLOCK) as f64;
            }
        }
        for (s, v) in sums.iter_mut().zip(block) {
            s.0 += v;
            s.1 += v * v;
        }
    }
    let n = SEEDS as f64;
    let blocks = sums
        .into_iter()
        .map(|(s, s2)| {
            let m = s / n;
            let var = ((s2 - n * m * m) / (n - 1.0)).max(0.0);
            (m, (var / n).sqrt())
        })
        .collect();
    Stats {
        blocks,
        pixels_hash,
    }
}

fn key(rel: &str, defines: &[(String, String)]) -> String {
    let d: Vec<String> = defines.iter().map(|(k, v)| format!("{k}={v}")).collect();
    format!("{rel}|{}", d.join(";"))
}

/// Writes the baseline with the code checked out now.
#[test]
#[ignore]
fn write_baseline() {
    if std::env::var("OPHIS_WRITE_BASELINE").is_err() {
        eprintln!(
            "set OPHIS_WRITE_BASELINE=1 to write {}",
            baseline_path().display()
        );
        return;
    }
    let mut out = String::from(
        "# scene|defines,scene_hash,pixels_hash,then per 8x8 block and channel: mean,stderr\n",
    );
    for rel in scene_files() {
        let text = std::fs::read_to_string(root().join("scenes").join(&rel)).unwrap();
        // A file without a sensor of its own or from a part is a BSDF collection for
        // `ophis bsdf` (layered-skin.xml), not a picture.
        if !text.contains("<sensor") && !text.contains("<include") {
            continue;
        }
        for d in variants(&text) {
            let s = render_stats(&rel, &d);
            write!(
                out,
                "{},{:016x},{:016x}",
                key(&rel, &d),
                scene_hash(&rel),
                s.pixels_hash
            )
            .unwrap();
            for (m, se) in &s.blocks {
                write!(out, ",{m:.9e},{se:.9e}").unwrap();
            }
            out.push('\n');
            eprintln!("{}", key(&rel, &d));
        }
    }
    std::fs::write(baseline_path(), out).unwrap();
}

#[test]
fn scenes_render_as_in_the_baseline() {
    let text = std::fs::read_to_string(baseline_path()).expect("baseline CSV");
    let mut rows = BTreeMap::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let mut f = line.split(',');
        let k = f.next().unwrap().to_string();
        let scene_hash = u64::from_str_radix(f.next().unwrap(), 16).unwrap();
        let pixels_hash = u64::from_str_radix(f.next().unwrap(), 16).unwrap();
        let v: Vec<f64> = f.map(|x| x.parse().unwrap()).collect();
        let blocks: Vec<(f64, f64)> = v.chunks(2).map(|c| (c[0], c[1])).collect();
        rows.insert(k, (scene_hash, pixels_hash, blocks));
    }
    let mut compared = Vec::new();
    let mut skipped = Vec::new();
    let mut identical = 0;
    for rel in scene_files() {
        let text = std::fs::read_to_string(root().join("scenes").join(&rel)).unwrap();
        for d in variants(&text) {
            let k = key(&rel, &d);
            let Some((h, ph, old)) = rows.get(&k) else {
                continue;
            };
            if *h != scene_hash(&rel) {
                skipped.push(k);
                continue;
            }
            let new = render_stats(&rel, &d);
            if new.pixels_hash == *ph {
                identical += 1;
            }
            compared.push((k, old.clone(), new.blocks));
        }
    }
    let tests: usize = compared.iter().map(|c| c.1.len()).sum();
    // Two-sided Šidák threshold: P(max |z| > t) = 0.001 over all comparisons.
    let p_each = 1.0 - (1.0f64 - 0.001).powf(1.0 / tests.max(1) as f64);
    // Each standard error comes from SEEDS − 1 degrees of freedom on each side (Welch).
    let t = student_quantile(1.0 - p_each / 2.0, 2.0 * (SEEDS as f64 - 1.0));
    let mut worst = (0.0f64, String::new());
    let mut failures = Vec::new();
    for (k, old, new) in &compared {
        for (i, ((mo, so), (mn, sn))) in old.iter().zip(new).enumerate() {
            let se = (so * so + sn * sn).sqrt();
            let z = if se > 0.0 {
                (mn - mo) / se
            } else if (mn - mo).abs() <= 1e-6 * mo.abs().max(1e-6) {
                0.0
            } else {
                f64::INFINITY
            };
            if z.abs() > worst.0 {
                worst = (z.abs(), format!("{k} block {} channel {}", i / 3, i % 3));
            }
            if z.abs() > t {
                failures.push(format!(
                    "{k} block {} channel {}: {mo:.5} ± {so:.5} before, {mn:.5} ± {sn:.5} now (z = {z:.1})",
                    i / 3,
                    i % 3
                ));
            }
        }
    }
    eprintln!(
        "scene baseline: {} variants compared ({identical} bit-identical), {} skipped (scene \
         changed: {skipped:?}); worst |z| = {:.2} at {} (threshold {t:.2})",
        compared.len(),
        skipped.len(),
        worst.0,
        worst.1
    );
    assert!(!compared.is_empty(), "nothing compared");
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Standard normal quantile (Acklam's rational approximation, relative error < 1.2e-9).
fn normal_quantile(p: f64) -> f64 {
    let a = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.38357751867269e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    let b = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    let c = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    let d = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    // The lower-tail quantile of q = min(p, 1 − p), then the sign for p.
    let q = p.min(1.0 - p);
    let lower = if q < 0.02425 {
        let r = (-2.0 * q.ln()).sqrt();
        (((((c[0] * r + c[1]) * r + c[2]) * r + c[3]) * r + c[4]) * r + c[5])
            / ((((d[0] * r + d[1]) * r + d[2]) * r + d[3]) * r + 1.0)
    } else {
        let r = q - 0.5;
        let s = r * r;
        (((((a[0] * s + a[1]) * s + a[2]) * s + a[3]) * s + a[4]) * s + a[5]) * r
            / (((((b[0] * s + b[1]) * s + b[2]) * s + b[3]) * s + b[4]) * s + 1.0)
    };
    if p < 0.5 {
        lower
    } else {
        -lower
    }
}

/// Student-t quantile with `nu` degrees of freedom from the normal one (Cornish–Fisher
/// expansion to 1/ν², accurate to a few parts in 1000 for ν ≳ 30 in the far tail).
fn student_quantile(p: f64, nu: f64) -> f64 {
    let z = normal_quantile(p);
    let z3 = z * z * z;
    let z5 = z3 * z * z;
    z + (z3 + z) / (4.0 * nu) + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * nu * nu)
}

#[test]
fn quantiles_match_tables() {
    assert!((normal_quantile(0.975) - 1.959964).abs() < 1e-5);
    assert!((normal_quantile(0.025) + 1.959964).abs() < 1e-5);
    assert!((normal_quantile(1.0 - 1e-7) - 5.199338).abs() < 1e-4);
    // t(0.975, 30) = 2.0423, t(0.9995, 60) = 3.4602 (standard tables).
    assert!((student_quantile(0.975, 30.0) - 2.0423).abs() < 2e-3);
    assert!((student_quantile(0.9995, 60.0) - 3.4602).abs() < 5e-3);
}
