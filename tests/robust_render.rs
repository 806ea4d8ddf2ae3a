//! Reproducibility and resuming, through the library: the same scene, seed and spp give
//! bit-identical sums whatever the thread count and tile order, and a render interrupted
//! mid-pass, saved to a state file and resumed, equals an uninterrupted one bit for bit; both
//! for uniform and adaptive renders (`render/adaptive.rs`), whose sample counts differ from
//! pixel to pixel.

use ophis::checkpoint::{hash_bytes, RenderState, StateInfo};
use ophis::film::Film;
use ophis::integrator::PathStrategy;
use ophis::render::{render_with, NoProgress, RenderControl, RenderOptions, TileOrder};
use ophis::scene::build::{load_scene_str, LoadOptions};
use ophis::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

/// The reference scene at 72 × 40: 3 × 2 tiles of different sizes (32 or 8 wide, 32 or 8 high).
fn scene_with_seed(spp: u32, seed: u64) -> Scene {
    scene_of(spp, seed, false)
}

/// The reference scene at 72 × 40, its sampler adaptive or not.
fn scene_of(spp: u32, seed: u64, adaptive: bool) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/reference.xml");
    let mut xml = std::fs::read_to_string(&path)
        .unwrap()
        .replace(r#"name="width" value="64""#, r#"name="width" value="72""#)
        .replace(r#"name="height" value="48""#, r#"name="height" value="40""#);
    if adaptive {
        xml = xml.replace(
            "</sampler>",
            r#"<boolean name="adaptive" value="true"/></sampler>"#,
        );
    }
    let opts = LoadOptions {
        defines: vec![],
        spp: Some(spp),
        seed: Some(seed),
        ..Default::default()
    };
    let scene = load_scene_str(&xml, &path, &opts)
        .expect("reference scene loads")
        .0;
    assert_eq!((scene.width, scene.height), (72, 40));
    scene
}

fn reference_scene(spp: u32) -> Scene {
    scene_with_seed(spp, 5)
}

fn opts(spp: u32) -> RenderOptions {
    RenderOptions {
        spp,
        time_limit: None,
        strategy: PathStrategy::Mis,
        engine: ophis::render::Engine::Auto,
    }
}

fn run(scene: &Scene, film: &mut Film, spp: u32, order: TileOrder, threads: usize) {
    let cancel = AtomicBool::new(false);
    let ctl = RenderControl {
        cancel: &cancel,
        progress: &NoProgress,
        checkpoint: None,
        tile_order: order,
    };
    pool(threads).install(|| render_with(scene, film, 0, &opts(spp), &ctl));
}

/// A rayon pool of `threads` threads.
fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

fn bits(f: &Film) -> Vec<u64> {
    f.pixels.iter().flatten().map(|v| v.to_bits()).collect()
}

#[test]
fn sums_are_bit_identical_across_threads_and_tile_orders() {
    let spp = 6;
    let scene = reference_scene(spp);
    let mut base = Film::new(scene.width, scene.height);
    run(&scene, &mut base, spp, TileOrder::RowMajor, 1);
    assert!(base.total_weight() == (scene.width * scene.height * spp) as f64);
    for (order, threads) in [
        (TileOrder::RowMajor, 2),
        (TileOrder::Reversed, 2),
        (TileOrder::Shuffled(3), 3),
    ] {
        let mut f = Film::new(scene.width, scene.height);
        run(&scene, &mut f, spp, order, threads);
        assert!(bits(&f) == bits(&base), "{order:?} with {threads} threads");
    }
    // The comparison can fail: another seed changes the sums.
    let other = scene_with_seed(spp, 6);
    let mut f = Film::new(scene.width, scene.height);
    run(&other, &mut f, spp, TileOrder::RowMajor, 2);
    assert!(bits(&f) != bits(&base));
}

#[test]
fn adaptive_sums_are_bit_identical_across_threads_and_tile_orders() {
    let spp = 12; // a pilot of 4
    let scene = scene_of(spp, 5, true);
    let mut base = Film::new(scene.width, scene.height);
    run(&scene, &mut base, spp, TileOrder::RowMajor, 1);
    let counts: std::collections::BTreeSet<u64> = base.pixels.iter().map(|p| p[3] as u64).collect();
    assert!(counts.len() > 5, "the counts should vary: {counts:?}");
    assert!(counts.iter().all(|&c| c >= 4), "{counts:?}");
    let budget = (scene.width * scene.height * spp) as f64;
    let n = (scene.width * scene.height) as f64;
    assert!((base.total_weight() - budget).abs() <= n / 2.0);
    for (order, threads) in [(TileOrder::Reversed, 2), (TileOrder::Shuffled(3), 3)] {
        let mut f = Film::new(scene.width, scene.height);
        run(&scene, &mut f, spp, order, threads);
        assert!(bits(&f) == bits(&base), "{order:?} with {threads} threads");
        assert_eq!(f.adaptive, base.adaptive);
    }
}

/// An adaptive render's image is an unbiased estimate: its mean over the image agrees with
/// a uniform render's within the spread of independent seeds (a two-sample t statistic).
#[test]
fn adaptive_render_agrees_with_a_uniform_one() {
    let spp = 16;
    let means = |adaptive: bool| -> Vec<f64> {
        (0..6)
            .map(|seed| {
                let scene = scene_of(spp, 100 + seed + 10 * adaptive as u64, adaptive);
                let mut f = Film::new(scene.width, scene.height);
                run(&scene, &mut f, spp, TileOrder::RowMajor, 2);
                assert_eq!(f.adaptive.is_some(), adaptive);
                let img = f.to_linear_srgb();
                img.iter().map(|p| (p[0] + p[1] + p[2]) as f64).sum::<f64>() / img.len() as f64
            })
            .collect()
    };
    let (a, u) = (means(true), means(false));
    let stats = |v: &[f64]| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64;
        (m, var / v.len() as f64)
    };
    let ((ma, va), (mu, vu)) = (stats(&a), stats(&u));
    let t = (ma - mu) / (va + vu).sqrt();
    // |t| < 4: a false alarm about once in 300 runs of 10 degrees of freedom, and the seeds
    // are fixed.
    assert!(t.abs() < 4.0, "adaptive {ma} vs uniform {mu}: t = {t}");
    assert!(va > 0.0 && vu > 0.0);
}

/// Renders `scene` on one thread in a shuffled tile order, writing a checkpoint after every
/// tile and cancelling after `stop_after` tiles; returns the interrupted film, the state
/// file's path (in a fresh directory named by `name`) and what it was written with.
fn interrupt(scene: &Scene, spp: u32, stop_after: usize, name: &str) -> (Film, PathBuf, StateInfo) {
    let state_path = temp(name).join("r.ophis-state");
    let info = StateInfo {
        scene_path: "reference.xml".into(),
        scene_hash: hash_bytes(b"reference"),
        seed: 5,
        spp,
        strategy: "mis".into(),
        defines: vec![],
    };
    let cancel = AtomicBool::new(false);
    let tiles_done = AtomicUsize::new(0);
    let save = |f: &Film| {
        info.write(f, &state_path).unwrap();
        if tiles_done.fetch_add(1, Ordering::SeqCst) + 1 == stop_after {
            cancel.store(true, Ordering::SeqCst);
        }
    };
    let ctl = RenderControl {
        cancel: &cancel,
        progress: &NoProgress,
        checkpoint: Some((Duration::ZERO, &save)),
        tile_order: TileOrder::Shuffled(9),
    };
    let mut part = Film::new(scene.width, scene.height);
    let stats = pool(1).install(|| render_with(scene, &mut part, 0, &opts(spp), &ctl));
    assert!(stats.stopped_early);
    (part, state_path, info)
}

/// Interrupts an adaptive render of `spp` after `stop_after` tiles, saves it, resumes it and
/// compares with an uninterrupted one.
fn adaptive_resume_case(spp: u32, stop_after: usize) {
    let scene = scene_of(spp, 5, true);
    let mut whole = Film::new(scene.width, scene.height);
    run(&scene, &mut whole, spp, TileOrder::RowMajor, 2);
    let (part, state_path, _) =
        interrupt(&scene, spp, stop_after, &format!("adaptive-{stop_after}"));
    let state = RenderState::read(&state_path).unwrap();
    assert_eq!(
        state.film, part,
        "the last checkpoint holds the interrupted film"
    );
    let mut resumed = state.film;
    run(&scene, &mut resumed, spp, TileOrder::Reversed, 2);
    assert!(bits(&resumed) == bits(&whole), "resumed render differs");
    assert_eq!(resumed.adaptive, whole.adaptive);
    let _ = std::fs::remove_dir_all(state_path.parent().unwrap());
}

#[test]
fn adaptive_render_interrupted_in_its_pilot_resumes_bit_identical() {
    // spp 20: pilot 5, passes 0–1, 1–2, 2–4, 4–5 | 5–8, 8–16, 16–20 of 6 tiles each; stop in
    // the third pass.
    adaptive_resume_case(20, 15);
}

#[test]
fn adaptive_render_interrupted_after_its_pilot_resumes_bit_identical() {
    // Stop in the fifth pass (5–8), after the targets are set.
    adaptive_resume_case(20, 27);
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ophis-robust-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn interrupted_saved_and_resumed_render_equals_uninterrupted() {
    let spp = 20; // passes 0–1, 1–3, 3–7, 7–15, 15–20
    let scene = reference_scene(spp);
    let mut whole = Film::new(scene.width, scene.height);
    run(&scene, &mut whole, spp, TileOrder::RowMajor, 2);

    // Stop after 20 tiles: three passes of 6 tiles, then 2 tiles into the fourth.
    let (part, state_path, info) = interrupt(&scene, spp, 20, "resume");
    let counts: std::collections::BTreeSet<u64> = part.pixels.iter().map(|p| p[3] as u64).collect();
    assert_eq!(
        counts.len(),
        2,
        "tiles should differ by one pass: {counts:?}"
    );

    let state = RenderState::read(&state_path).unwrap();
    assert_eq!(
        state.film, part,
        "the last checkpoint holds the interrupted film"
    );
    assert_eq!(state.info, info);
    let mut resumed = state.film;
    run(&scene, &mut resumed, spp, TileOrder::Reversed, 2);
    assert!(bits(&resumed) == bits(&whole), "resumed render differs");
    let _ = std::fs::remove_dir_all(state_path.parent().unwrap());
}

/// Whether every 32 × 32 tile of `f` holds one sample count in all its pixels.
fn tiles_uniform(f: &Film) -> bool {
    let t = ophis::render::TILE;
    (0..f.height.div_ceil(t)).all(|ty| {
        (0..f.width.div_ceil(t)).all(|tx| {
            let first = f.pixels[(ty * t * f.width + tx * t) as usize][3];
            (ty * t..((ty + 1) * t).min(f.height)).all(|y| {
                (tx * t..((tx + 1) * t).min(f.width))
                    .all(|x| f.pixels[(y * f.width + x) as usize][3] == first)
            })
        })
    })
}

/// Cancels a render once `after` pieces of tiles are done (progress reports one per piece).
struct CancelAfter<'a> {
    cancel: &'a AtomicBool,
    seen: AtomicUsize,
    after: usize,
}

impl ophis::render::Progress for CancelAfter<'_> {
    fn update(&self, _: u64, _: u64) {
        if self.seen.fetch_add(1, Ordering::SeqCst) + 1 == self.after {
            self.cancel.store(true, Ordering::SeqCst);
        }
    }
}

/// The reference scene's six tiles are few, so each tile's passes are rendered in quarters by
/// three threads at once; a render cancelled mid-pass must still leave every tile whole
/// (all its pixels at the same pass), both in the film it returns and in every checkpoint,
/// and each resumes bit for bit.
#[test]
fn renders_of_tiles_in_quarters_stop_and_checkpoint_on_whole_tiles() {
    let spp = 20;
    let scene = reference_scene(spp);
    let mut whole = Film::new(scene.width, scene.height);
    run(&scene, &mut whole, spp, TileOrder::RowMajor, 2);
    // 5 passes of 6 tiles in 15 pieces: stop in the first, third and fifth pass.
    for stop_after in [5, 37, 70] {
        let cancel = AtomicBool::new(false);
        let progress = CancelAfter {
            cancel: &cancel,
            seen: AtomicUsize::new(0),
            after: stop_after,
        };
        let saved = std::sync::Mutex::new(Vec::new());
        let save = |f: &Film| {
            assert!(tiles_uniform(f), "a checkpoint with a half-added tile");
            saved.lock().unwrap().push(f.clone());
        };
        let ctl = RenderControl {
            cancel: &cancel,
            progress: &progress,
            checkpoint: Some((Duration::ZERO, &save)),
            tile_order: TileOrder::Shuffled(stop_after as u64),
        };
        let mut part = Film::new(scene.width, scene.height);
        let stats = pool(3).install(|| render_with(&scene, &mut part, 0, &opts(spp), &ctl));
        // Passes run one after another, so a stop within the first four passes leaves the
        // fifth undone. A stop in the last pass may come after each of its tiles was begun
        // (each thread takes pieces from its own part of the list, so the last tile is often
        // begun early), and a begun tile is finished: that render ends complete, as correct
        // a result; the checks below hold for it too. (`stop after 70` failed this assertion
        // once in a CI run: a race in the test, not in the render.)
        if stop_after <= 4 * 15 {
            assert!(stats.stopped_early, "stop after {stop_after}");
        }
        assert!(
            tiles_uniform(&part),
            "stop after {stop_after}: a half-rendered tile"
        );
        let mut films = saved.into_inner().unwrap();
        assert!(!films.is_empty());
        films.push(part);
        for f in films {
            let mut resumed = f;
            run(&scene, &mut resumed, spp, TileOrder::Reversed, 2);
            assert!(
                bits(&resumed) == bits(&whole),
                "stop after {stop_after}: resumed differs"
            );
        }
    }
}
