//! Unit tests of merging: count weighting, and the refusals a render farm needs.

use super::*;

fn img(v: f32, w: usize) -> RgbImage {
    RgbImage {
        width: w,
        height: 1,
        data: vec![[v; 3]; w],
    }
}

fn input(name: &str, v: f32, w: usize, meta: &[(&str, &str)]) -> MergeInput {
    MergeInput {
        name: name.into(),
        image: img(v, w),
        metadata: meta
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
    }
}

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
    let a = input("a", 1.0, 2, &[(KEY_SAMPLES, "2")]);
    let b = input("b", 4.0, 2, &[(KEY_TILE_SPP, "3*1")]);
    let m = merge(&[a, b]).unwrap();
    assert_eq!(m.image.data[0], [(1.0 + 12.0) / 4.0; 3]);
    assert!(m.metadata.contains(&(KEY_SAMPLES.into(), "8".into())));
    // Neither input could be checked for seed or scene, so the output claims neither.
    assert_eq!(m.warnings.len(), 4, "{:?}", m.warnings);
    assert!(!m.metadata.iter().any(|(k, _)| k == KEY_SEED));
    let e = merge(&[input("d", 1.0, 2, &[])]).unwrap_err();
    assert!(e.contains("d: no 'ophis.samples'"), "{e}");
    let a2 = input("a", 1.0, 2, &[(KEY_SAMPLES, "2")]);
    let c = input("c", 1.0, 3, &[(KEY_SAMPLES, "3")]);
    let e = merge(&[a2, c]).unwrap_err();
    assert!(e.contains("same resolution"), "{e}");
}

const H1: &str = "00000000000000a1";
const H2: &str = "00000000000000b2";

fn part(name: &str, seed: &str, hash: &str) -> MergeInput {
    input(
        name,
        1.0,
        2,
        &[
            (KEY_TILE_SPP, "4*1"),
            (KEY_SEED, seed),
            (KEY_SCENE, "snake.xml -Dthickness=300"),
            (KEY_SCENE_HASH, hash),
        ],
    )
}

#[test]
fn refuses_repeated_seeds_by_name() {
    let e = merge(&[part("p1.exr", "1", H1), part("p1-again.exr", "1", H1)]).unwrap_err();
    assert!(
        e.contains("p1.exr and p1-again.exr both hold samples of seed 1"),
        "{e}"
    );
    // A merged file lists its seeds; merging it with one of its own parts is refused too.
    let m = merge(&[part("p1.exr", "1", H1), part("p2.exr", "2", H1)]).unwrap();
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    assert!(m.metadata.contains(&(KEY_SEED.into(), "1,2".into())));
    assert!(m.metadata.contains(&(KEY_SCENE_HASH.into(), H1.into())));
    assert!(m
        .metadata
        .contains(&(KEY_SCENE.into(), "snake.xml -Dthickness=300".into())));
    let merged = MergeInput {
        name: "m.exr".into(),
        image: m.image,
        metadata: m.metadata,
    };
    let e = merge(&[part("p3.exr", "3", H1), merged, part("p2.exr", "2", H1)]).unwrap_err();
    assert!(
        e.contains("m.exr and p2.exr both hold samples of seed 2"),
        "{e}"
    );
    let e = merge(&[part("x.exr", "4,4", H1)]).unwrap_err();
    assert!(e.contains("x.exr lists seed 4 twice"), "{e}");
    let e = merge(&[part("x.exr", "four", H1)]).unwrap_err();
    assert!(e.contains("x.exr: ophis.seed is 'four'"), "{e}");
}

#[test]
fn refuses_other_scenes_by_name() {
    let mut other = part("other.exr", "2", H2);
    other.metadata[2].1 = "snake.xml -Dthickness=320".into();
    let e = merge(&[part("p1.exr", "1", H1), other]).unwrap_err();
    assert!(
        e.contains(&format!(
            "other.exr renders snake.xml -Dthickness=320 (scene hash {H2}) but p1.exr renders \
             snake.xml -Dthickness=300 (scene hash {H1})"
        )),
        "{e}"
    );
    // An older file without the hash merges, with a warning, and the output claims no scene.
    let old = input("old.exr", 3.0, 2, &[(KEY_TILE_SPP, "4*1"), (KEY_SEED, "9")]);
    let m = merge(&[old, part("p1.exr", "1", H1)]).unwrap();
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    assert!(m.warnings[0].starts_with("old.exr has no ophis.scene_hash"));
    assert!(!m.metadata.iter().any(|(k, _)| k == KEY_SCENE_HASH));
    assert_eq!(m.image.data[0], [2.0; 3]);
}

#[test]
fn refuses_renders_carrying_aov_channels() {
    let with_aovs = input("aov.exr", 1.0, 2, &[(KEY_SAMPLES, "2"), (KEY_AOVS, "dd.T")]);
    let e = merge(&[with_aovs]).unwrap_err();
    assert!(e.contains("aov.exr carries AOV channels (dd.T)"), "{e}");
}
