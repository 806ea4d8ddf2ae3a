//! Mesh files: the shared loader error, the loaded arrays, and `TriangleMesh` constructors from
//! OBJ, PLY and serialized files (Mitsuba's `obj`, `ply` and `serialized` plugins).
//!
//! As in Mitsuba 3, a mesh file without vertex normals is shaded smoothly unless
//! `face_normals` is set: each vertex gets the mean of its triangles' unit normals weighted by
//! the triangle's angle at that vertex (Thürmer & Wüthrich, "Computing vertex normals from
//! polygonal facets", JGT 3(1), 1998), computed in object space.
use super::mesh::{MeshError, TriangleMesh};
use crate::math::{Transform, Vec2, Vec3};
use crate::plugin::{Args, DefaultValue, Param, SceneError, Ty};
use std::path::{Path, PathBuf};

/// Mesh arrays as read from a file, in object space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
    pub indices: Vec<[u32; 3]>,
}

impl MeshData {
    /// The mesh placed by `to_world` (its normals, if any, shade it unless `face_normals`).
    pub(crate) fn into_mesh(
        self,
        to_world: &Transform,
        flip_normals: bool,
        face_normals: bool,
    ) -> Result<TriangleMesh, MeshError> {
        let MeshData {
            positions,
            normals,
            uvs,
            indices,
        } = self;
        TriangleMesh::new(
            positions,
            normals,
            uvs,
            indices,
            to_world,
            flip_normals,
            face_normals,
        )
    }
}

/// Why a mesh file could not be loaded. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be opened or read.
    #[error("{}: cannot read file: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The path names a directory.
    #[error("{}: is a directory, expected a mesh file", path.display())]
    IsDirectory { path: PathBuf },
    /// A syntax or range error at a line of a text file (or of a PLY header).
    #[error("{}:{line}: {message}", path.display())]
    Syntax {
        path: PathBuf,
        line: usize,
        message: String,
    },
    /// An error in binary data, at a byte offset.
    #[error("{}: byte {offset}: {message}", path.display())]
    Binary {
        path: PathBuf,
        offset: usize,
        message: String,
    },
    /// The file holds no faces.
    #[error("{}: the file contains no faces", path.display())]
    Empty { path: PathBuf },
    /// The arrays read were rejected by the mesh constructor.
    #[error("{}: {source}", path.display())]
    Mesh {
        path: PathBuf,
        #[source]
        source: MeshError,
    },
}

/// Reads a whole file, mapping failures to [`LoadError`].
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, LoadError> {
    if path.is_dir() {
        return Err(LoadError::IsDirectory {
            path: path.to_path_buf(),
        });
    }
    read_in_parts(path, READ_PART).map_err(|source| LoadError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Parts in which [`read_file`] reads a file of more than one part on all threads.
const READ_PART: usize = 4 << 20;

/// The file at `path`, read in parts of `part` bytes on all threads where it has more than
/// one (on Unix): each thread copies its parts out of the page cache into a buffer whose pages
/// it is the first to touch, so the kernel's copying and page clearing are shared out (one
/// thread spent ~40 ms on the 24 MB PLY file of the 1M-triangle mesh). The file is read up to
/// the length it had when opened.
fn read_in_parts(path: &Path, part: usize) -> std::io::Result<Vec<u8>> {
    #[cfg(unix)]
    {
        use rayon::prelude::*;
        use std::os::unix::fs::FileExt;
        let file = std::fs::File::open(path)?;
        let len = usize::try_from(file.metadata()?.len()).unwrap_or(usize::MAX);
        if len > part && part > 0 {
            // Zeroed by the allocator's fresh pages, not by a pass over them.
            let mut buf = vec![0u8; len];
            buf.par_chunks_mut(part)
                .enumerate()
                .try_for_each(|(i, chunk)| file.read_exact_at(chunk, (i * part) as u64))?;
            return Ok(buf);
        }
    }
    std::fs::read(path)
}

/// Options of Mitsuba's `obj` and `ply` shapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshOptions {
    /// `flip_normals` (default false): negate geometric and shading normals.
    pub flip_normals: bool,
    /// `face_normals` (default false): ignore vertex normals.
    pub face_normals: bool,
    /// `flip_tex_coords`: v ← 1 − v. Mitsuba 3's default is true for OBJ files and false for
    /// PLY files (and serialized files have no such option); [`Default`] gives OBJ's.
    pub flip_tex_coords: bool,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            flip_normals: false,
            face_normals: false,
            flip_tex_coords: true,
        }
    }
}

impl TriangleMesh {
    /// Builds a mesh from loaded arrays (`path` only names the source in errors).
    pub fn from_data(
        mut data: MeshData,
        path: &Path,
        to_world: &Transform,
        opts: &MeshOptions,
    ) -> Result<TriangleMesh, LoadError> {
        if data.indices.is_empty() {
            return Err(LoadError::Empty {
                path: path.to_path_buf(),
            });
        }
        if opts.flip_tex_coords {
            if let Some(uvs) = &mut data.uvs {
                for uv in uvs {
                    uv.y = 1.0 - uv.y;
                }
            }
        }
        if data.normals.is_none() && !opts.face_normals {
            data.normals = Some(smooth_normals(&data.positions, &data.indices));
        }
        data.into_mesh(to_world, opts.flip_normals, opts.face_normals)
            .map_err(|source| LoadError::Mesh {
                path: path.to_path_buf(),
                source,
            })
    }
}

/// Angle-weighted vertex normals (see the module header); a vertex on no valid triangle gets
/// +x, as Mitsuba gives it, and triangles with an index out of range are skipped (the mesh
/// constructor reports them).
///
/// On all threads, bit for bit the same whatever their number: the vertices are split into
/// one range per thread, and each thread walks all the triangles in order but adds only to
/// its own vertices, so every vertex's sum is the same additions in the same order as on one
/// thread. (A triangle none of whose corners is in a thread's range costs that thread only the
/// range check.)
pub(crate) fn smooth_normals(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<Vec3> {
    use rayon::prelude::*;
    if positions.is_empty() {
        return Vec::new();
    }
    // Written by all threads (their pages first touched on all of them); every value is
    // overwritten below.
    let mut out = Vec::with_capacity(positions.len());
    out.par_extend(rayon::iter::repeat_n(Vec3::X, positions.len()));
    // Small meshes on the calling thread: one range.
    let ranges = if indices.len() < 1 << 14 {
        1
    } else {
        rayon::current_num_threads().max(1)
    };
    let chunk = positions.len().div_ceil(ranges);
    // The sums are allocated here, not by the worker threads: memory freed in a worker's
    // allocator arena is not reused by the later allocations of the scene's build, which
    // raised the peak of a 4M-triangle scene by 40 MB.
    let mut acc = vec![glam::DVec3::ZERO; positions.len()];
    out.par_chunks_mut(chunk)
        .zip(acc.par_chunks_mut(chunk))
        .enumerate()
        .for_each(|(c, (dst, acc))| smooth_normals_of(positions, indices, c * chunk, dst, acc));
    out
}

/// [`smooth_normals`] of the vertices `first .. first + dst.len()`, into `dst`, summing in
/// `acc` (zeros, as long as `dst`).
fn smooth_normals_of(
    positions: &[Vec3],
    indices: &[[u32; 3]],
    first: usize,
    dst: &mut [Vec3],
    acc: &mut [glam::DVec3],
) {
    let mine = |i: u32| (i as usize).wrapping_sub(first) < dst.len();
    for tri in indices {
        if !(mine(tri[0]) || mine(tri[1]) || mine(tri[2])) {
            continue;
        }
        // An array, not a collected Vec: one allocation per triangle was a third of this
        // function's time on a 1M-triangle mesh.
        let [Some(p0), Some(p1), Some(p2)] = tri.map(|i| positions.get(i as usize)) else {
            continue;
        };
        let p = [p0, p1, p2].map(|p| p.as_dvec3());
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let len = n.length();
        if !(len > 0.0 && len.is_finite()) {
            continue;
        }
        let n = n / len;
        // The angle at corner k between its edges a and b is atan2(|a×b|, a·b), and |a×b| is
        // `len` at every corner: no edge needs normalising (atan2 is scale-free). atan2 keeps
        // precision at small and near-straight angles; the third angle is π less the other
        // two, whose absolute error (~1e-15) is all a weight needs.
        let angle = |k: usize| len.atan2((p[(k + 1) % 3] - p[k]).dot(p[(k + 2) % 3] - p[k]));
        let own = tri.map(mine);
        let a0 = if own[0] || own[2] { angle(0) } else { 0.0 };
        let a1 = if own[1] || own[2] { angle(1) } else { 0.0 };
        let angles = [a0, a1, std::f64::consts::PI - a0 - a1];
        for k in 0..3 {
            if own[k] {
                acc[tri[k] as usize - first] += n * angles[k];
            }
        }
    }
    for (d, &n) in dst.iter_mut().zip(acc.iter()) {
        let l = n.length();
        *d = if l > 0.0 && l.is_finite() {
            (n / l).as_vec3()
        } else {
            Vec3::X
        };
    }
}

/// What the mesh-file plugins (`obj`, `ply`, `serialized`) take besides their placement.
pub(crate) const MESH_FILE: &[Param] = &[
    Param::new("filename", Ty::String, DefaultValue::Required)
        .doc("the mesh file, relative to the scene file"),
    Param::bool("face_normals", false)
        .doc("flat shading: ignore the file's normals and do not smooth"),
];

/// `flip_tex_coords` of the OBJ and PLY plugins, with the default Mitsuba 3 gives each.
pub(crate) const fn flip_tex_coords(default: bool) -> Param {
    Param::bool("flip_tex_coords", default).doc("v ↦ 1 − v (Mitsuba 3 flips OBJ's, not PLY's)")
}

/// The mesh files a plugin reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MeshFile {
    Obj,
    Ply,
    Serialized,
}

/// Loads a mesh-file shape: a mesh of only zero-area triangles is skipped with a warning (as
/// Mitsuba renders it), dropped degenerate triangles are reported.
pub(crate) fn mesh_file(
    a: &mut Args,
    parent: &Transform,
    kind: MeshFile,
) -> Result<super::Parts, SceneError> {
    let (to_world, flip) = super::placement(a, parent)?;
    let path = a
        .path("filename")?
        .ok_or_else(|| a.error("filename", "is required"))?;
    let opts = MeshOptions {
        flip_normals: flip,
        face_normals: a.bool("face_normals")?,
        // Mitsuba 3 flips OBJ's v, not PLY's; serialized files are used as stored.
        flip_tex_coords: kind != MeshFile::Serialized && a.bool("flip_tex_coords")?,
    };
    let data = match kind {
        MeshFile::Obj => super::obj::read_obj(&path),
        MeshFile::Ply => super::ply::read_ply(&path),
        // Mesh `shape_index` of the file.
        MeshFile::Serialized => super::serialized::read_serialized(&path, a.u32("shape_index")?),
    };
    let mesh = data.and_then(|d| TriangleMesh::from_data(d, &path, &to_world, &opts));
    let mesh = match mesh {
        Err(LoadError::Mesh {
            source: MeshError::Empty { dropped },
            ..
        }) => {
            let d = a.describe();
            a.warn(format!(
                "{d}: all {dropped} triangles of '{}' have zero area; the shape is skipped",
                path.display()
            ));
            return Ok(Vec::new());
        }
        other => other.map_err(|e| a.error("filename", e))?,
    };
    if mesh.degenerate_dropped() > 0 {
        let d = a.describe();
        a.warn(format!(
            "{d}: dropped {} degenerate triangles",
            mesh.degenerate_dropped()
        ));
    }
    Ok(vec![(None, super::Shape::Mesh(mesh))])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_read_in_parts_are_read_whole() {
        let dir = std::env::temp_dir().join(format!("ophis-parts-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("f.bin");
        let data: Vec<u8> = (0..100_003u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect();
        std::fs::write(&path, &data).unwrap();
        // Parts that divide the file, that do not, one part, and larger than the file.
        for part in [1000, 4096, 33_333, 100_003, 1 << 20] {
            assert_eq!(read_in_parts(&path, part).unwrap(), data, "parts of {part}");
        }
        assert!(read_in_parts(&dir.join("missing"), 1000).is_err());
        std::fs::write(&path, b"").unwrap();
        assert!(read_in_parts(&path, 1000).unwrap().is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn smooth_normals_are_the_same_on_any_number_of_threads() {
        // A mesh big enough to be split, whose triangles join vertices across the split (random
        // corners), with a few invalid triangles: every vertex's normal the same, bit for bit,
        // on 1, 2 and 3 threads.
        let mut rng = crate::math::Pcg32::new(3, 8);
        let nv = 5000u32;
        let p: Vec<Vec3> = (0..nv)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
            .collect();
        let mut tris: Vec<[u32; 3]> = (0..40_000)
            .map(|_| [0; 3].map(|_| (rng.next_f32() * nv as f32) as u32 % nv))
            .collect();
        tris[7] = [1, 2, nv + 5];
        tris[9] = [3, 3, 4];
        let on = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| smooth_normals(&p, &tris))
        };
        let bits = |n: Vec<Vec3>| {
            n.iter()
                .map(|v| v.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        let one = bits(on(1));
        assert_eq!(one, bits(on(2)));
        assert_eq!(one, bits(on(3)));
    }

    #[test]
    fn smooth_normals_weight_faces_by_their_angle() {
        // A vertex shared by a right-angled triangle in z = 0 (angle 90° at the shared corner)
        // and one in x = 0 (angle 45°): the normal leans 2:1 towards the first face's normal.
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let tris = [[0, 1, 2], [0, 3, 4]];
        let n = smooth_normals(&p, &tris);
        let want = (Vec3::Z * std::f32::consts::FRAC_PI_2 + Vec3::X * std::f32::consts::FRAC_PI_4)
            .normalize();
        assert!((n[0] - want).length() < 1e-6, "{}", n[0]);
        assert!((n[1] - Vec3::Z).length() < 1e-6 && (n[4] - Vec3::X).length() < 1e-6);
        // A zero-area triangle and an unused vertex contribute nothing.
        let n = smooth_normals(&[Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::Y], &[[0, 1, 2]]);
        assert!(n.iter().all(|&v| v == Vec3::X));
    }

    #[test]
    fn smooth_normals_agree_with_the_textbook_angle_weights() {
        // Against each corner's angle from its normalised edges, atan2(|a×b|, a·b) per corner,
        // on a random mesh with slivers (small and near-straight angles): the same normals to
        // f32 precision. Either formula rounds differently; a wrong angle (say, a corner's
        // neighbour's) moves normals by ~0.1.
        let mut rng = crate::math::Pcg32::new(11, 2);
        let nv = 3000u32;
        let mut p: Vec<Vec3> = (0..nv)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
            .collect();
        let mut tris: Vec<[u32; 3]> = (0..20_000)
            .map(|_| [0; 3].map(|_| (rng.next_f32() * nv as f32) as u32 % nv))
            .collect();
        // Slivers: a corner 1e-4 from the middle of its opposite edge, or from a corner.
        for i in 0..200 {
            let [a, b, c] = tris[i * 50].map(|k| p[k as usize]);
            let t = if i % 2 == 0 { 0.5 } else { 1e-3 };
            p[tris[i * 50][2] as usize] = a + (b - a) * t + (c - a) * 1e-4;
        }
        tris.retain(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
        let mut acc = vec![glam::DVec3::ZERO; p.len()];
        for t in &tris {
            let q = t.map(|k| p[k as usize].as_dvec3());
            let n = (q[1] - q[0]).cross(q[2] - q[0]);
            if n.length() == 0.0 {
                continue;
            }
            for k in 0..3 {
                let a = (q[(k + 1) % 3] - q[k]).normalize();
                let b = (q[(k + 2) % 3] - q[k]).normalize();
                acc[t[k] as usize] += n.normalize() * a.cross(b).length().atan2(a.dot(b));
            }
        }
        let got = smooth_normals(&p, &tris);
        let mut worst = 0.0f64;
        for (g, a) in got.iter().zip(&acc) {
            if a.length() > 1e-9 {
                worst = worst.max((g.as_dvec3() - a.normalize()).length());
            }
        }
        assert!(worst < 1e-6, "largest difference {worst}");
    }

    #[test]
    fn mesh_files_without_normals_are_shaded_smoothly_unless_face_normals() {
        let data = MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.5)],
            normals: None,
            uvs: None,
            indices: vec![[0, 1, 2], [1, 3, 2]],
        };
        let p = Path::new("m.ply");
        let smooth = TriangleMesh::from_data(
            data.clone(),
            p,
            &Transform::IDENTITY,
            &MeshOptions::default(),
        )
        .unwrap();
        assert!(smooth.has_vertex_normals());
        let flat = MeshOptions {
            face_normals: true,
            ..MeshOptions::default()
        };
        let m = TriangleMesh::from_data(data, p, &Transform::IDENTITY, &flat).unwrap();
        assert!(!m.has_vertex_normals());
    }
}
