//! Combining independent renders of one scene (different seeds, different machines) into the
//! image one render with all their samples would have made.
//!
//! Each EXR ophis writes holds per-pixel means of linear sRGB and, in its header, how many
//! samples each pixel got: `ophis.samples` (total) and `ophis.tile_spp`, the samples per
//! pixel of every 32×32 tile in row-major order, run-length encoded as `count*run` items
//! separated by commas (`64*920` for a finished 1280×720 render; an interrupted render has
//! tiles one pass ahead of others). The weighted mean of means, each weighted by its pixel's
//! sample count, is exactly the mean over all samples (up to float rounding). An adaptive
//! render's pixels hold different counts within a tile; its tiles record their pixels' mean
//! count, rounded, so its pixels are weighted by their tile's mean: still an unbiased mean of
//! independent estimates, only not exactly the one all samples together would give.
//!
//! That holds only for independent renders of one scene, which a render farm can get wrong:
//! two tasks given the same seed take the very same samples (merging them would claim twice the
//! samples with no new information), and a part rendered from another scene, or with other
//! `-D` values, at the same resolution would blend silently. So [`merge`] refuses inputs whose
//! seeds overlap (`ophis.seed`, a comma-separated list in merged files) and inputs whose
//! `ophis.scene_hash` differ (see [`identity`]), naming the files. Files written before these
//! keys existed merge with a warning that the check could not be made.

mod identity;
#[cfg(test)]
mod tests;

pub use identity::{render_metadata, SceneIdentity};

use crate::film::Film;
use crate::image_io::RgbImage;
use crate::render::{tile_spp, TILE};

/// Metadata key of the total sample count.
pub const KEY_SAMPLES: &str = "ophis.samples";
/// Metadata key of the complete samples per pixel.
pub(crate) const KEY_SPP: &str = "ophis.spp";
/// Metadata key of the per-tile samples per pixel.
pub const KEY_TILE_SPP: &str = "ophis.tile_spp";
/// Metadata key of the seed (a comma-separated list of seeds in a merged file).
pub(crate) const KEY_SEED: &str = "ophis.seed";
/// Header key listing the AOV channels of an `aov` render (which merging would drop).
pub const KEY_AOVS: &str = "ophis.aovs";
/// Metadata key of the readable scene name (file name and `-D` values).
pub(crate) const KEY_SCENE: &str = "ophis.scene";
/// Metadata key of the scene hash ([`SceneIdentity::hash_hex`]).
pub(crate) const KEY_SCENE_HASH: &str = "ophis.scene_hash";

/// Run-length encodes a list of per-tile counts.
pub(crate) fn encode_tile_spp(counts: &[u64]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < counts.len() {
        let mut j = i;
        while j < counts.len() && counts[j] == counts[i] {
            j += 1;
        }
        out.push(format!("{}*{}", counts[i], j - i));
        i = j;
    }
    out.join(",")
}

/// Per-tile sample counts of a film, row-major.
pub(crate) fn film_tile_spp(film: &Film) -> Vec<u64> {
    let mut v = Vec::new();
    for ty in 0..film.height.div_ceil(TILE) {
        for tx in 0..film.width.div_ceil(TILE) {
            v.push(if film.adaptive.is_some() {
                tile_mean_count(film, tx * TILE, ty * TILE)
            } else {
                tile_spp(film, tx * TILE, ty * TILE) as u64
            });
        }
    }
    v
}

/// The mean sample count of the pixels of the tile at (x0, y0), rounded.
fn tile_mean_count(film: &Film, x0: u32, y0: u32) -> u64 {
    let (x1, y1) = ((x0 + TILE).min(film.width), (y0 + TILE).min(film.height));
    let sum: f64 = (y0..y1)
        .flat_map(|y| (x0..x1).map(move |x| (y * film.width + x) as usize))
        .map(|i| film.pixels[i][3])
        .sum();
    (sum / ((x1 - x0) * (y1 - y0)) as f64).round() as u64
}

/// Decodes `ophis.tile_spp` into one count per pixel of a `width × height` image.
pub fn decode_tile_spp(s: &str, width: usize, height: usize) -> Result<Vec<u64>, String> {
    let t = TILE as usize;
    let (tw, th) = (width.div_ceil(t), height.div_ceil(t));
    let mut tiles = Vec::with_capacity(tw * th);
    for item in s.split(',') {
        let (c, n) = item
            .split_once('*')
            .ok_or_else(|| format!("'{item}' where COUNT*RUN was expected"))?;
        let c: u64 = c.trim().parse().map_err(|_| format!("count '{c}'"))?;
        let n: usize = n.trim().parse().map_err(|_| format!("run '{n}'"))?;
        if tiles.len() + n > tw * th {
            return Err(format!("more than the {} tiles of the image", tw * th));
        }
        tiles.extend(std::iter::repeat_n(c, n));
    }
    if tiles.len() != tw * th {
        return Err(format!(
            "{} tiles where {} were expected",
            tiles.len(),
            tw * th
        ));
    }
    let mut px = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            px.push(tiles[(y / t) * tw + x / t]);
        }
    }
    Ok(px)
}

/// One render to merge: its image, its metadata and a name for messages.
pub struct MergeInput {
    pub name: String,
    pub image: RgbImage,
    pub metadata: Vec<(String, String)>,
}

fn meta<'a>(m: &'a [(String, String)], key: &str) -> Option<&'a str> {
    m.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

/// Per-pixel sample counts of an input, from `ophis.tile_spp`, or spread evenly from
/// `ophis.samples` when an older file lacks it.
fn pixel_counts(inp: &MergeInput) -> Result<Vec<u64>, String> {
    let (w, h) = (inp.image.width, inp.image.height);
    if let Some(s) = meta(&inp.metadata, KEY_TILE_SPP) {
        return decode_tile_spp(s, w, h)
            .map_err(|e| format!("{}: bad {KEY_TILE_SPP}: found {e}", inp.name));
    }
    let total = meta(&inp.metadata, KEY_SAMPLES).ok_or_else(|| {
        format!(
            "{}: no '{KEY_SAMPLES}' in the EXR header; only images written by `ophis render` \
             carry the sample counts that merging needs",
            inp.name
        )
    })?;
    let total: u64 = total
        .parse()
        .map_err(|_| format!("{}: {KEY_SAMPLES} is '{total}', not a count", inp.name))?;
    let n = (w * h) as u64;
    if !total.is_multiple_of(n) {
        return Err(format!(
            "{}: {total} samples do not spread evenly over {w} × {h} pixels and there is no {KEY_TILE_SPP}",
            inp.name
        ));
    }
    Ok(vec![total / n; w * h])
}

/// A merged image, its header (summed counts, the seeds, the scene), and what could not be
/// checked.
#[derive(Debug)]
pub struct Merged {
    pub image: RgbImage,
    pub metadata: Vec<(String, String)>,
    /// Inputs whose seed or scene could not be checked (files from before those keys existed).
    pub warnings: Vec<String>,
}

/// The seeds an input holds samples of: `ophis.seed` is one seed, or a list in merged files.
fn seeds_of(inp: &MergeInput) -> Result<Option<Vec<u64>>, String> {
    let Some(s) = meta(&inp.metadata, KEY_SEED) else {
        return Ok(None);
    };
    s.split(',')
        .map(|t| t.trim().parse::<u64>())
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
        .map_err(|_| {
            format!(
                "{}: {KEY_SEED} is '{s}', not a seed or comma-separated seeds",
                inp.name
            )
        })
}

/// "snake.xml -Dthickness=300 (scene hash 0123…)" for messages.
fn scene_of(inp: &MergeInput) -> String {
    format!(
        "{} (scene hash {})",
        meta(&inp.metadata, KEY_SCENE).unwrap_or("an unnamed scene"),
        meta(&inp.metadata, KEY_SCENE_HASH).unwrap_or("?")
    )
}

/// Merges renders weighted per pixel by their sample counts. Refuses inputs of different
/// resolutions, of different scenes, or whose seeds overlap, naming the files. The result's
/// metadata carries the summed counts, every seed and the scene, ready to merge again.
pub fn merge(inputs: &[MergeInput]) -> Result<Merged, String> {
    let first = inputs.first().ok_or("nothing to merge")?;
    let (w, h) = (first.image.width, first.image.height);
    let mut sum = vec![[0.0f64; 3]; w * h];
    let mut count = vec![0u64; w * h];
    // (seed, the input that holds it)
    let mut seen: Vec<(u64, &str)> = Vec::new();
    let mut warnings = Vec::new();
    // The output claims a seed list or a scene only when every input had one.
    let (mut all_seeded, mut all_hashed) = (true, true);
    let hashed = inputs
        .iter()
        .find(|i| meta(&i.metadata, KEY_SCENE_HASH).is_some());
    for inp in inputs {
        if (inp.image.width, inp.image.height) != (w, h) {
            return Err(format!(
                "{} is {} × {} but {} is {w} × {h}: only renders of the same resolution merge",
                inp.name, inp.image.width, inp.image.height, first.name
            ));
        }
        if let Some(list) = meta(&inp.metadata, KEY_AOVS) {
            return Err(format!(
                "{} carries AOV channels ({list}); ophis merge combines only R, G and B and would \
                 drop them: merge renders of the scene without its aov integrator, or render \
                 the AOVs once at the full sample count",
                inp.name
            ));
        }
        match (meta(&inp.metadata, KEY_SCENE_HASH), hashed) {
            (Some(a), Some(f)) if Some(a) != meta(&f.metadata, KEY_SCENE_HASH) => {
                return Err(format!(
                    "{} renders {} but {} renders {}: only renders of the same scene, with the \
                     same -D values, merge",
                    inp.name,
                    scene_of(inp),
                    f.name,
                    scene_of(f)
                ));
            }
            (Some(_), _) => {}
            (None, _) => {
                all_hashed = false;
                warnings.push(format!(
                    "{} has no {KEY_SCENE_HASH} (written by an older ophis): cannot check that it \
                 renders the same scene",
                    inp.name
                ));
            }
        }
        match seeds_of(inp)? {
            Some(seeds) => {
                for s in seeds {
                    if let Some((_, other)) = seen.iter().find(|(t, _)| *t == s) {
                        let (a, b) = (other, &inp.name);
                        return Err(if a == b {
                            format!("{b} lists seed {s} twice in {KEY_SEED}")
                        } else {
                            format!(
                                "{a} and {b} both hold samples of seed {s}: renders with the \
                                 same seed take the same samples, so merging them would count \
                                 each sample twice; render each part with its own --seed"
                            )
                        });
                    }
                    seen.push((s, &inp.name));
                }
            }
            None => {
                all_seeded = false;
                warnings.push(format!(
                    "{} has no {KEY_SEED}: cannot check that its samples are independent of \
                     the others'",
                    inp.name
                ));
            }
        }
        let c = pixel_counts(inp)?;
        for (i, (s, px)) in sum.iter_mut().zip(&inp.image.data).enumerate() {
            for (acc, v) in s.iter_mut().zip(px) {
                *acc += *v as f64 * c[i] as f64;
            }
            count[i] += c[i];
        }
    }
    let data = sum
        .iter()
        .zip(&count)
        .map(|(s, &c)| {
            if c == 0 {
                [0.0; 3]
            } else {
                s.map(|v| (v / c as f64) as f32)
            }
        })
        .collect();
    let t = TILE as usize;
    let tiles: Vec<u64> = (0..h.div_ceil(t))
        .flat_map(|ty| (0..w.div_ceil(t)).map(move |tx| (tx, ty)))
        .map(|(tx, ty)| count[ty * t * w + tx * t])
        .collect();
    let seeds: Vec<String> = seen.iter().map(|(s, _)| s.to_string()).collect();
    let mut metadata = vec![
        (
            KEY_SPP.to_string(),
            tiles.iter().min().unwrap_or(&0).to_string(),
        ),
        (
            KEY_SAMPLES.to_string(),
            count.iter().sum::<u64>().to_string(),
        ),
        (KEY_TILE_SPP.to_string(), encode_tile_spp(&tiles)),
    ];
    if all_seeded {
        metadata.push((KEY_SEED.to_string(), seeds.join(",")));
    }
    if let (true, Some(f)) = (all_hashed, hashed) {
        for key in [KEY_SCENE, KEY_SCENE_HASH] {
            if let Some(v) = meta(&f.metadata, key) {
                metadata.push((key.to_string(), v.to_string()));
            }
        }
    }
    Ok(Merged {
        image: RgbImage {
            width: w,
            height: h,
            data,
        },
        metadata,
        warnings,
    })
}
