//! `independent`: uniform random numbers, independent from dimension to dimension and from
//! sample to sample (PCG32 streams; see `sampler/mod.rs` for how each pixel sample's stream is
//! derived from the seed, so that images do not depend on the thread count).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `sample_count` (0.6: `sampleCount`) | integer | 4 | — | samples per pixel (the command line's `--spp` overrides it); between 1 and 16777216 |
//! | `seed` | integer | 0 | — | seed of the random sequence (the command line's `--seed` overrides it); non-negative |
//! | `adaptive` | boolean | false | — | an ophis extension: the same samples in all, a quarter of them spread evenly and the rest where the neighbouring pixels are noisiest (see `render/adaptive.rs`) |
//!
//! Known limits: none. Mitsuba's low-discrepancy samplers load as `sobol` (its own file).

use super::SamplerKind;
use crate::plugin::{declare, Args, Check, Param, SceneError};
use crate::scene::SamplerSettings;

/// Mitsuba's default sample count.
const DEFAULT_SPP: i64 = 4;

/// The parameters every sampler reads.
pub(super) const COUNT_AND_SEED: &[Param] = &[
    Param::int("sample_count", DEFAULT_SPP)
        .v06("sampleCount")
        .check(Check::Range(1.0, (1 << 24) as f64))
        .doc("samples per pixel (the command line's `--spp` overrides it)"),
    Param::int("seed", 0)
        .check(Check::NonNegative)
        .doc("seed of the random sequence (the command line's `--seed` overrides it)"),
    Param::bool("adaptive", false).doc(
        "an ophis extension: the same samples in all, a quarter of them spread evenly and the \
         rest where the neighbouring pixels are noisiest (see `render/adaptive.rs`)",
    ),
];

declare!(PLUGIN: SamplerSettings = Sampler "independent" []
    "independent uniform random numbers (PCG32)"
    [COUNT_AND_SEED] load);

fn load(a: &mut Args, _: ()) -> Result<SamplerSettings, SceneError> {
    settings(a, SamplerKind::Independent)
}

/// The settings of a sampler of `kind`, read through [`COUNT_AND_SEED`].
pub(super) fn settings(a: &Args, kind: SamplerKind) -> Result<SamplerSettings, SceneError> {
    Ok(SamplerSettings {
        kind,
        spp: a.u32("sample_count")?,
        seed: a.int("seed")? as u64,
        adaptive: a.bool("adaptive")?,
    })
}

impl Default for SamplerSettings {
    /// Mitsuba's sampler without parameters (also used without a `<sampler>`).
    fn default() -> Self {
        SamplerSettings {
            kind: SamplerKind::Independent,
            spp: DEFAULT_SPP as u32,
            seed: 0,
            adaptive: false,
        }
    }
}
