//! The figures of `ophis thinfilm` (waiting for `ophis::plot`).

use anyhow::{bail, Result};
use ophis::optics::filmtool::FilmStack;
use std::path::Path;

/// R(λ) for each angle.
pub fn plot(_st: &FilmStack, _angles: &[f64], _wavelengths: &[f64], _path: &Path) -> Result<()> {
    bail!("--plot: plotting is not available in this build yet")
}

/// Colour of reflected D65 over thickness (x) × angle (y).
pub fn chart(_st: &FilmStack, _range: (f64, f64), _path: &Path) -> Result<()> {
    bail!("--chart: plotting is not available in this build yet")
}
