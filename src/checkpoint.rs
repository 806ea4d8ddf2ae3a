//! Render state files: the accumulated film of an unfinished render plus what is needed to
//! continue it (`ophis render --checkpoint` writes them, `ophis render --resume` reads them).
//!
//! Format (all integers little-endian), version 1 (version 2 when the film has AOV channels,
//! with the two fields marked ² added; version 3 for an adaptive render, with the fields
//! marked ² — the AOV count possibly 0 — and ³):
//!
//! | field        | type                     | meaning                                        |
//! |--------------|--------------------------|------------------------------------------------|
//! | magic        | 8 bytes `OPHISST\0`      |                                                |
//! | version      | u32                      | 1                                              |
//! | scene_hash   | u64                      | FNV-1a of the scene file's bytes               |
//! | seed         | u64                      | sampler seed                                   |
//! | spp          | u32                      | target samples per pixel                       |
//! | width,height | u32, u32                 | film resolution                                |
//! | scene_path   | string (u32 length, UTF-8)| the scene file, absolute                      |
//! | strategy     | string                   | estimator name (`mis`, `light`, `bsdf`)        |
//! | defines      | u32 count, string pairs  | `-D name=value` overrides                      |
//! | aov names ²  | u32 count c, strings     | the `aov` integrator's channel names           |
//! | pixels       | width·height·4 f64       | X, Y, Z sums and sample count per pixel        |
//! | aov sums ²   | width·height·c f64       | AOV channel sums per pixel, row-major          |
//! | spp, pilot ³ | u32, u32                 | the adaptive render's target and pilot         |
//! | targets? ³   | u32                      | 1 once the per-pixel targets are set, else 0   |
//! | Y² sums ³    | width·height f64         | the pilot's sums of squared luminance          |
//! | progress ³   | width·height u32         | nominal sample each pixel's passes reached     |
//! | targets ³    | width·height u32         | per-pixel target counts (only when set)        |
//! | checksum     | u64                      | FNV-1a of every byte before it                 |
//!
//! The film is stored as f64 sums, exactly as held in memory, so a resumed render continues
//! bit for bit. Files are written to a temporary name beside the target, synced, then renamed
//! over it: a crash leaves either the old state or the new one, never half of one. Only the
//! scene file itself is hashed, not the files it includes or the meshes it loads.

use crate::film::Film;
use crate::render::adaptive::{Adaptive, MAX_FACTOR};
use std::io::Write;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"OPHISST\0";
const VERSION: u32 = 1;
/// The version of files whose film carries AOV channels.
const VERSION_AOV: u32 = 2;
/// The version of files of an adaptive render.
const VERSION_ADAPTIVE: u32 = 3;
/// Most AOV channels accepted when reading.
const MAX_AOV_CHANNELS: u32 = 1024;
/// Longest string field accepted when reading (paths, names, define values).
const MAX_STRING: u32 = 1 << 16;
/// Most `-D` pairs accepted when reading.
const MAX_DEFINES: u32 = 4096;

/// What went wrong reading or writing a state file; each variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum StateError {
    #[error("{path}: cannot read render state: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: cannot write render state: {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: not an ophis render state file (found {found}, expected {expected})")]
    Malformed {
        path: PathBuf,
        found: String,
        expected: String,
    },
}

/// What a render state records besides the film.
#[derive(Clone, Debug, PartialEq)]
pub struct StateInfo {
    /// The scene file (absolute path).
    pub scene_path: PathBuf,
    /// [`hash_bytes`] of the scene file.
    pub scene_hash: u64,
    /// Sampler seed.
    pub seed: u64,
    /// Target samples per pixel.
    pub spp: u32,
    /// Estimator name.
    pub strategy: String,
    /// `-D` overrides, in command-line order.
    pub defines: Vec<(String, String)>,
}

/// An unfinished render: settings and the accumulated film.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderState {
    pub info: StateInfo,
    /// The accumulated sums.
    pub film: Film,
}

/// FNV-1a, 64-bit: a small stable hash for identifying a scene file (not for security).
pub fn hash_bytes(bytes: &[u8]) -> u64 {
    fnv(0xcbf2_9ce4_8422_2325, bytes)
}

fn fnv(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// A writer that hashes what passes through it, so the checksum needs no second copy.
struct Hashing<W: Write> {
    w: W,
    h: u64,
}

impl<W: Write> Hashing<W> {
    fn put(&mut self, b: &[u8]) -> std::io::Result<()> {
        self.h = fnv(self.h, b);
        self.w.write_all(b)
    }
    fn put_str(&mut self, s: &str) -> std::io::Result<()> {
        self.put(&(s.len() as u32).to_le_bytes())?;
        self.put(s.as_bytes())
    }
}

impl StateInfo {
    /// Streams the state file for `film` into `w`.
    pub fn encode(&self, film: &Film, w: impl Write) -> std::io::Result<()> {
        let mut o = Hashing {
            w,
            h: 0xcbf2_9ce4_8422_2325,
        };
        o.put(MAGIC)?;
        let version = if film.adaptive.is_some() {
            VERSION_ADAPTIVE
        } else if film.aov_names.is_empty() {
            VERSION
        } else {
            VERSION_AOV
        };
        o.put(&version.to_le_bytes())?;
        o.put(&self.scene_hash.to_le_bytes())?;
        o.put(&self.seed.to_le_bytes())?;
        o.put(&self.spp.to_le_bytes())?;
        o.put(&film.width.to_le_bytes())?;
        o.put(&film.height.to_le_bytes())?;
        o.put_str(&self.scene_path.to_string_lossy())?;
        o.put_str(&self.strategy)?;
        o.put(&(self.defines.len() as u32).to_le_bytes())?;
        for (k, v) in &self.defines {
            o.put_str(k)?;
            o.put_str(v)?;
        }
        if version != VERSION {
            o.put(&(film.aov_names.len() as u32).to_le_bytes())?;
            for name in &film.aov_names {
                o.put_str(name)?;
            }
        }
        let mut buf = [0u8; 32];
        for p in &film.pixels {
            for (c, v) in buf.chunks_exact_mut(8).zip(p) {
                c.copy_from_slice(&v.to_le_bytes());
            }
            o.put(&buf)?;
        }
        for v in &film.aov {
            o.put(&v.to_le_bytes())?;
        }
        if let Some(a) = &film.adaptive {
            o.put(&a.spp.to_le_bytes())?;
            o.put(&a.pilot.to_le_bytes())?;
            o.put(&(!a.targets.is_empty() as u32).to_le_bytes())?;
            for v in &a.sq {
                o.put(&v.to_le_bytes())?;
            }
            for v in a.done.iter().chain(&a.targets) {
                o.put(&v.to_le_bytes())?;
            }
        }
        let sum = o.h;
        o.w.write_all(&sum.to_le_bytes())?;
        o.w.flush()
    }

    /// Writes the state of `film` atomically: temporary file beside `path`, fsync, rename.
    pub fn write(&self, film: &Film, path: &Path) -> Result<(), StateError> {
        let err = |source| StateError::Write {
            path: path.to_path_buf(),
            source,
        };
        let name = path.file_name().ok_or_else(|| {
            err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "no file name",
            ))
        })?;
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".{}.tmp", std::process::id()));
        let tmp = path.with_file_name(tmp_name);
        let result = (|| {
            let f = std::fs::File::create(&tmp)?;
            let mut bw = std::io::BufWriter::new(f);
            self.encode(film, &mut bw)?;
            bw.into_inner().map_err(|e| e.into_error())?.sync_all()?;
            std::fs::rename(&tmp, path)
        })();
        if let Err(e) = result {
            let _ = std::fs::remove_file(&tmp);
            return Err(err(e));
        }
        Ok(())
    }
}

impl RenderState {
    #[cfg(test)]
    /// Samples per pixel that every pixel holds.
    pub(crate) fn spp_done(&self) -> u32 {
        self.film
            .pixels
            .iter()
            .map(|p| p[3] as u32)
            .min()
            .unwrap_or(0)
    }

    #[cfg(test)]
    /// The file's bytes.
    pub(crate) fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        self.info
            .encode(&self.film, &mut out)
            .expect("writing to memory");
        out
    }

    /// Writes the state atomically.
    pub fn write(&self, path: &Path) -> Result<(), StateError> {
        self.info.write(&self.film, path)
    }

    /// Reads a state file, checking its structure and checksum before allocating the film.
    pub fn read(path: &Path) -> Result<RenderState, StateError> {
        let bytes = std::fs::read(path).map_err(|source| StateError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_bytes(&bytes, path)
    }

    /// Parses a state file's bytes (`path` names it in messages).
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<RenderState, StateError> {
        let bad = |found: String, expected: &str| StateError::Malformed {
            path: path.to_path_buf(),
            found,
            expected: expected.to_string(),
        };
        if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
            return Err(bad("a different signature".into(), "the signature OPHISST"));
        }
        if bytes.len() < MAGIC.len() + 12 {
            return Err(bad(format!("{} bytes", bytes.len()), "a complete header"));
        }
        let (body, tail) = bytes.split_at(bytes.len() - 8);
        let stored = u64::from_le_bytes(tail.try_into().expect("8 bytes"));
        let mut r = Reader {
            b: body,
            at: MAGIC.len(),
        };
        let version = r
            .u32()
            .ok_or_else(|| bad("end of file".into(), "a version"))?;
        if !(VERSION..=VERSION_ADAPTIVE).contains(&version) {
            return Err(bad(format!("version {version}"), "version 1, 2 or 3"));
        }
        if hash_bytes(body) != stored {
            return Err(bad(
                "a checksum mismatch (the file is truncated or damaged)".into(),
                "an intact file",
            ));
        }
        let trunc = || bad("end of file".into(), "a complete header");
        let scene_hash = r.u64().ok_or_else(trunc)?;
        let seed = r.u64().ok_or_else(trunc)?;
        let spp = r.u32().ok_or_else(trunc)?;
        let width = r.u32().ok_or_else(trunc)?;
        let height = r.u32().ok_or_else(trunc)?;
        let scene_path = PathBuf::from(r.string().ok_or_else(trunc)?);
        let strategy = r.string().ok_or_else(trunc)?;
        let n_defines = r.u32().ok_or_else(trunc)?;
        if n_defines > MAX_DEFINES {
            return Err(bad(format!("{n_defines} defines"), "at most 4096"));
        }
        let mut defines = Vec::new();
        for _ in 0..n_defines {
            let k = r.string().ok_or_else(trunc)?;
            let v = r.string().ok_or_else(trunc)?;
            defines.push((k, v));
        }
        let mut aov_names = Vec::new();
        if version != VERSION {
            let c = r.u32().ok_or_else(trunc)?;
            let least = (version == VERSION_AOV) as u32;
            if c < least || c > MAX_AOV_CHANNELS {
                return Err(bad(
                    format!("{c} AOV channels"),
                    &format!("{least} to {MAX_AOV_CHANNELS}"),
                ));
            }
            for _ in 0..c {
                aov_names.push(r.string().ok_or_else(trunc)?);
            }
        }
        let n = width as u64 * height as u64;
        let per_pixel = 32 + 8 * aov_names.len() as u64;
        let film_end = n
            .checked_mul(per_pixel)
            .and_then(|b| b.checked_add(r.at as u64))
            .filter(|&e| e <= r.b.len() as u64)
            .ok_or_else(|| {
                bad(
                    format!(
                        "{} bytes of pixels for {width} × {height}",
                        r.b.len() - r.at
                    ),
                    &format!("{per_pixel} bytes per pixel"),
                )
            })?;
        let adaptive = if version == VERSION_ADAPTIVE {
            let mut a = Reader {
                b: r.b,
                at: film_end.min(r.b.len() as u64) as usize,
            };
            let head = || bad("end of file".into(), "the adaptive render's header");
            let (spp, pilot, set) = (
                a.u32().ok_or_else(head)?,
                a.u32().ok_or_else(head)?,
                a.u32().ok_or_else(head)?,
            );
            if crate::render::adaptive::pilot(spp) != Some(pilot) || set > 1 {
                return Err(bad(
                    format!("spp {spp}, pilot {pilot}, targets flag {set}"),
                    "an adaptive render's pilot (a quarter of spp, at least 4) and a flag 0 or 1",
                ));
            }
            let rest = (a.b.len() - a.at) as u64;
            let want = n * (12 + 4 * set as u64);
            if rest != want {
                return Err(bad(
                    format!("{rest} bytes of adaptive state for {width} × {height}"),
                    &format!("{want} bytes"),
                ));
            }
            let (sq, ints) = a.b[a.at..].split_at((n * 8) as usize);
            let mut ints = ints
                .chunks_exact(4)
                .map(|v| u32::from_le_bytes(v.try_into().expect("4 bytes")));
            let done: Vec<u32> = ints.by_ref().take(n as usize).collect();
            let targets: Vec<u32> = ints.collect();
            let reach = if targets.is_empty() { pilot } else { spp };
            if done.iter().any(|&d| d > reach) {
                return Err(bad(
                    "a pixel's progress beyond its plan".into(),
                    "progress within the pilot until the targets are set, within spp after",
                ));
            }
            if targets
                .iter()
                .any(|&t| t < pilot || t > spp.saturating_mul(MAX_FACTOR))
            {
                return Err(bad(
                    "a target count out of range".into(),
                    "targets between the pilot and 16 × spp",
                ));
            }
            Some(Adaptive {
                spp,
                pilot,
                sq: sq
                    .chunks_exact(8)
                    .map(|v| f64::from_le_bytes(v.try_into().expect("8 bytes")))
                    .collect(),
                done,
                targets,
            })
        } else {
            None
        };
        let rest = (r.b.len() - r.at) as u64;
        if width == 0 || height == 0 || (adaptive.is_none() && rest != n * per_pixel) {
            return Err(bad(
                format!("{rest} bytes of pixels for {width} × {height}"),
                &format!("{} bytes", n * per_pixel),
            ));
        }
        let (px_bytes, aov_bytes) = r.b[r.at..film_end as usize].split_at((n * 32) as usize);
        let aov = aov_bytes
            .chunks_exact(8)
            .map(|v| f64::from_le_bytes(v.try_into().expect("8 bytes")))
            .collect();
        let mut pixels = Vec::with_capacity(n as usize);
        for chunk in px_bytes.chunks_exact(32) {
            let mut p = [0.0f64; 4];
            for (c, v) in p.iter_mut().zip(chunk.chunks_exact(8)) {
                *c = f64::from_le_bytes(v.try_into().expect("8 bytes"));
            }
            pixels.push(p);
        }
        Ok(RenderState {
            info: StateInfo {
                scene_path,
                scene_hash,
                seed,
                spp,
                strategy,
                defines,
            },
            film: Film {
                width,
                height,
                pixels,
                aov_names,
                aov,
                adaptive,
            },
        })
    }
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Option<&[u8]> {
        let s = self.b.get(self.at..self.at.checked_add(n)?)?;
        self.at += n;
        Some(s)
    }
    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.take(4)?.try_into().ok()?))
    }
    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }
    fn string(&mut self) -> Option<String> {
        let n = self.u32()?;
        if n > MAX_STRING {
            return None;
        }
        String::from_utf8(self.take(n as usize)?.to_vec()).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> RenderState {
        let mut film = Film::new(3, 2);
        for (i, p) in film.pixels.iter_mut().enumerate() {
            *p = [i as f64 * 0.1, 1.0 / 3.0, -0.0, 4.0];
        }
        RenderState {
            info: StateInfo {
                scene_path: "/scenes/a b.xml".into(),
                scene_hash: hash_bytes(b"<scene/>"),
                seed: 7,
                spp: 16,
                strategy: "mis".into(),
                defines: vec![("spp".into(), "4".into()), ("x".into(), "ü".into())],
            },
            film,
        }
    }

    #[test]
    fn round_trips_bit_for_bit() {
        let s = sample();
        let back = RenderState::from_bytes(&s.to_bytes(), Path::new("s")).unwrap();
        assert_eq!(back, s);
        assert_eq!(back.spp_done(), 4);
    }

    #[test]
    fn aov_channels_round_trip_in_version_2() {
        let mut s = sample();
        s.film.aov_names = vec!["dd.T".into(), "nn.X".into()];
        s.film.aov = (0..12).map(|i| i as f64 * 0.25 - 1.0).collect();
        let bytes = s.to_bytes();
        assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()), 2);
        let back = RenderState::from_bytes(&bytes, Path::new("s")).unwrap();
        assert_eq!(back, s);
        // Files without AOVs keep version 1.
        assert_eq!(sample().to_bytes()[8], 1);
        for n in [bytes.len() - 9, bytes.len() - 100] {
            assert!(RenderState::from_bytes(&bytes[..n], Path::new("s")).is_err());
        }
    }

    fn adaptive_sample(targets: bool) -> RenderState {
        let mut s = sample();
        let mut a = Adaptive::new(16, 6).unwrap();
        a.sq = (0..6).map(|i| i as f64 * 0.7).collect();
        if targets {
            a.targets = vec![4, 4, 20, 30, 16, 22];
            a.done = vec![8, 8, 8, 8, 4, 4];
        } else {
            a.done = vec![4, 4, 4, 4, 2, 2];
        }
        s.film.adaptive = Some(a);
        s
    }

    #[test]
    fn an_adaptive_render_round_trips_in_version_3() {
        for targets in [false, true] {
            for aov in [false, true] {
                let mut s = adaptive_sample(targets);
                if aov {
                    s.film.aov_names = vec!["dd.T".into()];
                    s.film.aov = (0..6).map(|i| i as f64).collect();
                }
                let bytes = s.to_bytes();
                assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()), 3);
                let back = RenderState::from_bytes(&bytes, Path::new("s")).unwrap();
                assert_eq!(back, s);
                for n in 0..bytes.len() {
                    assert!(RenderState::from_bytes(&bytes[..n], Path::new("s")).is_err());
                }
            }
        }
    }

    #[test]
    fn an_inconsistent_adaptive_state_is_an_error() {
        // Files with a valid checksum whose adaptive part does not make sense.
        type Spoil = fn(&mut Adaptive);
        let cases: [(&str, Spoil); 4] = [
            ("pilot", |a| a.pilot = 5),
            ("target below the pilot", |a| a.targets[0] = 3),
            ("target above 16 x spp", |a| a.targets[1] = 16 * 16 + 1),
            ("progress beyond the pilot without targets", |a| {
                a.targets.clear();
                a.done[0] = 5;
            }),
        ];
        for (what, spoil) in cases {
            let mut s = adaptive_sample(true);
            spoil(s.film.adaptive.as_mut().unwrap());
            let e = RenderState::from_bytes(&s.to_bytes(), Path::new("s.state"));
            assert!(e.is_err(), "{what} accepted");
        }
    }

    #[test]
    fn every_truncation_and_byte_flip_is_an_error() {
        let bytes = sample().to_bytes();
        for n in 0..bytes.len() {
            let e = RenderState::from_bytes(&bytes[..n], Path::new("s.state"));
            assert!(e.is_err(), "truncated at {n} accepted");
            assert!(e.unwrap_err().to_string().starts_with("s.state: "));
        }
        for i in 0..bytes.len() {
            let mut b = bytes.clone();
            b[i] ^= 0x40;
            assert!(
                RenderState::from_bytes(&b, Path::new("s")).is_err(),
                "flip at {i} accepted"
            );
        }
    }

    #[test]
    fn write_replaces_atomically_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("ophis-state-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("r.state");
        std::fs::write(&p, b"old").unwrap();
        sample().write(&p).unwrap();
        assert_eq!(RenderState::read(&p).unwrap(), sample());
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(names.len(), 1);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
