//! ophis — a spectral path tracer for structural colour: thin-film iridescence and layered
//! materials, reading Mitsuba XML scenes.

// `!(x > 0.0)` is used on purpose throughout: unlike `x <= 0.0` it also rejects NaN, which is
// what input validation and sample guards need.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

/// Bounding volume hierarchy over all scene primitives, plus a brute-force oracle.
pub mod accel;
/// Scattering functions (BSDFs) and materials.
pub mod bsdf;
/// Cameras: perspective, thin lens, orthographic.
pub mod camera;
/// Render state files for checkpoints and resuming.
pub mod checkpoint;
/// Film: XYZ accumulation and reconstruction filters.
pub mod film;
/// Image reading and writing: OpenEXR, Radiance HDR, PNG.
pub mod image_io;
/// Path tracing.
pub mod integrator;
/// Light sources.
pub mod light;
/// Memory estimates and limits checked before a scene is built.
pub mod limits;
/// Geometry and sampling primitives.
pub mod math;
/// Merging independent renders weighted by their sample counts.
pub mod merge;
/// Wave optics: exact thin-film interference.
pub mod optics;
/// Plugins: the scene description they read, their parameter declarations, the registry.
pub mod plugin;
/// The render loop over tiles.
pub mod render;
/// Sample generators.
pub mod sampler;
/// Scene loading (Mitsuba XML) and the built scene.
pub mod scene;
/// Shapes: spheres, disks, triangle meshes and their loaders.
pub mod shape;
/// Lanes of `f32` (one, or eight with AVX2) for arithmetic shared by scalar and vector code.
pub mod simd;
/// Spectral types, colour-matching functions, RGB uplift, named IOR data.
pub mod spectrum;
#[cfg(test)]
mod test_util;
/// Textures.
pub mod texture;
/// Tools above the renderer: the BSDF inspector behind `ophis bsdf`, quick renders, figures.
pub mod tools;
