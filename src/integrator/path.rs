//! Unidirectional path tracing with next-event estimation and multiple importance sampling
//! (Veach 1997, ch. 9, power heuristic β = 2), Russian roulette after `rr_depth`, spectral
//! transport of four hero wavelengths (Wilkie et al. 2014).
//!
//! Depth follows Mitsuba's `path` integrator: `max_depth` counts path segments, so
//! `max_depth = 1` shows only emitters seen directly, 2 adds direct lighting, and `None`
//! (Mitsuba's −1) leaves termination to Russian roulette (with a safety cap far beyond where
//! energy matters).
//!
//! A path is a [`PathState`] advanced one vertex at a time: [`PathState::escape`] when its ray
//! leaves the scene, [`PathState::scatter`] when it meets a surface. Scattering does not trace
//! its shadow ray itself; it hands it back with the contribution it carries if unoccluded, so
//! that [`radiance`] (one path, tracing each ray at once) and the wavefront integrator
//! ([`super::wave`], many paths, tracing rays in batches) share every line of the estimator.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `max_depth` (0.6: `maxDepth`) | integer | -1 | segments | longest path (1: emitters seen directly, 2: direct light; −1: unbounded); between -1 and 1048576 |
//! | `rr_depth` (0.6: `rrDepth`) | integer | 5 | segments | depth from which Russian roulette may end paths; between 0 and 1048576 |
//! | `hide_emitters` (0.6: `hideEmitters`) | boolean | false | — | do not show emitters seen directly from the camera |
//!
//! Mitsuba's integrators that ophis does not have (`volpath`, `prb`, `ptracer`, 0.6's `bdpt`,
//! `sppm`, …) render as this one, reading these parameters, with a warning.
//!
//! ## Smooth environments and the BSDF's own samples
//!
//! Next-event estimation chooses one light per vertex ([`crate::light::LightSampler`]); a
//! `constant` environment is sampled about the surface normal. The *smooth environments* are
//! the `constant` one and, beside a light that is neither (the sun, a lamp), Preetham's clear
//! sky (`sky`, the sky of `sunsky`), whose radiance varies slowly over the sphere (its
//! brightest part is the broad glow around the sun, not a feature a BSDF's samples would
//! miss); a bitmap `envmap` may hold a sun or a window and is not one.
//!
//! At a vertex whose BSDF has a
//! glossy or delta lobe and samples f · cos closely ([`crate::bsdf::Bxdf::samples_smooth_env`]:
//! rough conductors, dielectrics and films, the plastics, the closed-form coats) the BSDF's own
//! samples carry a smooth environment with little variance: they are drawn in proportion to
//! f · cos, their lobe chosen in proportion to its albedo. Light samples weighted against them
//! by MIS only move part of the diffuse lobe's share onto rarer samples, which unbalances that
//! lobe choice, and they take light samples from a sun beside the sky. A Lambertian surface's
//! cosine samples carry the sky as well as the light's cosine samples do; beside other lights
//! those light samples are better spent on them (a sun or a lamp is reached best, or only, by
//! light samples), while with the sky alone they are a second look at its visibility and
//! stay. Such a vertex therefore chooses among the other lights only (the same choice
//! conditioned on not picking a smooth environment), a BSDF sample from it that escapes to a
//! smooth environment has MIS weight 1, and an area light it hits is weighted with the
//! conditional choice's probability, which the `env_by_bsdf` field of [`PathState`]
//! remembers. Only with both techniques in use (`--strategy mis`). The random walk's own
//! samples are noisy: it keeps choosing the sky (on the thin-film sphere with the walked coat,
//! leaving the grey sky to the walk's samples gave 3.3× the noise per sample), unless it
//! samples from its mixture density (`multilayered`'s `rough_coat` = `mixture`), whose samples
//! weigh the coat's reflection by its exact value: then it is one of them (on the flagship,
//! `bench/noise.py` at 320×180, 16 spp, 2 pairs, 2026-12-06, with the mixture's first version,
//! keeping the sky's light samples for it was 0.89× as fast to equal noise as the walk's own
//! sampling, leaving them out 0.96×).
//!
//! The sky joined the constant environment in that class in the eleventh session: on the
//! flagship (`bench/noise.py --spp 64 --repeats 3 --cpu`, 320×180, adaptive, 2026-12-03) the
//! ground's Lambertian vertices then spend their light samples on the sun, which had shared
//! them with the sky (its part of the even mixture and its share of the power took 32 % of
//! them), and the sky's light on the ground comes from the cosine samples: relVar × spp
//! 0.127 → 0.103 at 1.06× the CPU per sample, 1.23× (1.10–1.27×) faster to equal noise.
//! With the light choice of [`crate::light::LightSampler`] (the sky's share of it no longer
//! padded), `scenes/daylight.xml` (a diffuse and a rough gold sphere on a diffuse ground,
//! 160², 64 spp, 2 pairs) renders 2.25× (2.03–2.47×) faster to equal noise than before
//! (0.157 → 0.087). With the sky alone (the same scene, `sun_scale` 0) the gold sphere's
//! light samples stay a little better (0.069 against 0.071), so there the sky is not one.
//!
//! Measured (`bench/noise.py` against the build before, 96², 64 spp, Sobol, 2 pairs; noise
//! per sample before → after, and the speed-up at equal noise, which counts the light
//! samples no longer traced): the thin-film benchmark sphere (`bench/thinfilm-sphere.xml`,
//! grey sky and sun) with the smooth film coat 0.00079 → 0.00014 (6.6×), with the rough coat
//! in closed form 0.0043 → 0.0023 (2.1×); over a base of albedo 0.5, 0.0026 → 0.00018 (17×)
//! and 0.0052 → 0.0019 (2.8×); an isolated `plastic` sphere (diffuse 0.5) 0.0015 → 0.00052
//! (2.9×), `roughplastic` 0.0021 → 0.0010 (2.1×), `diffuse` 0.0012 → 0.00024 (5.3×); a
//! diffuse sphere on a diffuse ground under sky and sun 0.0097 → 0.0057 (1.8×; 2.5× with
//! independent samples), level with a sun 7 or 40 times dimmer (1.01×) and unchanged without
//! one. It costs noise where a sky alone lights a diffuse-heavy plastic that its surroundings
//! occlude (a plastic sphere on a plastic ground, no sun: 0.017 → 0.022), the light sample
//! having been a second look at the sky's visibility, but the time saved still leaves it ahead
//! (1.08×); the same scene with Lambertian surfaces would lose 1.2×, which is why they keep
//! the sky's light samples when it is the only light.
//!
//! Known limits: no participating media outside `multilayered`.

use crate::bsdf::{Bsdf, Material, TransportMode};
use crate::light::LightSampleContext;
use crate::math::{power_heuristic, Ray, Vec3};
use crate::plugin::{declare, Args, Check, Param, SceneError};
use crate::sampler::Sampler;
use crate::scene::{IntegratorKind, IntegratorSettings, Scene};
use crate::shape::SurfaceInteraction;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::TexCoord;

/// Which estimators to combine; the render tests compare them against each other.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathStrategy {
    /// Light sampling and BSDF sampling combined by MIS (the default).
    Mis,
    /// Only light sampling for emitters reachable that way (delta BSDF paths still hit lights).
    LightOnly,
    /// Only BSDF sampling (next-event estimation off).
    BsdfOnly,
}

/// Paths never exceed this many segments, even with `max_depth = −1`; Russian roulette has ended
/// all but a negligible fraction long before.
const SAFETY_DEPTH: u32 = 1024;

/// The settings a path consults at every vertex.
#[derive(Clone, Copy, Debug)]
pub struct PathConfig {
    pub(crate) max_depth: u32,
    pub(crate) rr_depth: u32,
    pub(crate) hide_emitters: bool,
    pub(crate) strategy: PathStrategy,
    pub(crate) use_nee: bool,
    pub(crate) use_bsdf_hits: bool,
    /// Whether vertices whose BSDF samples smooth environments well
    /// ([`crate::bsdf::Bsdf::samples_smooth_env`]) leave those lights out of their light
    /// choice: with both techniques in use and such a light in the scene.
    pub(crate) env_to_bsdf: bool,
    /// Whether next-event estimation has lights besides the smooth environments to choose
    /// ([`crate::light::LightSampler::has_other_lights`]).
    pub(crate) other_lights: bool,
}

impl PathConfig {
    /// The `path` integrator's settings of `scene` with the given strategy.
    pub fn new(scene: &Scene, strategy: PathStrategy) -> PathConfig {
        let s = &scene.integrator;
        PathConfig {
            max_depth: s.max_depth.unwrap_or(SAFETY_DEPTH).min(SAFETY_DEPTH),
            rr_depth: s.rr_depth,
            hide_emitters: s.hide_emitters,
            strategy,
            use_nee: strategy != PathStrategy::BsdfOnly,
            use_bsdf_hits: strategy != PathStrategy::LightOnly,
            env_to_bsdf: strategy == PathStrategy::Mis && scene.light_sampler.has_smooth_env(),
            other_lights: scene.light_sampler.has_other_lights(),
        }
    }
}

/// A shadow ray and the radiance it adds to its path when nothing blocks it.
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay {
    pub ray: Ray,
    pub contribution: SampledSpectrum,
}

/// One path between vertices: its next ray, throughput and what MIS needs of the last vertex.
#[derive(Clone, Copy, Debug)]
pub struct PathState {
    /// The ray to trace next.
    pub ray: Ray,
    /// Radiance gathered so far.
    pub l: SampledSpectrum,
    /// Throughput.
    pub(crate) beta: SampledSpectrum,
    /// Product of η² over refractions (Russian roulette's correction).
    pub(crate) eta_scale: f32,
    /// Whether the last bounce was a delta lobe (or there was none yet).
    pub(crate) specular_bounce: bool,
    /// Solid-angle density of the last BSDF sample (for MIS at an emitter hit).
    pub(crate) prev_pdf: f32,
    /// Whether the last vertex left smooth environments to its BSDF's samples (its light
    /// choice left them out; see the module notes).
    pub(crate) env_by_bsdf: bool,
    /// The last vertex, as a light-sampling context.
    pub(crate) prev_ctx: LightSampleContext,
    /// Surfaces scattered at (null surfaces not counted).
    pub(crate) depth: u32,
    pub(crate) null_crossings: u32,
    /// Pixel footprint for texture filtering: the camera's estimate at the path length (no ray
    /// differentials yet; after a bounce this underestimates the footprint).
    pub(crate) path_length: f32,
}

impl PathState {
    /// A path starting with the camera ray `ray`.
    pub fn new(ray: Ray) -> PathState {
        PathState {
            ray,
            l: SampledSpectrum::ZERO,
            beta: SampledSpectrum::ONE,
            eta_scale: 1.0,
            specular_bounce: true,
            prev_pdf: 0.0,
            env_by_bsdf: false,
            prev_ctx: LightSampleContext {
                p: ray.o,
                n: Vec3::ZERO,
            },
            depth: 0,
            null_crossings: 0,
            path_length: 0.0,
        }
    }

    /// The radiance estimate of a finished path (NaN and infinities never reach the film).
    pub fn radiance(&self) -> SampledSpectrum {
        if self.l.is_finite() {
            self.l
        } else {
            SampledSpectrum::ZERO
        }
    }

    /// The ray escaped the scene: adds the environment lights it sees. The path ends.
    pub fn escape(&mut self, scene: &Scene, cfg: &PathConfig, wl: &SampledWavelengths) {
        if self.depth == 0 && cfg.hide_emitters {
            return;
        }
        let d = self.ray.d;
        for &li in &scene.infinite_lights {
            let light = &scene.lights[li as usize];
            let le = light.le(d, wl);
            if le.is_black() {
                continue;
            }
            let w = self.emitter_hit_weight(scene, cfg, li, || {
                light.pdf_li(&self.prev_ctx, d, &scene.shapes, None)
            });
            self.l += self.beta * le * w;
        }
    }

    /// The ray met the surface `si`: adds its emission, then samples the next direction and
    /// a light. Returns whether the path goes on (with `self.ray` its next ray), and the
    /// shadow ray of next-event estimation, if any, whose contribution the caller adds to
    /// `self.l` when it is unoccluded.
    pub fn scatter(
        &mut self,
        scene: &Scene,
        cfg: &PathConfig,
        wl: &SampledWavelengths,
        si: &SurfaceInteraction,
        sampler: &mut Sampler,
    ) -> (bool, Option<ShadowRay>) {
        let wo = -self.ray.d;
        self.path_length += si.t;
        // Emission from an area light that the path hit.
        if let Some(li) = scene.shape_light[si.shape as usize] {
            if !(self.depth == 0 && cfg.hide_emitters) {
                let light = &scene.lights[li as usize];
                let le = light.l(si, wo, wl);
                if !le.is_black() {
                    let d = self.ray.d;
                    let w = self.emitter_hit_weight(scene, cfg, li, || {
                        light.pdf_li(&self.prev_ctx, d, &scene.shapes, Some(si))
                    });
                    self.l += self.beta * le * w;
                }
            }
        }

        let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
        if matches!(material, Material::Null) {
            // Mitsuba's `null` BSDF: the surface only marks a boundary (or an emitter); the
            // path continues unchanged and the crossing does not count as a bounce.
            self.null_crossings += 1;
            if self.null_crossings > SAFETY_DEPTH {
                return (false, None);
            }
            self.ray = Ray::spawn(si.p, si.ng, self.ray.d);
            return (true, None);
        }

        self.depth += 1;
        if self.depth >= cfg.max_depth {
            return (false, None);
        }

        let front = si.ng.dot(wo) >= 0.0;
        let tc = TexCoord { uv: si.uv, p: si.p };
        let bsdf = Bsdf {
            frame: material.shading_frame(
                si,
                wo,
                scene.camera.footprint(scene.height, self.path_length),
            ),
            bxdf: material.bxdf(&tc, wl, front, sampler.vertex_seed()),
            two_sided: material.is_two_sided(),
        };
        let flags = bsdf.flags();
        if flags.0 == 0 {
            return (false, None);
        }

        // Next-event estimation. The light sample's set of dimensions (its 2D point, then the
        // light choice) is drawn at every vertex, used or not.
        sampler.start_set();
        let u = sampler.get_2d();
        let u_light = sampler.get_1d();
        let mut shadow = None;
        let env_by_bsdf =
            cfg.env_to_bsdf && flags.is_non_specular() && bsdf.samples_smooth_env(cfg.other_lights);
        if cfg.use_nee && flags.is_non_specular() {
            let ctx = LightSampleContext { p: si.p, n: si.ng };
            if let Some((li, pmf)) = scene.light_sampler.sample_for(u_light, env_by_bsdf) {
                let light = &scene.lights[li];
                if let Some(ls) = light.sample_li(&ctx, u, wl, &scene.shapes) {
                    if ls.pdf > 0.0 && !ls.l.is_black() {
                        let f = bsdf.f(wo, ls.wi, TransportMode::Radiance)
                            * ls.wi.dot(bsdf.frame.n).abs();
                        if !f.is_black() {
                            let light_pdf = pmf * ls.pdf;
                            let w = if ls.is_delta || cfg.strategy == PathStrategy::LightOnly {
                                1.0
                            } else {
                                let bsdf_pdf = bsdf.pdf(wo, ls.wi, TransportMode::Radiance);
                                power_heuristic(light_pdf, bsdf_pdf)
                            };
                            shadow = Some(ShadowRay {
                                ray: Ray::spawn_to(si.p, si.ng, ls.p_light),
                                contribution: self.beta * f * ls.l * (w / light_pdf),
                            });
                        }
                    }
                }
            }
        }

        // BSDF sampling: the set's 2D point, the lobe choice, and (below) Russian roulette.
        sampler.start_set();
        let u = sampler.get_2d();
        let uc = sampler.get_1d();
        let Some(bs) = bsdf.sample_f(wo, uc, u, TransportMode::Radiance) else {
            return (false, shadow);
        };
        let cos = bs.wi.dot(bsdf.frame.n).abs();
        self.beta *= bs.f * (cos / bs.pdf);
        if !self.beta.is_finite() {
            return (false, shadow);
        }
        self.prev_pdf = if bs.pdf_is_proportional {
            bsdf.pdf(wo, bs.wi, TransportMode::Radiance)
        } else {
            bs.pdf
        };
        self.specular_bounce = bs.is_specular();
        self.env_by_bsdf = env_by_bsdf;
        if bs.is_transmission() {
            self.eta_scale *= bs.eta * bs.eta;
        }
        self.prev_ctx = LightSampleContext { p: si.p, n: si.ng };
        self.ray = Ray::spawn(si.p, si.ng, bs.wi);

        // Russian roulette on the throughput, corrected for radiance compression at refraction.
        if self.depth >= cfg.rr_depth {
            let q = (self.beta.max_value() * self.eta_scale).min(0.95);
            if !(q > 0.0) || sampler.get_1d() >= q {
                return (false, shadow);
            }
            self.beta /= q;
        }
        (!self.beta.is_black(), shadow)
    }

    /// MIS weight for emission found by BSDF sampling.
    #[inline]
    fn emitter_hit_weight(
        &self,
        scene: &Scene,
        cfg: &PathConfig,
        light: u32,
        pdf_li: impl FnOnce() -> f32,
    ) -> f32 {
        if self.specular_bounce {
            // Light sampling cannot produce this path (camera ray or delta lobe).
            return 1.0;
        }
        if !cfg.use_bsdf_hits {
            return 0.0;
        }
        if !cfg.use_nee {
            return 1.0;
        }
        if self.env_by_bsdf && scene.light_sampler.is_smooth_env(light as usize) {
            // The last vertex's light choice left this light out: its BSDF sample is the only
            // technique.
            return 1.0;
        }
        let light_pdf = scene
            .light_sampler
            .pmf_for(light as usize, self.env_by_bsdf)
            * pdf_li();
        power_heuristic(self.prev_pdf, light_pdf)
    }
}

/// Estimates the radiance arriving along a camera ray at the path's wavelengths (with the
/// scene's integrator: `direct` scenes are handed to [`super::direct::radiance`]).
pub fn radiance(
    scene: &Scene,
    ray: Ray,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
    strategy: PathStrategy,
) -> SampledSpectrum {
    if let IntegratorKind::Direct {
        emitter_samples,
        bsdf_samples,
    } = scene.integrator.kind
    {
        let counts = match strategy {
            PathStrategy::Mis => (emitter_samples, bsdf_samples),
            PathStrategy::LightOnly => (emitter_samples, 0),
            PathStrategy::BsdfOnly => (0, bsdf_samples),
        };
        return super::direct::radiance(scene, ray, wl, sampler, counts);
    }
    let cfg = PathConfig::new(scene, strategy);
    let mut path = PathState::new(ray);
    loop {
        let Some((_, si)) = scene.intersect(&path.ray) else {
            path.escape(scene, &cfg, wl);
            break;
        };
        let (alive, shadow) = path.scatter(scene, &cfg, wl, &si, sampler);
        if let Some(s) = shadow {
            if !scene.occluded(&s.ray) {
                path.l += s.contribution;
            }
        }
        if !alive {
            break;
        }
    }
    path.radiance()
}

// The `path` plugin: its declaration and loader (the estimator is above).

/// Whether emitters seen directly are shown; `direct` reads it too.
pub(crate) const HIDE_EMITTERS: Param = Param::bool("hide_emitters", false)
    .v06("hideEmitters")
    .doc("do not show emitters seen directly from the camera");

declare!(PLUGIN: IntegratorSettings = Integrator "path" []
    "unidirectional path tracing with next-event estimation and MIS"
    [&[
        Param::int("max_depth", -1)
            .v06("maxDepth")
            .check(Check::Range(-1.0, (1 << 20) as f64))
            .unit("segments")
            .doc("longest path (1: emitters seen directly, 2: direct light; −1: unbounded)"),
        Param::int("rr_depth", 5)
            .v06("rrDepth")
            .check(Check::Range(0.0, (1 << 20) as f64))
            .unit("segments")
            .doc("depth from which Russian roulette may end paths"),
        HIDE_EMITTERS,
    ]] load);

fn load(a: &mut Args, _: ()) -> Result<IntegratorSettings, SceneError> {
    let max_depth = a.int("max_depth")?;
    Ok(IntegratorSettings {
        kind: IntegratorKind::Path,
        max_depth: u32::try_from(max_depth).ok(),
        rr_depth: a.u32("rr_depth")?,
        hide_emitters: a.bool("hide_emitters")?,
        aov: None,
    })
}
