//! What identifies a render's scene, stored in its EXR header so that `ophis merge` can refuse
//! renders of different scenes.
//!
//! `ophis.scene_hash` is a 64-bit FNV-1a hash (16 hex digits) of the scene as loaded: the
//! tree after `<include>`s, `<default>`s and `-D` values are resolved, i.e. every object's tag,
//! plugin, id and name, and every parameter's name and parsed value, in document order. So it
//! changes with anything that changes the expected image (a colour, a `-D` value, an included
//! file, the resolution, the film's filter) and not with comments, whitespace, the file's
//! location, or how a value was spelled (`1` or `1.0`, `intIOR` or `int_ior`). The sampler's
//! `seed` and `sample_count` are left out on purpose: renders of one scene with different
//! seeds and sample counts are exactly what merging combines, even when a farm passes them as
//! `-Dseed=…`. Files a parameter names (meshes, textures, `.spd` spectra) enter by their name
//! only, not their contents.
//!
//! `ophis.scene` is a readable name for messages: the scene's file name and its `-D` values.

use crate::film::Film;
use crate::scene::mitsuba::{Node, SpectrumValue, Tag, Value};

use super::{
    encode_tile_spp, film_tile_spp, KEY_SAMPLES, KEY_SCENE, KEY_SCENE_HASH, KEY_SEED, KEY_SPP,
    KEY_TILE_SPP,
};

/// A scene's identity: a hash of its resolved tree and a readable name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneIdentity {
    /// File name and `-D` values, e.g. `snake.xml -Dthickness=300` (Latin-1, as EXR needs).
    pub name: String,
    /// Hash of the resolved scene tree (see the module documentation).
    pub hash: u64,
}

impl SceneIdentity {
    /// The identity of a loaded scene tree; `file_name` and `defines` make the readable name.
    pub fn of(root: &Node, file_name: &str, defines: &[(String, String)]) -> SceneIdentity {
        let mut h = Fnv::new();
        hash_node(&mut h, root);
        let mut name = file_name.to_string();
        for (k, v) in defines {
            name.push_str(&format!(" -D{k}={v}"));
        }
        SceneIdentity {
            name: latin1(&name),
            hash: h.0,
        }
    }

    /// The hash as written in the header: 16 lowercase hex digits.
    pub fn hash_hex(&self) -> String {
        format!("{:016x}", self.hash)
    }
}

/// The header of a render: sample counts, seed and scene identity, in the keys `ophis merge`
/// reads. `spp_complete` is the number of samples every pixel has.
pub fn render_metadata(
    film: &Film,
    spp_complete: u32,
    seed: u64,
    scene: &SceneIdentity,
) -> Vec<(String, String)> {
    vec![
        (KEY_SPP.to_string(), spp_complete.to_string()),
        (
            KEY_SAMPLES.to_string(),
            (film.total_weight() as u64).to_string(),
        ),
        (
            KEY_TILE_SPP.to_string(),
            encode_tile_spp(&film_tile_spp(film)),
        ),
        (KEY_SEED.to_string(), seed.to_string()),
        (KEY_SCENE.to_string(), scene.name.clone()),
        (KEY_SCENE_HASH.to_string(), scene.hash_hex()),
    ]
}

/// EXR text attributes are Latin-1; other characters become `?`.
fn latin1(s: &str) -> String {
    s.chars()
        .map(|c| if (c as u32) < 256 { c } else { '?' })
        .collect()
}

/// FNV-1a, 64 bit, over length-prefixed fields (so that "ab","c" and "a","bc" differ).
struct Fnv(u64);

impl Fnv {
    fn new() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, b: &[u8]) {
        for &x in (b.len() as u64).to_le_bytes().iter().chain(b) {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn str(&mut self, s: &str) {
        self.bytes(s.as_bytes());
    }
}

fn hash_node(h: &mut Fnv, node: &Node) {
    h.str(node.tag.as_str());
    h.str(&node.plugin);
    h.str(node.id.as_deref().unwrap_or(""));
    for (name, value, _) in node.props.iter() {
        if node.tag == Tag::Sampler && (name == "seed" || name == "sample_count") {
            continue;
        }
        h.str(name);
        hash_value(h, value);
    }
    for c in &node.children {
        h.str("child");
        h.str(c.name.as_deref().unwrap_or(""));
        hash_node(h, &c.node);
    }
    h.str("end");
}

fn hash_value(h: &mut Fnv, v: &Value) {
    h.str(v.type_name());
    match v {
        // Only the file's name: the same scene on another machine lives under another folder.
        Value::Spectrum(SpectrumValue::File(p)) => {
            h.str(&p.file_name().unwrap_or_default().to_string_lossy());
        }
        Value::Float(x) => h.bytes(&x.to_bits().to_le_bytes()),
        // Debug output of the parsed value is deterministic (floats print their shortest
        // round-tripping form), and covers every other variant without a second list of them.
        other => h.str(&format!("{other:?}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mitsuba::load_str;
    use std::path::Path;

    fn id(xml: &str, defines: &[(&str, &str)]) -> SceneIdentity {
        let d: Vec<(String, String)> = defines
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        let (root, _) = load_str(xml, Path::new("t.xml"), &d).unwrap();
        SceneIdentity::of(&root, "t.xml", &d)
    }

    const SCENE: &str = r#"<scene version="3.0.0">
        <default name="spp" value="4"/><default name="seed" value="0"/>
        <default name="r" value="0.5"/>
        <sensor type="perspective"><sampler type="independent">
            <integer name="sample_count" value="$spp"/><integer name="seed" value="$seed"/>
        </sampler><film type="hdrfilm"><integer name="width" value="8"/></film></sensor>
        <shape type="sphere"><bsdf type="diffuse"><rgb name="reflectance" value="$r"/></bsdf></shape>
    </scene>"#;

    #[test]
    fn hash_follows_the_scene_not_its_spelling_seed_or_spp() {
        let base = id(SCENE, &[]);
        assert_eq!(base.name, "t.xml");
        assert_eq!(base.hash_hex().len(), 16);
        // Seeds and sample counts are what merging combines.
        assert_eq!(id(SCENE, &[("seed", "7"), ("spp", "64")]).hash, base.hash);
        // Whitespace, comments and number spelling do not matter.
        let respelled = SCENE
            .replace("value=\"0.5\"", "value=\"0.50\"")
            .replace("<shape", "<!-- a ball -->\n   <shape");
        assert_eq!(id(&respelled, &[]).hash, base.hash);
        // A colour, a resolution, a plugin change it.
        let other = id(SCENE, &[("r", "0.6")]);
        assert_ne!(other.hash, base.hash);
        assert_eq!(other.name, "t.xml -Dr=0.6");
        assert_ne!(id(&SCENE.replace("\"8\"", "\"9\""), &[]).hash, base.hash);
        assert_ne!(
            id(&SCENE.replace("\"diffuse\"", "\"conductor\""), &[]).hash,
            base.hash
        );
    }

    #[test]
    fn names_are_latin1() {
        assert_eq!(latin1("schlange-ü-蛇.xml"), "schlange-ü-?.xml");
    }
}
