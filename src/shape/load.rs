//! Mesh files: the shared loader error, the loaded arrays, and `TriangleMesh` constructors from
//! OBJ and PLY files (Mitsuba's `obj` and `ply` plugins).
use super::mesh::{MeshError, TriangleMesh};
use crate::math::{Transform, Vec2, Vec3};
use std::path::{Path, PathBuf};

/// Mesh arrays as read from a file, in object space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
    pub indices: Vec<[u32; 3]>,
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
    std::fs::read(path).map_err(|source| LoadError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Options of Mitsuba's `obj` and `ply` shapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshOptions {
    /// `flip_normals` (default false): negate geometric and shading normals.
    pub flip_normals: bool,
    /// `face_normals` (default false): ignore vertex normals.
    pub face_normals: bool,
    /// `flip_tex_coords` (default true): v ← 1 − v, as Mitsuba 3 does for OBJ and PLY files.
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
        TriangleMesh::new(
            data.positions,
            data.normals,
            data.uvs,
            data.indices,
            to_world,
            opts.flip_normals,
            opts.face_normals,
        )
        .map_err(|source| LoadError::Mesh {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Mitsuba's `obj` shape.
    pub fn from_obj(
        path: &Path,
        to_world: &Transform,
        opts: &MeshOptions,
    ) -> Result<TriangleMesh, LoadError> {
        let data = super::obj::read_obj(path)?;
        TriangleMesh::from_data(data, path, to_world, opts)
    }

    /// Mitsuba's `ply` shape.
    pub fn from_ply(
        path: &Path,
        to_world: &Transform,
        opts: &MeshOptions,
    ) -> Result<TriangleMesh, LoadError> {
        let data = super::ply::read_ply(path)?;
        TriangleMesh::from_data(data, path, to_world, opts)
    }
}
