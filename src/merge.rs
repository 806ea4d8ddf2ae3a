//! Combining independent renders of one scene (different seeds, different machines) into the
//! image one render with all their samples would have made.
//!
//! Each EXR ophis writes holds per-pixel means of linear sRGB and, in its header, how many
//! samples each pixel got: `ophis.samples` (total) and `ophis.tile_spp`, the samples per
//! pixel of every 32×32 tile in row-major order, run-length encoded as `count*run` items
//! separated by commas (`64*920` for a finished 1280×720 render; an interrupted render has
//! tiles one pass ahead of others). The weighted mean of means, each weighted by its pixel's
//! sample count, is exactly the mean over all samples (up to float rounding).

use crate::film::Film;
use crate::image_io::RgbImage;
use crate::render::{tile_spp, TILE};

/// Metadata key of the total sample count.
pub const KEY_SAMPLES: &str = "ophis.samples";
/// Metadata key of the complete samples per pixel.
pub const KEY_SPP: &str = "ophis.spp";
/// Metadata key of the per-tile samples per pixel.
pub const KEY_TILE_SPP: &str = "ophis.tile_spp";
/// Metadata key of the seed.
pub const KEY_SEED: &str = "ophis.seed";
/// Header key listing the AOV channels of an `aov` render (which merging would drop).
pub const KEY_AOVS: &str = "ophis.aovs";

/// Run-length encodes a list of per-tile counts.
pub fn encode_tile_spp(counts: &[u64]) -> String {
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
pub fn film_tile_spp(film: &Film) -> Vec<u64> {
    let mut v = Vec::new();
    for ty in 0..film.height.div_ceil(TILE) {
        for tx in 0..film.width.div_ceil(TILE) {
            v.push(tile_spp(film, tx * TILE, ty * TILE) as u64);
        }
    }
    v
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
    if total % n != 0 {
        return Err(format!(
            "{}: {total} samples do not spread evenly over {w} × {h} pixels and there is no {KEY_TILE_SPP}",
            inp.name
        ));
    }
    Ok(vec![total / n; w * h])
}

/// Merges renders weighted per pixel by their sample counts. Returns the image and its
/// metadata (summed counts, the list of seeds), ready to merge again.
pub fn merge(inputs: &[MergeInput]) -> Result<(RgbImage, Vec<(String, String)>), String> {
    let first = inputs.first().ok_or("nothing to merge")?;
    let (w, h) = (first.image.width, first.image.height);
    let mut sum = vec![[0.0f64; 3]; w * h];
    let mut count = vec![0u64; w * h];
    let mut seeds = Vec::new();
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
        let c = pixel_counts(inp)?;
        for (i, (s, px)) in sum.iter_mut().zip(&inp.image.data).enumerate() {
            for (acc, v) in s.iter_mut().zip(px) {
                *acc += *v as f64 * c[i] as f64;
            }
            count[i] += c[i];
        }
        seeds.push(meta(&inp.metadata, KEY_SEED).unwrap_or("?").to_string());
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
    let meta = vec![
        (
            KEY_SPP.to_string(),
            tiles.iter().min().unwrap_or(&0).to_string(),
        ),
        (
            KEY_SAMPLES.to_string(),
            count.iter().sum::<u64>().to_string(),
        ),
        (KEY_TILE_SPP.to_string(), encode_tile_spp(&tiles)),
        (KEY_SEED.to_string(), seeds.join(",")),
    ];
    Ok((
        RgbImage {
            width: w,
            height: h,
            data,
        },
        meta,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tile_counts_round_trip() {
        let counts = [4, 4, 4, 2, 2, 4];
        let s = encode_tile_spp(&counts);
        assert_eq!(s, "4*3,2*2,4*1");
        // 70 × 40 pixels = 3 × 2 tiles.
        let px = decode_tile_spp(&s, 70, 40).unwrap();
        assert_eq!(px[0], 4);
        assert_eq!(px[69], 4);
        assert_eq!(px[39 * 70], 2);
        assert_eq!(px[39 * 70 + 69], 4);
        for bad in ["", "4", "4*7", "x*1", "4*3,2*2", "4*3,2*2,4*1,1*1"] {
            assert!(decode_tile_spp(bad, 70, 40).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn merge_weights_by_counts_and_refuses_mismatches() {
        let img = |v: f32, w| RgbImage {
            width: w,
            height: 1,
            data: vec![[v; 3]; w],
        };
        let a = MergeInput {
            name: "a".into(),
            image: img(1.0, 2),
            metadata: vec![(KEY_SAMPLES.into(), "2".into())],
        };
        let b = MergeInput {
            name: "b".into(),
            image: img(4.0, 2),
            metadata: vec![(KEY_TILE_SPP.into(), "3*1".into())],
        };
        let (m, meta) = merge(&[a, b]).unwrap();
        assert_eq!(m.data[0], [(1.0 + 12.0) / 4.0; 3]);
        assert!(meta.contains(&(KEY_SAMPLES.into(), "8".into())));
        let c = MergeInput {
            name: "c".into(),
            image: img(1.0, 3),
            metadata: vec![(KEY_SAMPLES.into(), "3".into())],
        };
        let d = MergeInput {
            name: "d".into(),
            image: img(1.0, 2),
            metadata: vec![],
        };
        let e = merge(&[d]).unwrap_err();
        assert!(e.contains("d: no 'ophis.samples'"), "{e}");
        let a2 = MergeInput {
            name: "a".into(),
            image: img(1.0, 2),
            metadata: vec![(KEY_SAMPLES.into(), "2".into())],
        };
        let e = merge(&[a2, c]).unwrap_err();
        assert!(e.contains("same resolution"), "{e}");
        let with_aovs = MergeInput {
            name: "aov.exr".into(),
            image: img(1.0, 2),
            metadata: vec![
                (KEY_SAMPLES.into(), "2".into()),
                (KEY_AOVS.into(), "dd.T".into()),
            ],
        };
        let e = merge(&[with_aovs]).unwrap_err();
        assert!(e.contains("aov.exr carries AOV channels (dd.T)"), "{e}");
    }
}
