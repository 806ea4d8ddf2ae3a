//! What the lanes need to know of a scene, in flat tables indexed by shape, material, light and
//! spectrum: which hits the vector vertex handles, and the parameters it gathers per lane.
//!
//! A hit is handled in lanes when its shape's material is one the lanes implement (today
//! `diffuse` with a constant spectrum) and its shape either does not emit or is a triangle mesh
//! emitting a constant spectrum. Every other hit — and every escaped ray — is shaded by the
//! scalar code of [`crate::integrator::path`], lane by lane.

use crate::bsdf::material::{ConductorIor, Roughness};
use crate::bsdf::microfacet::{MicrofacetDistribution, MicrofacetType};
use crate::bsdf::{Interface, Material};
use crate::light::Light;
use crate::scene::Scene;
use crate::shape::Shape;
use crate::spectrum::Spectrum;
use crate::texture::{FloatTexture, SpectrumTexture};

/// How [`SpectrumTable`] entries are evaluated (see [`Spectrum::sample`]).
pub(super) const SPEC_CONSTANT: u32 = 0;
pub(super) const SPEC_ALBEDO: u32 = 1;
pub(super) const SPEC_UNBOUNDED: u32 = 2;
pub(super) const SPEC_ILLUMINANT: u32 = 3;
pub(super) const SPEC_CURVE: u32 = 4;

/// Material kinds of the lanes.
pub(super) const MAT_DIFFUSE: u32 = 0;
/// `dielectric` (smooth).
pub(super) const MAT_DIELECTRIC: u32 = 1;
/// `conductor` (smooth, including the perfect mirror).
pub(super) const MAT_CONDUCTOR: u32 = 2;
/// `roughconductor` with GGX.
pub(super) const MAT_ROUGH_CONDUCTOR: u32 = 3;

/// Groups of paths that share their shading code: hits on a lane material, by its kind and
/// whether the shape is a mesh (`2 · kind + mesh`), and the paths the scalar code shades
/// (other hits, and escaped rays). The pool is ordered by group before shading
/// ([`super::pool::Pool::group`]), so that a chunk of lanes mostly runs one material's code
/// on one kind of surface.
pub(super) const CLASSES: usize = 2 * (MAT_ROUGH_CONDUCTOR as usize + 1) + 1;
/// [`CLASSES`]: paths the lanes do not shade (the last group).
pub(super) const CLASS_SCALAR: u8 = CLASSES as u8 - 1;

/// The group of a lane hit on a material of kind `kind` (`MAT_*`, the last of which is
/// `MAT_ROUGH_CONDUCTOR`).
fn shade_class(kind: u32, mesh: bool) -> u8 {
    assert!(
        kind <= MAT_ROUGH_CONDUCTOR,
        "material kind {kind} has no group"
    );
    (2 * kind + mesh as u32) as u8
}

/// Spectra the lanes can evaluate: a constant, an RGB uplift (Jakob–Hanika sigmoid
/// polynomial) with its scale and, for emission, the D65 factor, or a tabulated curve.
#[derive(Debug, Default)]
pub(super) struct SpectrumTable {
    pub(super) mode: Vec<u32>,
    /// Tabulated curves (`SPEC_CURVE` entries hold their index in `c0`'s place: `curve`).
    pub(super) curves: Vec<std::sync::Arc<crate::spectrum::spectra::PiecewiseLinear>>,
    pub(super) curve: Vec<u32>,
    /// The constant's value, or the polynomial's c0.
    pub c0: Vec<f32>,
    pub c1: Vec<f32>,
    pub c2: Vec<f32>,
    pub(super) scale: Vec<f32>,
}

impl SpectrumTable {
    /// Adds `s`; `None` for spectra the lanes cannot evaluate (tabulated, blackbody).
    fn add(&mut self, s: &Spectrum) -> Option<u32> {
        let mut curve = 0;
        let (mode, c, scale) = match s {
            Spectrum::Constant(v) => (SPEC_CONSTANT, [*v, 0.0, 0.0], 1.0),
            Spectrum::RgbAlbedo(p) => (SPEC_ALBEDO, [p.c0, p.c1, p.c2], 1.0),
            Spectrum::RgbUnbounded { scale, poly } => {
                (SPEC_UNBOUNDED, [poly.c0, poly.c1, poly.c2], *scale)
            }
            Spectrum::RgbIlluminant { scale, poly } => {
                (SPEC_ILLUMINANT, [poly.c0, poly.c1, poly.c2], *scale)
            }
            Spectrum::PiecewiseLinear(p) => {
                curve = self.curves.len() as u32;
                self.curves.push(p.clone());
                (SPEC_CURVE, [0.0; 3], 1.0)
            }
            Spectrum::Blackbody { .. } => return None,
        };
        self.curve.push(curve);
        self.mode.push(mode);
        self.c0.push(c[0]);
        self.c1.push(c[1]);
        self.c2.push(c[2]);
        self.scale.push(scale);
        Some(self.mode.len() as u32 - 1)
    }
}

/// The scene's tables; see the module header.
#[derive(Debug)]
pub struct Program {
    /// A number no other program made by this process has: the threads keep their path pools
    /// from tile to tile of one render, and only of one ([`super::Buffers`]).
    pub(super) id: u64,
    /// Per shape: 1 when hits on it are shaded in lanes.
    pub(super) shape_lanes: Vec<u32>,
    /// Per shape: 1 for a triangle mesh (its interaction is computed in lanes).
    pub(super) shape_mesh: Vec<u32>,
    /// Per shape: the index of its material in the material tables (0 where unused).
    pub(super) shape_mat: Vec<u32>,
    /// Per shape: 1 + the light it is, or 0.
    pub(super) shape_emit: Vec<u32>,
    /// Per shape: the group its hits are shaded with ([`shade_class`]).
    pub(super) shape_class: Vec<u8>,
    /// Whether a mesh has [`super::surface::BIG_MESH`] triangles or more (its hits' corner data
    /// are then requested ahead of shading: [`super::surface::prefetch_meshes`]).
    pub(super) big_meshes: bool,
    /// The materials the lanes implement.
    pub(super) mats: MaterialTable,
    /// Per light: 1 for an area light on a triangle mesh with a spectrum the lanes evaluate
    /// (sampled and evaluated in lanes).
    pub(super) light_lanes: Vec<u32>,
    /// Per light: the probability of choosing it.
    pub(super) light_pmf: Vec<f32>,
    /// Per light: the probability of choosing it at a vertex that leaves smooth environments
    /// to its BSDF ([`crate::light::LightSampler::pmf_for`]).
    pub(super) light_pmf_no_env: Vec<f32>,
    /// Per light: its radiance spectrum entry (lane lights only).
    pub(super) light_spec: Vec<u32>,
    /// Per light: 1 / area of its shape (lane lights only).
    pub(super) light_inv_area: Vec<f32>,
    /// Per light: its shape (lane lights only).
    pub(super) light_shape: Vec<u32>,
    /// Per light: 1 when its mesh's normals are flipped (lane lights only).
    pub(super) light_flip: Vec<u32>,
    pub(super) spectra: SpectrumTable,
}

impl Program {
    /// The tables of `scene`.
    pub fn new(scene: &Scene) -> Program {
        let mut spectra = SpectrumTable::default();
        // Lights first: a shape is shaded in lanes only if its emission is.
        let n_lights = scene.lights.len();
        let mut light_lanes = vec![0; n_lights];
        let mut light_spec = vec![0; n_lights];
        let mut light_inv_area = vec![0.0; n_lights];
        let mut light_shape = vec![0; n_lights];
        let mut light_flip = vec![0; n_lights];
        let light_pmf: Vec<f32> = (0..n_lights).map(|i| scene.light_sampler.pmf(i)).collect();
        let mut light_pmf_no_env: Vec<f32> = (0..n_lights)
            .map(|i| scene.light_sampler.pmf_for(i, true))
            .collect();
        for (i, light) in scene.lights.iter().enumerate() {
            let Light::Area(a) = light else { continue };
            let Some(Shape::Mesh(m)) = scene.shapes.get(a.shape as usize) else {
                continue;
            };
            if let Some(e) = spectra.add(&a.radiance) {
                light_lanes[i] = 1;
                light_spec[i] = e;
                light_inv_area[i] = 1.0 / m.area();
                light_shape[i] = a.shape;
                light_flip[i] = m.flips_normals() as u32;
            }
        }
        let mut mats = MaterialTable::default();
        let mut mat_index = vec![None; scene.materials.len()];
        for (i, m) in scene.materials.iter().enumerate() {
            mat_index[i] = mats.add(m, &mut spectra);
        }
        let n_shapes = scene.shapes.len();
        let mut shape_lanes = vec![0; n_shapes];
        let mut shape_mesh = vec![0; n_shapes];
        let mut shape_mat = vec![0; n_shapes];
        let mut shape_emit = vec![0; n_shapes];
        for (s, shape) in scene.shapes.iter().enumerate() {
            shape_mesh[s] = matches!(shape, Shape::Mesh(_)) as u32;
            let light = scene.shape_light[s];
            shape_emit[s] = light.map_or(0, |l| l + 1);
            let emission_ok = light.is_none_or(|l| light_lanes[l as usize] == 1);
            if let Some(m) = mat_index[scene.shape_material[s] as usize] {
                shape_mat[s] = m;
                shape_lanes[s] = emission_ok as u32;
            }
        }
        let shape_class = (0..n_shapes)
            .map(|s| match shape_lanes[s] {
                0 => CLASS_SCALAR,
                _ => shade_class(mats.kind[shape_mat[s] as usize], shape_mesh[s] == 1),
            })
            .collect();
        // Lanes that do not use a table still gather from it (at index 0).
        if mats.kind.is_empty() {
            mats.push(MAT_DIFFUSE, [0; 4], [0.0; 4]);
        }
        if spectra.mode.is_empty() {
            spectra.add(&Spectrum::Constant(0.0));
        }
        let (mut light_lanes, mut light_pmf) = (light_lanes, light_pmf);
        if n_lights == 0 {
            light_lanes.push(0);
            light_pmf.push(0.0);
            light_pmf_no_env.push(0.0);
            light_spec.push(0);
            light_inv_area.push(0.0);
            light_shape.push(0);
            light_flip.push(0);
        }
        let big_meshes = scene
            .shapes
            .iter()
            .any(|s| matches!(s, Shape::Mesh(m) if m.triangle_count() >= super::surface::BIG_MESH));
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        Program {
            id: NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            shape_lanes,
            shape_mesh,
            big_meshes,
            shape_mat,
            shape_emit,
            shape_class,
            mats,
            light_lanes,
            light_pmf,
            light_pmf_no_env,
            light_spec,
            light_inv_area,
            light_shape,
            light_flip,
            spectra,
        }
    }
}

/// Per lane material: its kind (`MAT_*`), four spectrum entries and four numbers:
///
/// | kind | spectra | numbers |
/// |---|---|---|
/// | diffuse | reflectance | — |
/// | dielectric | specular reflectance, specular transmittance | η |
/// | conductor | specular reflectance, η, k (mirror: none) | exterior index, mirror flag (1) |
/// | rough conductor | as conductor | as conductor, then α_u, α_v |
#[derive(Debug, Default)]
pub(super) struct MaterialTable {
    pub(super) kind: Vec<u32>,
    pub(super) spec: [Vec<u32>; 4],
    pub(super) num: [Vec<f32>; 4],
}

impl MaterialTable {
    fn push(&mut self, kind: u32, spec: [u32; 4], num: [f32; 4]) -> u32 {
        self.kind.push(kind);
        for k in 0..4 {
            self.spec[k].push(spec[k]);
            self.num[k].push(num[k]);
        }
        self.kind.len() as u32 - 1
    }

    /// Adds `m` if the lanes implement it.
    fn add(&mut self, m: &Material, spectra: &mut SpectrumTable) -> Option<u32> {
        let constant = |t: &SpectrumTexture| match t {
            SpectrumTexture::Constant(s) => Some(s.clone()),
            _ => None,
        };
        match m {
            Material::Diffuse { reflectance } => {
                let r = spectra.add(&constant(reflectance)?)?;
                Some(self.push(MAT_DIFFUSE, [r, 0, 0, 0], [0.0; 4]))
            }
            Material::Surface(s) => {
                let r_s = spectra.add(&constant(&s.specular_reflectance)?)?;
                let t_s = spectra.add(&constant(&s.specular_transmittance)?)?;
                let metal = |ior: &Option<ConductorIor>, spectra: &mut SpectrumTable| match ior {
                    None => Some(([0, 0], [1.0, 1.0])),
                    Some(c) => Some(([spectra.add(&c.eta)?, spectra.add(&c.k)?], [c.ext_ior, 0.0])),
                };
                let alphas = |r: &Roughness| match (&r.alpha_u, &r.alpha_v, r.distribution) {
                    (FloatTexture::Constant(u), FloatTexture::Constant(v), MicrofacetType::Ggx) => {
                        Some((*u, *v))
                    }
                    _ => None,
                };
                match (&s.interface, &s.rough) {
                    (Interface::Dielectric { eta }, None) => {
                        Some(self.push(MAT_DIELECTRIC, [r_s, t_s, 0, 0], [*eta, 0.0, 0.0, 0.0]))
                    }
                    (Interface::Conductor(ior), None) => {
                        let ([e, k], [ext, mirror]) = metal(ior, spectra)?;
                        Some(self.push(MAT_CONDUCTOR, [r_s, e, k, 0], [ext, mirror, 0.0, 0.0]))
                    }
                    (Interface::Conductor(ior), Some(r)) => {
                        let (au, av) = alphas(r)?;
                        let ([e, k], [ext, mirror]) = metal(ior, spectra)?;
                        // The distribution clamps its roughness (see `MicrofacetDistribution`).
                        let d = MicrofacetDistribution::new(MicrofacetType::Ggx, au, av);
                        Some(self.push(
                            MAT_ROUGH_CONDUCTOR,
                            [r_s, e, k, 0],
                            [ext, mirror, d.alpha_x, d.alpha_y],
                        ))
                    }
                    _ => None,
                }
            }
            _ => None,
        }
    }
}
