//! `sobol`: Owen-scrambled Sobol points (Burley 2020, "Practical Hash-based Owen Scrambling",
//! JCGT 9(4), through the `sobol_burley` crate), a low-discrepancy sequence whose images
//! converge faster than independent samples' on smooth integrands.
//!
//! Mitsuba's other low-discrepancy or stratified samplers (3.x `stratified`, `multijitter`,
//! `orthogonal`, `ldsampler`; 0.6 `halton`, `hammersley`) all ask for well-spread samples and
//! load as this one.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `sample_count` (0.6: `sampleCount`) | integer | 4 | — | samples per pixel (the command line's `--spp` overrides it); between 1 and 16777216 |
//! | `seed` | integer | 0 | — | seed of the random sequence (the command line's `--seed` overrides it); non-negative |
//! | `adaptive` | boolean | false | — | an ophis extension: the same samples in all, a quarter of them spread evenly and the rest where the neighbouring pixels are noisiest (see `render/adaptive.rs`) |
//!
//! A path's dimensions come in sets of four (see `sampler/mod.rs`): the camera's and the first
//! vertex's are dimensions of one sequence chosen for well-stratified 2D pairs, later sets are
//! padded (each the sequence's first four dimensions with its own scramble), so deep paths keep
//! stratified samples. Known limits: 2¹⁶ samples per pixel; beyond that, samples continue as
//! independent ones. Mitsuba's `jitter`, `strength`
//! and `dimension` are not read.

use super::SamplerKind;
use crate::plugin::{declare, Args, SceneError};
use crate::scene::SamplerSettings;

declare!(PLUGIN: SamplerSettings = Sampler "sobol"
    ["stratified", "multijitter", "ldsampler", "orthogonal", "halton", "hammersley"]
    "Owen-scrambled Sobol points (Mitsuba's low-discrepancy samplers load as this one)"
    [super::independent::COUNT_AND_SEED] load);

fn load(a: &mut Args, _: ()) -> Result<SamplerSettings, SceneError> {
    super::independent::settings(a, SamplerKind::Sobol)
}
