//! `ophis render`: render a scene to EXR and PNG.

use anyhow::{bail, Context, Result};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use ophis::film::Film;
use ophis::image_io::{write_exr, write_png, RgbImage};
use ophis::integrator::PathStrategy;
use ophis::render::{render, Progress, RenderOptions};
use ophis::scene::build::{load_scene, LoadOptions};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// Arguments of `ophis render`.
#[derive(Parser)]
pub struct RenderArgs {
    /// The scene file (Mitsuba XML, version 3.x or 0.6).
    scene: PathBuf,
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
    /// Estimator: `mis` (default), `light` (light sampling only) or `bsdf` (BSDF sampling only).
    #[arg(long, default_value = "mis", value_parser = ["mis", "light", "bsdf"])]
    strategy: String,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

/// Resolves `-o` into the list of files to write.
fn output_paths(scene: &Path, output: Option<&Path>) -> Vec<PathBuf> {
    let base = match output {
        Some(o) => {
            match o
                .extension()
                .and_then(|e| e.to_str())
                .map(|e| e.to_ascii_lowercase())
            {
                Some(e) if e == "exr" || e == "png" => return vec![o.to_path_buf()],
                _ => o.to_path_buf(),
            }
        }
        None => PathBuf::from(scene.file_stem().unwrap_or_default()),
    };
    let with = |ext: &str| {
        let mut s = base.clone().into_os_string();
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

pub fn run(args: RenderArgs) -> Result<()> {
    let defines = parse_defines(&args.defines)?;
    if let Some(t) = args.time {
        if !(t > 0.0 && t.is_finite()) {
            bail!("--time expects a positive number of seconds, got {t}");
        }
    }
    if args.spp == Some(0) {
        bail!("--spp must be at least 1");
    }
    let outputs = output_paths(&args.scene, args.output.as_deref());
    for o in &outputs {
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
        defines,
        spp: args.spp,
        seed: args.seed,
    };
    let (scene, warnings) = load_scene(&args.scene, &load_opts)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // First Ctrl-C: finish the tiles in flight and write what we have. Second: leave now.
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
        strategy: match args.strategy.as_str() {
            "light" => PathStrategy::LightOnly,
            "bsdf" => PathStrategy::BsdfOnly,
            _ => PathStrategy::Mis,
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
    let mut film = Film::new(scene.width, scene.height);
    let stats = render(&scene, &mut film, 0, &opts, &cancel, &Bar(bar.clone()));
    bar.finish_and_clear();

    let image = RgbImage {
        width: film.width as usize,
        height: film.height as usize,
        data: film.to_linear_srgb(),
    };
    let meta = vec![
        ("ophis.spp".to_string(), stats.spp_complete.to_string()),
        ("ophis.samples".to_string(), stats.samples.to_string()),
        ("ophis.seed".to_string(), scene.sampler.seed.to_string()),
    ];
    for o in &outputs {
        let is_png = o
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if is_png {
            write_png(o, &image).with_context(|| format!("writing {}", o.display()))?;
        } else {
            write_exr(o, &image, &meta).with_context(|| format!("writing {}", o.display()))?;
        }
    }
    let names: Vec<String> = outputs.iter().map(|p| p.display().to_string()).collect();
    let sps = stats.samples as f64 / stats.seconds.max(1e-9);
    eprintln!(
        "{}x{}, {} spp{}, {:.2} s, {:.3} Msamples/s -> {}",
        scene.width,
        scene.height,
        stats.spp_complete,
        if stats.stopped_early {
            format!(" (stopped early; {} samples)", stats.samples)
        } else {
            String::new()
        },
        stats.seconds,
        sps / 1e6,
        names.join(", ")
    );
    if cancel.load(Ordering::SeqCst) {
        bail!(
            "render interrupted; kept {} samples ({} complete spp)",
            stats.samples,
            stats.spp_complete
        );
    }
    Ok(())
}
