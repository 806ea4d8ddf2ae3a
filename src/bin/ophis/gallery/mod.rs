//! `ophis gallery`: render every thesis and paper figure and compose labelled contact sheets
//! (the figures and the composition are in `sheets.rs`).

mod sheets;

use anyhow::{bail, Result};
use clap::Parser;
use sheets::{default_scenes_dir, make_gallery, sheets, Quality};
use std::path::PathBuf;

/// Arguments of `ophis gallery`.
#[derive(Parser)]
pub struct GalleryArgs {
    /// Folder the sheets are written to.
    #[arg(long, default_value = "docs/gallery")]
    out: PathBuf,
    /// CI size: 8×8-pixel renders at 1 spp (checks that every figure renders, in seconds).
    #[arg(long)]
    quick: bool,
    /// Render size in pixels (square; default 128, or 8 with --quick).
    #[arg(long)]
    res: Option<u32>,
    /// Samples per pixel (default 32, or 1 with --quick).
    #[arg(long)]
    spp: Option<u32>,
    /// Only these sheets (repeatable; see --list).
    #[arg(long)]
    only: Vec<String>,
    /// List the sheets and exit.
    #[arg(long)]
    list: bool,
    /// The scenes folder (default: ./scenes, else the source tree's).
    #[arg(long)]
    scenes: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

pub fn run(args: GalleryArgs) -> Result<()> {
    if args.list {
        for s in sheets() {
            println!(
                "{:<22} {} ({} x {})",
                s.name,
                s.title,
                s.rows.len(),
                s.cols.len()
            );
        }
        return Ok(());
    }
    let mut q = if args.quick {
        Quality::QUICK
    } else {
        Quality::PREVIEW
    };
    if let Some(r) = args.res {
        if r == 0 || r > 4096 {
            bail!("--res must be between 1 and 4096, got {r}");
        }
        q.res = r;
        q.cell = q.cell.max(r.min(256));
    }
    if let Some(s) = args.spp {
        if s == 0 {
            bail!("--spp must be at least 1");
        }
        q.spp = s;
    }
    if let Some(n) = args.threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()?;
    }
    let scenes = args.scenes.unwrap_or_else(default_scenes_dir);
    let t = std::time::Instant::now();
    let written = make_gallery(&scenes, &args.out, q, &args.only, &mut |l| eprintln!("{l}"))?;
    eprintln!(
        "gallery: {} sheets in {:.1} s -> {}",
        written.len(),
        t.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}
