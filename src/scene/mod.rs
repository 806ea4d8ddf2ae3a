//! Scene loading and the built scene: geometry with its BVH, materials, lights, camera and
//! render settings.

pub mod build;
pub mod builtin;
pub mod mitsuba;

use crate::accel::{Accel, Bvh};
use crate::bsdf::Material;
use crate::camera::Camera;
use crate::film::Filter;
use crate::light::{Light, LightSampler};
use crate::math::{Bounds3, Ray};
use crate::sampler::SamplerKind;
use crate::shape::{Hit, Shape, SurfaceInteraction};

/// Which light-transport estimator renders the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorKind {
    /// Mitsuba's `path`: full path tracing.
    Path,
    /// Mitsuba's `direct`: emission and direct light at the first surface, with this many
    /// light and BSDF samples per camera sample.
    Direct {
        emitter_samples: u32,
        bsdf_samples: u32,
    },
}

/// Integrator settings (Mitsuba's `path` and `direct`).
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratorSettings {
    /// The estimator.
    pub kind: IntegratorKind,
    /// Longest path in segments; `None` = unbounded (Russian roulette ends paths).
    pub max_depth: Option<u32>,
    /// Depth from which Russian roulette may end paths.
    pub rr_depth: u32,
    /// Hide directly visible emitters.
    pub hide_emitters: bool,
    /// Mitsuba's `aov` integrator around the path tracer: extra channels to record.
    pub aov: Option<crate::integrator::aov::AovSettings>,
}

impl Default for IntegratorSettings {
    fn default() -> Self {
        IntegratorSettings {
            kind: IntegratorKind::Path,
            max_depth: None,
            rr_depth: 5,
            hide_emitters: false,
            aov: None,
        }
    }
}

/// Sampling settings.
#[derive(Clone, Debug, PartialEq)]
pub struct SamplerSettings {
    pub kind: SamplerKind,
    pub spp: u32,
    pub seed: u64,
    /// Spend the samples where the neighbouring pixels are noisy ([`crate::render::adaptive`];
    /// an ophis extension).
    pub adaptive: bool,
}

/// A scene ready to render.
#[derive(Debug)]
pub struct Scene {
    pub shapes: Vec<Shape>,
    pub bvh: Bvh,
    pub materials: Vec<Material>,
    /// Material index per shape.
    pub shape_material: Vec<u32>,
    /// Area light index per shape, if the shape emits.
    pub shape_light: Vec<Option<u32>>,
    /// A label per shape for messages and the `shape_index` AOV's legend: the element's `id`,
    /// or its plugin name, with the part for shapes made of several (`snake.belly`).
    pub shape_labels: Vec<String>,
    pub lights: Vec<Light>,
    pub light_sampler: LightSampler,
    /// Indices of lights at infinity (environment, constant).
    pub infinite_lights: Vec<u32>,
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
    pub filter: Filter,
    pub integrator: IntegratorSettings,
    pub sampler: SamplerSettings,
    pub bounds: Bounds3,
}

impl Scene {
    /// Closest hit along the ray.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<(Hit, SurfaceInteraction)> {
        self.bvh.intersect_interaction(&self.shapes, ray)
    }

    /// Whether anything blocks the ray before `ray.t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.bvh.occluded(&self.shapes, ray)
    }

    /// Number of triangles and analytic primitives.
    pub fn primitive_count(&self) -> usize {
        self.shapes.iter().map(|s| s.prim_count()).sum()
    }
}
