//! `ophis render`: render a scene to EXR and PNG.

use anyhow::{bail, Context, Result};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use ophis::checkpoint::{hash_bytes, RenderState, StateInfo};
use ophis::film::Film;
use ophis::image_io::{write_exr, write_exr_channels, write_png, RgbImage};
use ophis::integrator::PathStrategy;
use ophis::merge::{render_metadata, SceneIdentity};
use ophis::render::{render_with, Engine, Progress, RenderControl, RenderOptions, TileOrder};
use ophis::scene::build::{load_scene_into, load_scene_str_into, LoadOptions};
use ophis::scene::builtin::XENOPELTIS_XML;
use ophis::scene::mitsuba;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// The scene path that stands for the built-in Xenopeltis scene (also in render states).
const BUILTIN: &str = "<built-in>/xenopeltis.xml";

/// Arguments of `ophis render`.
#[derive(Parser)]
pub struct RenderArgs {
    /// The scene file (Mitsuba XML, version 3.x or 0.6). Without one (and without `--resume`,
    /// which remembers it), the built-in Xenopeltis scene is rendered to `xenopeltis.png` and
    /// `.exr` (its XML is `scenes/xenopeltis.xml`; `-D` sets its parameters).
    scene: Option<PathBuf>,
    /// Output path: `x.exr` or `x.png` writes one file; a name without either extension writes
    /// both `name.exr` and `name.png`. Default: the scene's file name in the current directory.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Set a scene parameter, as Mitsuba's `-D name=value` (fills `$name`, overrides `<default>`).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    defines: Vec<String>,
    /// Samples per pixel (overrides the scene's sampler `sample_count`).
    #[arg(long)]
    spp: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Seed of the random sequences (overrides the scene's sampler `seed`); renders with
    /// different seeds are independent estimates.
    #[arg(long)]
    seed: Option<u64>,
    /// Stop after this many seconds; the image is normalised by the samples each pixel got.
    #[arg(long, value_name = "SECONDS")]
    time: Option<f64>,
    /// Adaptive sampling: `on` spends the same samples in all, a quarter spread evenly and the
    /// rest where the neighbouring pixels are noisiest; `off` spreads them all evenly.
    /// Overrides the sampler's `adaptive` (an ophis extension; off by default, on in the
    /// built-in scene). A resumed render continues the way it started.
    #[arg(long, value_parser = ["on", "off"])]
    adaptive: Option<String>,
    /// Estimator: `mis` (default), `light` (light sampling only) or `bsdf` (BSDF sampling only).
    #[arg(long, value_parser = ["mis", "light", "bsdf"])]
    strategy: Option<String>,
    /// Save the render state every SECONDS (and at the end), atomically, to the state file
    /// (`--state`, default: the output name with `.ophis-state`), for `--resume`.
    #[arg(long, value_name = "SECONDS")]
    checkpoint: Option<f64>,
    /// Continue the render saved in STATE until the target spp (`--spp` may raise it). The
    /// scene, `-D`, `--seed` and `--strategy` come from the state; giving different ones is
    /// an error. Checkpoints go back to STATE.
    #[arg(long, value_name = "STATE")]
    resume: Option<PathBuf>,
    /// Where to write the render state (checkpoints, and on interruption).
    #[arg(long, value_name = "PATH")]
    state: Option<PathBuf>,
    /// Instruction set of the traversal and the wavefront lanes: `auto` (default: the widest
    /// the CPU has), `avx512` (16 lanes), `avx2` (8 lanes) or `baseline` (scalar). For
    /// benchmarks and checks; the image does not depend on it.
    #[arg(long, default_value = "auto", value_parser = ["auto", "avx512", "avx2", "baseline"])]
    isa: String,
    /// Tile order: `row` (default), `reversed` or `shuffled`. The image does not depend on it.
    #[arg(long, default_value = "row", value_parser = ["row", "reversed", "shuffled"])]
    tile_order: String,
    /// Integrator implementation: `auto` (default: the wavefront integrator where it supports
    /// the scene) or `scalar` (one path at a time). The image does not depend on it.
    #[arg(long, default_value = "auto", value_parser = ["auto", "scalar"])]
    engine: String,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
    /// After the render, print where the wavefront integrator's time went (refill, trace,
    /// group, shade, shadow rays, retire: each one's share of the threads' time) and the rays
    /// it traced per sample.
    #[arg(long)]
    stats: bool,
}

fn single_output(output: Option<&Path>) -> bool {
    output
        .and_then(|o| o.extension())
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("exr") || e.eq_ignore_ascii_case("png"))
}

/// The output name without extension: `-o` (minus `.exr`/`.png`) or the scene's file stem.
fn output_base(scene: &Path, output: Option<&Path>) -> PathBuf {
    match output {
        Some(o) if single_output(output) => o.with_extension(""),
        Some(o) => o.to_path_buf(),
        None => PathBuf::from(scene.file_stem().unwrap_or_default()),
    }
}

/// Resolves `-o` into the list of files to write.
fn output_paths(base: &Path, output: Option<&Path>) -> Vec<PathBuf> {
    if let (true, Some(o)) = (single_output(output), output) {
        return vec![o.to_path_buf()];
    }
    let with = |ext: &str| {
        let mut s = base.as_os_str().to_owned();
        s.push(".");
        s.push(ext);
        PathBuf::from(s)
    };
    vec![with("exr"), with("png")]
}

/// Fails early if an output file cannot be created, rather than after an hour of rendering.
fn check_writable(path: &Path) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        bail!(
            "cannot write {}: directory {} does not exist",
            path.display(),
            dir.display()
        );
    }
    if path.is_dir() {
        bail!("cannot write {}: it is a directory", path.display());
    }
    let probe = dir.join(format!(".ophis-write-test-{}", std::process::id()));
    std::fs::write(&probe, b"").with_context(|| format!("cannot write into {}", dir.display()))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

struct Bar(ProgressBar);
impl Progress for Bar {
    fn update(&self, done: u64, total: u64) {
        self.0.set_length(total);
        self.0.set_position(done);
    }
}

pub(crate) fn parse_defines(defs: &[String]) -> Result<Vec<(String, String)>> {
    defs.iter()
        .map(|d| match d.split_once('=') {
            Some((k, v)) if !k.is_empty() => Ok((k.to_string(), v.to_string())),
            _ => bail!("-D expects NAME=VALUE, got '{d}'"),
        })
        .collect()
}

/// The settings a render runs with, from the command line or from a state being resumed.
struct Plan {
    scene: PathBuf,
    info: StateInfo,
    film: Option<Film>,
    state_path: Option<PathBuf>,
}

/// Reads the scene file once, for its hash (the loader reads it again; scenes are small).
fn scene_hash(path: &Path) -> Result<u64> {
    if path == Path::new(BUILTIN) {
        return Ok(hash_bytes(XENOPELTIS_XML.as_bytes()));
    }
    if path.is_dir() {
        bail!("{}: is a directory, not a scene file", path.display());
    }
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    Ok(hash_bytes(&bytes))
}

fn plan(args: &RenderArgs, defines: Vec<(String, String)>, base: &Path) -> Result<Plan> {
    let state_default = || {
        args.state.clone().unwrap_or_else(|| {
            let mut s = base.as_os_str().to_owned();
            s.push(".ophis-state");
            PathBuf::from(s)
        })
    };
    let Some(resume) = &args.resume else {
        let scene = args.scene.clone().unwrap_or_else(|| PathBuf::from(BUILTIN));
        let hash = scene_hash(&scene)?;
        let scene_abs = if scene == Path::new(BUILTIN) {
            scene.clone()
        } else {
            std::path::absolute(&scene).unwrap_or_else(|_| scene.clone())
        };
        return Ok(Plan {
            scene,
            info: StateInfo {
                scene_path: scene_abs,
                scene_hash: hash,
                seed: args.seed.unwrap_or(0),
                spp: args.spp.unwrap_or(0),
                strategy: args.strategy.clone().unwrap_or_else(|| "mis".into()),
                defines,
            },
            film: None,
            state_path: Some(state_default()),
        });
    };
    let st = RenderState::read(resume)?;
    let mut info = st.info;
    let scene = args
        .scene
        .clone()
        .unwrap_or_else(|| info.scene_path.clone());
    let hash = scene_hash(&scene)?;
    if hash != info.scene_hash {
        bail!(
            "cannot resume {}: the scene {} is not the file it was started from \
             (its contents changed, or it is another file); render it afresh instead",
            resume.display(),
            scene.display()
        );
    }
    let differs = |what: &str, given: String, stored: String| -> Result<()> {
        if given != stored {
            bail!(
                "cannot resume {}: {what} {given} differs from the {stored} stored in it; \
                 a resumed render keeps the settings it started with",
                resume.display()
            );
        }
        Ok(())
    };
    if let Some(seed) = args.seed {
        differs("--seed", seed.to_string(), info.seed.to_string())?;
    }
    if let Some(s) = &args.strategy {
        differs("--strategy", s.clone(), info.strategy.clone())?;
    }
    if !defines.is_empty() {
        let show = |d: &[(String, String)]| {
            d.iter()
                .map(|(k, v)| format!("-D {k}={v}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        differs("-D", show(&defines), show(&info.defines))?;
    }
    if let Some(spp) = args.spp {
        info.spp = spp;
    }
    Ok(Plan {
        scene,
        info,
        film: Some(st.film),
        state_path: Some(args.state.clone().unwrap_or_else(|| resume.clone())),
    })
}

/// What identifies the scene in the EXR header, for `ophis merge`: a hash of the tree as
/// loaded (read once more; the builder does not hand its tree back) and a readable name.
fn identity(scene: &Path, defines: &[(String, String)]) -> Result<SceneIdentity> {
    let (root, _) = if scene == Path::new(BUILTIN) {
        mitsuba::load_str(XENOPELTIS_XML, Path::new("xenopeltis.xml"), defines)?
    } else {
        mitsuba::load_file(scene, defines)?
    };
    let name = scene.file_name().unwrap_or_default().to_string_lossy();
    Ok(SceneIdentity::of(&root, &name, defines))
}

fn tile_order(name: &str, seed: u64) -> TileOrder {
    match name {
        "reversed" => TileOrder::Reversed,
        "shuffled" => TileOrder::Shuffled(seed),
        _ => TileOrder::RowMajor,
    }
}

pub fn run(args: RenderArgs) -> Result<()> {
    let defines = parse_defines(&args.defines)?;
    for (name, v) in [("--time", args.time), ("--checkpoint", args.checkpoint)] {
        if let Some(t) = v {
            if !(t > 0.0 && t.is_finite() && t < 1e9) {
                bail!("{name} expects a positive number of seconds, got {t}");
            }
        }
    }
    if args.spp == Some(0) {
        bail!("--spp must be at least 1");
    }
    let scene_arg = args.scene.clone().or_else(|| args.resume.clone());
    let base = output_base(
        scene_arg.as_deref().unwrap_or(Path::new("xenopeltis.xml")),
        args.output.as_deref(),
    );
    let mut plan = plan(&args, defines, &base)?;
    let outputs = output_paths(&base, args.output.as_deref());
    for o in outputs.iter().chain(&plan.state_path) {
        check_writable(o)?;
    }
    if let Some(n) = args.threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("starting the thread pool")?;
    }

    let load_opts = LoadOptions {
        defines: plan.info.defines.clone(),
        spp: (plan.info.spp > 0).then_some(plan.info.spp),
        seed: (args.seed.is_some() || args.resume.is_some()).then_some(plan.info.seed),
        ..Default::default()
    };
    let mut warnings = Vec::new();
    let loaded = if plan.scene == Path::new(BUILTIN) {
        if !args.quiet {
            eprintln!("rendering the built-in Xenopeltis scene (scenes/xenopeltis.xml)");
        }
        load_scene_str_into(
            XENOPELTIS_XML,
            Path::new("xenopeltis.xml"),
            &load_opts,
            &mut warnings,
        )
    } else {
        load_scene_into(&plan.scene, &load_opts, &mut warnings)
    };
    // Warnings first, also when loading failed: they often explain the error.
    for w in &warnings {
        eprintln!("{w}");
    }
    let mut scene = loaded?;
    if let Some(a) = &args.adaptive {
        scene.sampler.adaptive = a == "on";
    }
    let isa = match args.isa.as_str() {
        "avx512" => Some(ophis::accel::Isa::Avx512),
        "avx2" => Some(ophis::accel::Isa::Avx2),
        "baseline" => Some(ophis::accel::Isa::Baseline),
        _ => None,
    };
    if let Some(isa) = isa {
        if !scene.bvh.set_isa(isa) {
            anyhow::bail!("--isa {}: this CPU does not support it", isa.name());
        }
    }
    let scene_id = identity(&plan.scene, &plan.info.defines)?;
    plan.info.spp = scene.sampler.spp;
    plan.info.seed = scene.sampler.seed;
    let mut film = match plan.film.take() {
        Some(f) if (f.width, f.height) != (scene.width, scene.height) => bail!(
            "cannot resume: the state holds a {} × {} image but the scene now renders {} × {}",
            f.width,
            f.height,
            scene.width,
            scene.height
        ),
        Some(f) => {
            let names = aov_channel_names(&scene);
            if f.aov_names != names {
                bail!(
                    "cannot resume: the state holds the AOV channels [{}] but the scene now \
                     records [{}]",
                    f.aov_names.join(", "),
                    names.join(", ")
                );
            }
            if let Some(a) = f.adaptive.as_ref().filter(|a| a.spp != scene.sampler.spp) {
                bail!(
                    "cannot resume: the state is an adaptive render whose samples were planned \
                     for {} spp; it cannot continue to {} (render it again, or resume it without \
                     --spp)",
                    a.spp,
                    scene.sampler.spp
                );
            }
            f
        }
        None => Film::with_aovs(scene.width, scene.height, aov_channel_names(&scene)),
    };

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // First Ctrl-C / SIGTERM: finish the tiles in flight and write what we have.
        // Second: leave now.
        let _ = ctrlc::set_handler(move || {
            if cancel.swap(true, Ordering::SeqCst) {
                eprintln!("\ninterrupted twice: exiting without writing");
                std::process::exit(130);
            }
            eprintln!("\ninterrupted: finishing tiles in flight, then writing the image (Ctrl-C again to quit now)");
        });
    }

    let opts = RenderOptions {
        spp: scene.sampler.spp,
        time_limit: args.time.map(Duration::from_secs_f64),
        strategy: match plan.info.strategy.as_str() {
            "light" => PathStrategy::LightOnly,
            "bsdf" => PathStrategy::BsdfOnly,
            _ => PathStrategy::Mis,
        },
        engine: match args.engine.as_str() {
            "scalar" => Engine::Scalar,
            _ => Engine::Auto,
        },
    };
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(1);
        b.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] [{wide_bar}] {percent}% ETA {eta}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        b
    };
    let state_path = plan.state_path.clone().expect("always set");
    let save = |f: &Film| {
        if let Err(e) = plan.info.write(f, &state_path) {
            eprintln!("warning: checkpoint failed: {e}");
        }
    };
    let ctl = RenderControl {
        cancel: &cancel,
        progress: &Bar(bar.clone()),
        checkpoint: args
            .checkpoint
            .map(|s| (Duration::from_secs_f64(s), &save as &(dyn Fn(&Film) + Sync))),
        tile_order: tile_order(&args.tile_order, plan.info.seed),
    };
    ophis::integrator::wave::stages::take();
    let stats = render_with(&scene, &mut film, 0, &opts, &ctl);
    let stage_times = ophis::integrator::wave::stages::take();
    bar.finish_and_clear();

    let kept = film.total_weight() as u64;
    let image = RgbImage {
        width: film.width as usize,
        height: film.height as usize,
        data: film.to_linear_srgb(),
    };
    let meta = render_metadata(&film, stats.spp_complete, scene.sampler.seed, &scene_id);
    let (extra, aov_meta) = aov_outputs(&scene, &film, &image);
    let meta: Vec<(String, String)> = meta.into_iter().chain(aov_meta).collect();
    for o in &outputs {
        let is_png = o
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if is_png {
            write_png(o, &image).with_context(|| format!("writing {}", o.display()))?;
        } else if extra.is_empty() {
            write_exr(o, &image, &meta).with_context(|| format!("writing {}", o.display()))?;
        } else {
            write_exr_channels(o, &image, &extra, &meta)
                .with_context(|| format!("writing {}", o.display()))?;
        }
    }
    // The state is worth keeping when the render can be continued or was asked for.
    let keep_state = stats.stopped_early || args.checkpoint.is_some() || args.resume.is_some();
    if keep_state {
        plan.info
            .write(&film, &state_path)
            .with_context(|| "saving the render state")?;
    }
    let names: Vec<String> = outputs.iter().map(|p| p.display().to_string()).collect();
    let sps = stats.samples as f64 / stats.seconds.max(1e-9);
    eprintln!(
        "{}x{}, {} spp{}, {:.2} s, {:.2} CPU s, {:.3} Msamples/s -> {}",
        scene.width,
        scene.height,
        stats.spp_complete,
        if stats.stopped_early {
            format!(" (stopped early; {kept} samples)")
        } else {
            String::new()
        },
        stats.seconds,
        stats.cpu_seconds,
        sps / 1e6,
        names.join(", ")
    );
    if let Some(note) = adaptive_note(&film) {
        eprintln!("{note}");
    }
    if args.stats {
        eprintln!("{}", stage_report(&stage_times, stats.samples));
    }
    let resume_hint = format!(
        "continue with: ophis render --resume {}",
        state_path.display()
    );
    if cancel.load(Ordering::SeqCst) {
        bail!(
            "render interrupted; kept {kept} samples ({} complete spp of {}) in {}; {resume_hint}",
            stats.spp_complete,
            opts.spp,
            names.join(", ")
        );
    }
    if stats.stopped_early {
        eprintln!(
            "time budget reached after {} complete spp of {}; {resume_hint}",
            stats.spp_complete, opts.spp
        );
    }
    Ok(())
}

/// For an adaptive render, a line on how its samples were spread (the summary line above it
/// keeps the format scripts read).
fn adaptive_note(film: &Film) -> Option<String> {
    film.adaptive.as_ref()?;
    let counts = film.pixels.iter().map(|p| p[3] as u64);
    let (lo, hi) = (counts.clone().min()?, counts.max()?);
    let mean = film.total_weight() / film.pixels.len() as f64;
    Some(format!(
        "adaptive sampling: {lo} to {hi} samples per pixel, {mean:.1} on average"
    ))
}

/// An EXR channel: its name and row-major values.
type NamedChannel = (String, Vec<f32>);

/// The AOV channels the scene's integrator records (none without `aov`).
fn aov_channel_names(scene: &ophis::scene::Scene) -> Vec<String> {
    scene
        .integrator
        .aov
        .as_ref()
        .map_or(Vec::new(), |a| a.channel_names())
}

/// The extra EXR channels of an `aov` render — the nested integrator's RGBA copy under its name
/// (as Mitsuba writes it) and the AOVs — and the header entries that describe them: the channel
/// list (`ophis.aovs`, which `ophis merge` refuses) and the shape labels behind `shape_index`.
fn aov_outputs(
    scene: &ophis::scene::Scene,
    film: &Film,
    image: &RgbImage,
) -> (Vec<NamedChannel>, Vec<(String, String)>) {
    let Some(aov) = &scene.integrator.aov else {
        return (Vec::new(), Vec::new());
    };
    let mut extra = Vec::new();
    if let Some(name) = &aov.image_name {
        for (c, ch) in ["R", "G", "B"].iter().enumerate() {
            extra.push((
                format!("{name}.{ch}"),
                image.data.iter().map(|p| p[c]).collect(),
            ));
        }
        extra.push((format!("{name}.A"), vec![1.0; image.data.len()]));
    }
    extra.extend(film.aov_images());
    let mut meta = vec![(
        ophis::merge::KEY_AOVS.to_string(),
        extra
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
            .join(","),
    )];
    if aov
        .aovs
        .iter()
        .any(|a| a.kind == ophis::integrator::aov::AovKind::ShapeIndex)
    {
        let legend: Vec<String> = scene
            .shape_labels
            .iter()
            .enumerate()
            .map(|(i, l)| format!("{}={l}", i + 1))
            .collect();
        meta.push(("ophis.shapes".to_string(), legend.join(";")));
    }
    (extra, meta)
}

/// The `--stats` lines: each wavefront stage's share of the time, and rays per sample.
fn stage_report(t: &ophis::integrator::wave::stages::StageTimes, samples: u64) -> String {
    use ophis::integrator::wave::stages::Stage;
    let total = t.total();
    if t.rays == 0 || total <= 0.0 {
        return "stats: the wavefront integrator did not render this scene (the scalar engine \
                did: it keeps no stage times)"
            .to_string();
    }
    let shares: Vec<String> = Stage::ALL
        .iter()
        .zip(&t.seconds)
        .map(|(s, &x)| format!("{} {:.1} %", s.name(), 100.0 * x / total))
        .collect();
    let per_sample = |n: u64| n as f64 / samples.max(1) as f64;
    format!(
        "stats: wavefront stages, share of {:.2} thread s: {}\n\
         stats: per sample {:.2} rays and {:.2} shadow rays; {:.0} ns per traced ray in trace, \
         {:.0} ns per path vertex in all",
        total,
        shares.join(", "),
        per_sample(t.rays),
        per_sample(t.shadow_rays),
        1e9 * t.seconds[Stage::Trace as usize] / t.rays as f64,
        1e9 * total / t.rays as f64,
    )
}
