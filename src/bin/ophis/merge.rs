//! `ophis merge`: combine independent renders of one scene into one image.

use anyhow::{bail, Context, Result};
use clap::Parser;
use ophis::image_io::{read_exr_metadata, read_image, write_exr};
use ophis::merge::{merge, MergeInput};
use std::path::PathBuf;

/// Arguments of `ophis merge`.
#[derive(Parser)]
pub struct MergeArgs {
    /// The merged EXR to write.
    output: PathBuf,
    /// EXR files written by `ophis render` (same scene and resolution, different seeds).
    /// Renders of different scenes (by `ophis.scene_hash`) or with overlapping seeds are
    /// refused.
    #[arg(required = true, num_args = 1..)]
    inputs: Vec<PathBuf>,
}

pub fn run(args: MergeArgs) -> Result<()> {
    if args.inputs.contains(&args.output) {
        bail!(
            "the output {} is also an input; write the merge to a new file",
            args.output.display()
        );
    }
    let mut inputs = Vec::with_capacity(args.inputs.len());
    for p in &args.inputs {
        let metadata = read_exr_metadata(p)?;
        let image = read_image(p)?;
        inputs.push(MergeInput {
            name: p.display().to_string(),
            image,
            metadata,
        });
    }
    let merged = merge(&inputs).map_err(anyhow::Error::msg)?;
    for w in &merged.warnings {
        eprintln!("warning: {w}");
    }
    let meta = merged.metadata;
    write_exr(&args.output, &merged.image, &meta)
        .with_context(|| format!("writing {}", args.output.display()))?;
    let samples = meta
        .iter()
        .find(|(k, _)| k == ophis::merge::KEY_SAMPLES)
        .map(|(_, v)| v.as_str())
        .unwrap_or("?");
    eprintln!(
        "merged {} renders ({samples} samples) -> {}",
        inputs.len(),
        args.output.display()
    );
    Ok(())
}
