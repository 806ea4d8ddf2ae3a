//! Sanity limits: an estimate of the memory a scene will need, made from the scene
//! description and the mesh files' sizes and headers before anything large is allocated, and
//! a refusal when it exceeds the memory this process may use.
//!
//! The machine's memory is the smaller of `MemTotal` in `/proc/meminfo` and the cgroup limit
//! (`/sys/fs/cgroup/memory.max`, as set by Slurm, Kubernetes or Docker). The environment
//! variable `OPHIS_MEMORY_LIMIT` (bytes, or with a `K`, `M`, `G` or `T` suffix, powers of
//! 1024) overrides both. Where none of these exist (not Linux), the check is skipped.
//!
//! The estimate is deliberately coarse (it is there to catch a resolution or a mesh that is off
//! by orders of magnitude, not to budget to the byte):
//!
//! | what                | bytes                                                        |
//! |---------------------|--------------------------------------------------------------|
//! | film                | 48 per pixel (f64 XYZ + count sums, f32 RGB image, PNG bytes; an adaptive render's state, 16 more, is within the coarseness) |
//! | PLY mesh            | 32 per vertex + 112 per triangle (indices, BVH, build), counts from the header; a polygon counts as 2 triangles |
//! | OBJ mesh            | file size × 6 (an OBJ line of ~30 bytes becomes ~180 bytes)   |
//! | serialized mesh     | file size × 12 (zlib packs the ~44 bytes of a vertex and a triangle into ~15; the mesh needs ~150) |
//! | `instance`          | the meshes of the group it copies                             |

use crate::film::MAX_RESOLUTION;
use crate::scene::mitsuba::{Location, Node, SceneError, Tag};
use std::path::Path;

/// Bytes per film pixel.
const FILM_PIXEL: u64 = 48;
const VERTEX: u64 = 32;
const TRIANGLE: u64 = 112;
const OBJ_FACTOR: u64 = 6;
const SERIALIZED_FACTOR: u64 = 12;

/// Estimated memory of a scene, in bytes, by part.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MemoryEstimate {
    pub width: u64,
    pub height: u64,
    pub film: u64,
    pub meshes: u64,
    /// The largest single item: bytes, where it is declared, and what it is.
    pub largest: Option<(u64, Location, String)>,
}

impl MemoryEstimate {
    /// The total in bytes.
    pub fn total(&self) -> u64 {
        self.film.saturating_add(self.meshes)
    }
}

/// Formats bytes in binary units.
pub(crate) fn human(bytes: u64) -> String {
    let units = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut v = bytes as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < units.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{bytes} bytes")
    } else {
        format!("{v:.1} {}", units[u])
    }
}

/// Parses `123`, `4K`, `16G`, … (powers of 1024).
pub(crate) fn parse_size(s: &str) -> Option<u64> {
    let s = s.trim();
    let (num, mult) = match s.chars().last()?.to_ascii_uppercase() {
        'K' => (&s[..s.len() - 1], 1u64 << 10),
        'M' => (&s[..s.len() - 1], 1 << 20),
        'G' => (&s[..s.len() - 1], 1 << 30),
        'T' => (&s[..s.len() - 1], 1 << 40),
        _ => (s, 1),
    };
    num.trim().parse::<u64>().ok()?.checked_mul(mult)
}

/// The memory this process may use, if it can be found out.
pub fn machine_memory() -> Option<u64> {
    if let Ok(v) = std::env::var("OPHIS_MEMORY_LIMIT") {
        return parse_size(&v);
    }
    let total = std::fs::read_to_string("/proc/meminfo").ok().and_then(|m| {
        m.lines()
            .find(|l| l.starts_with("MemTotal:"))
            .and_then(|l| parse_size(&l["MemTotal:".len()..].replace("kB", "K")))
    });
    let cgroup = std::fs::read_to_string("/sys/fs/cgroup/memory.max")
        .ok()
        .and_then(|s| s.trim().parse::<u64>().ok());
    match (total, cgroup) {
        (Some(t), Some(c)) => Some(t.min(c)),
        (t, c) => t.or(c),
    }
}

/// Vertex and polygon counts from a PLY header (first 64 KiB), if readable.
fn ply_counts(path: &Path) -> Option<(u64, u64)> {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take(1 << 16)
        .read_to_end(&mut head)
        .ok()?;
    let text = String::from_utf8_lossy(&head);
    let (mut v, mut f) = (0, 0);
    for line in text.lines().take_while(|l| l.trim() != "end_header") {
        let w: Vec<&str> = line.split_whitespace().collect();
        if let ["element", name, n] = w[..] {
            let n: u64 = n.parse().ok()?;
            match name {
                "vertex" => v = n,
                "face" => f = n,
                _ => {}
            }
        }
    }
    Some((v, f))
}

fn mesh_bytes(node: &Node) -> (u64, String) {
    let Ok(Some(path)) = node.props.get_path_opt("filename") else {
        return (0, String::new());
    };
    let Ok(meta) = std::fs::metadata(&path) else {
        return (0, String::new());
    };
    if !meta.is_file() {
        return (0, String::new());
    }
    let bytes = match node.plugin.as_str() {
        "ply" => ply_counts(&path)
            .map(|(v, f)| {
                v.saturating_mul(VERTEX)
                    .saturating_add(f.saturating_mul(2 * TRIANGLE))
            })
            .unwrap_or(0),
        "obj" => meta.len().saturating_mul(OBJ_FACTOR),
        "serialized" => meta.len().saturating_mul(SERIALIZED_FACTOR),
        _ => 0,
    };
    (bytes, format!("the mesh {}", path.display()))
}

/// Estimates the memory a parsed scene will need.
pub fn estimate(root: &Node) -> MemoryEstimate {
    let (mut w, mut h) = (768u64, 576u64);
    let mut meshes = 0u64;
    let mut film_loc = root.loc.clone();
    let mut largest: Option<(u64, Location, String)> = None;
    let mut consider = |bytes: u64, loc: &Location, what: String| {
        if largest.as_ref().is_none_or(|l| bytes > l.0) {
            largest = Some((bytes, loc.clone(), what));
        }
    };
    for child in &root.children {
        let node = &child.node;
        match node.tag {
            Tag::Sensor => {
                for c in &node.children {
                    if c.node.tag == Tag::Film {
                        film_loc = c.node.loc.clone();
                        // Out-of-range values are left to the builder's own message.
                        let get = |n: &str, d: u64| match c.node.props.get_int_opt(n) {
                            Ok(Some(v)) if v > 0 && v <= MAX_RESOLUTION => v as u64,
                            _ => d,
                        };
                        w = get("width", w);
                        h = get("height", h);
                    }
                }
            }
            // Instances copy their group's meshes; the group itself is built only through them.
            Tag::Shape if node.plugin == "instance" => {
                for g in node.children_with_tag(Tag::Shape) {
                    for s in g.children_with_tag(Tag::Shape) {
                        let (b, what) = mesh_bytes(s);
                        meshes = meshes.saturating_add(b);
                        consider(b, &node.loc, format!("{what} (instanced)"));
                    }
                }
            }
            Tag::Shape if node.plugin == "shapegroup" => {}
            Tag::Shape => {
                let (b, what) = mesh_bytes(node);
                meshes = meshes.saturating_add(b);
                let loc = node.props.location("filename").unwrap_or(&node.loc);
                consider(b, loc, what);
            }
            _ => {}
        }
    }
    let film = w.saturating_mul(h).saturating_mul(FILM_PIXEL);
    consider(film, &film_loc, format!("the {w} × {h} film"));
    MemoryEstimate {
        width: w,
        height: h,
        film,
        meshes,
        largest,
    }
}

/// Refuses a scene whose estimate exceeds `available` bytes (when known), with a message
/// that says what takes the memory and how to lower it.
pub fn check(root: &Node, available: Option<u64>) -> Result<MemoryEstimate, SceneError> {
    let e = estimate(root);
    if let Some(avail) = available {
        if e.total() > avail {
            let (_, loc, what) = e
                .largest
                .clone()
                .unwrap_or((0, root.loc.clone(), String::new()));
            return Err(SceneError::at(
                &loc,
                format!(
                    "the scene needs about {} of memory but this machine allows {} \
                     (film {} × {}: {}; meshes: {}; the largest part is {what}); lower the \
                     film resolution or use smaller meshes (set OPHIS_MEMORY_LIMIT to \
                     override the limit)",
                    human(e.total()),
                    human(avail),
                    e.width,
                    e.height,
                    human(e.film),
                    human(e.meshes)
                ),
            ));
        }
    }
    Ok(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_print() {
        assert_eq!(parse_size("16G"), Some(16 << 30));
        assert_eq!(parse_size(" 24683656 K"), Some(24683656 << 10));
        assert_eq!(parse_size("12"), Some(12));
        assert_eq!(parse_size("x"), None);
        assert_eq!(parse_size("99999999999T"), None);
        assert_eq!(human(1536), "1.5 KiB");
        assert_eq!(human(3), "3 bytes");
    }

    #[test]
    fn this_machine_reports_some_memory_on_linux() {
        if cfg!(target_os = "linux") && std::env::var("OPHIS_MEMORY_LIMIT").is_err() {
            let m = machine_memory().expect("/proc/meminfo");
            assert!(m > 1 << 26, "{m}");
        }
    }
}
