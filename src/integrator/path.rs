//! Unidirectional path tracing with next-event estimation and multiple importance sampling
//! (Veach 1997, ch. 9, power heuristic β = 2), Russian roulette after `rr_depth`, spectral
//! transport of four hero wavelengths (Wilkie et al. 2014).
//!
//! Depth follows Mitsuba's `path` integrator: `max_depth` counts path segments, so
//! `max_depth = 1` shows only emitters seen directly, 2 adds direct lighting, and `None`
//! (Mitsuba's −1) leaves termination to Russian roulette (with a safety cap far beyond where
//! energy matters).
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
//! Known limits: no participating media outside `multilayered`.

use crate::bsdf::{Bsdf, Material, TransportMode};
use crate::light::LightSampleContext;
use crate::math::{power_heuristic, Ray, Vec3};
use crate::plugin::{declare, Args, Check, Param, SceneError};
use crate::sampler::Sampler;
use crate::scene::{IntegratorKind, IntegratorSettings, Scene};
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

/// Estimates the radiance arriving along a camera ray at the path's wavelengths (with the
/// scene's integrator: `direct` scenes are handed to [`super::direct::radiance`]).
pub fn radiance(
    scene: &Scene,
    mut ray: Ray,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
    strategy: PathStrategy,
) -> SampledSpectrum {
    let settings = &scene.integrator;
    if let IntegratorKind::Direct {
        emitter_samples,
        bsdf_samples,
    } = settings.kind
    {
        let counts = match strategy {
            PathStrategy::Mis => (emitter_samples, bsdf_samples),
            PathStrategy::LightOnly => (emitter_samples, 0),
            PathStrategy::BsdfOnly => (0, bsdf_samples),
        };
        return super::direct::radiance(scene, ray, wl, sampler, counts);
    }
    let max_depth = settings.max_depth.unwrap_or(SAFETY_DEPTH).min(SAFETY_DEPTH);
    let mut l = SampledSpectrum::ZERO;
    let mut beta = SampledSpectrum::ONE;
    let mut eta_scale = 1.0f32;
    let mut specular_bounce = true;
    let mut prev_pdf = 0.0f32;
    let mut prev_ctx = LightSampleContext {
        p: ray.o,
        n: Vec3::ZERO,
    };
    let use_nee = strategy != PathStrategy::BsdfOnly;
    let use_bsdf_hits = strategy != PathStrategy::LightOnly;
    let mut depth = 0u32;
    let mut null_crossings = 0u32;
    // Pixel footprint for texture filtering: the camera's estimate at the path length (no ray
    // differentials yet; after a bounce this underestimates the footprint).
    let mut path_length = 0.0f32;

    loop {
        let Some((_hit, si)) = scene.intersect(&ray) else {
            // Escaped: environment lights.
            if depth == 0 && settings.hide_emitters {
                break;
            }
            for &li in &scene.infinite_lights {
                let light = &scene.lights[li as usize];
                let le = light.le(ray.d, wl);
                if le.is_black() {
                    continue;
                }
                let w = emitter_hit_weight(
                    scene,
                    li,
                    specular_bounce,
                    use_nee,
                    use_bsdf_hits,
                    prev_pdf,
                    || light.pdf_li(&prev_ctx, ray.d, &scene.shapes, None),
                );
                l += beta * le * w;
            }
            break;
        };

        let wo = -ray.d;
        path_length += si.t;
        // Emission from an area light that the path hit.
        if let Some(li) = scene.shape_light[si.shape as usize] {
            if !(depth == 0 && settings.hide_emitters) {
                let light = &scene.lights[li as usize];
                let le = light.l(&si, wo, wl);
                if !le.is_black() {
                    let w = emitter_hit_weight(
                        scene,
                        li,
                        specular_bounce,
                        use_nee,
                        use_bsdf_hits,
                        prev_pdf,
                        || light.pdf_li(&prev_ctx, ray.d, &scene.shapes, Some(&si)),
                    );
                    l += beta * le * w;
                }
            }
        }

        let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
        if matches!(material, Material::Null) {
            // Mitsuba's `null` BSDF: the surface only marks a boundary (or an emitter); the
            // path continues unchanged and the crossing does not count as a bounce.
            null_crossings += 1;
            if null_crossings > SAFETY_DEPTH {
                break;
            }
            ray = Ray::spawn(si.p, si.ng, ray.d);
            continue;
        }

        depth += 1;
        if depth >= max_depth {
            break;
        }

        let front = si.ng.dot(wo) >= 0.0;
        let tc = TexCoord { uv: si.uv, p: si.p };
        let (bxdf, two_sided) = material.eval(&tc, wl, front, sampler.vertex_seed());
        let bsdf = Bsdf {
            frame: material.shading_frame(
                &si,
                wo,
                scene.camera.footprint(scene.height, path_length),
            ),
            bxdf,
            two_sided,
        };
        let flags = bsdf.flags();
        if flags.0 == 0 {
            break;
        }

        // Next-event estimation. The light sample's dimensions are drawn at every vertex so
        // that later bounces use the same sampler dimensions whatever the material.
        let u_light = sampler.get_1d();
        let u = sampler.get_2d();
        if use_nee && flags.is_non_specular() {
            let ctx = LightSampleContext { p: si.p, n: si.ng };
            if let Some((li, pmf)) = scene.light_sampler.sample(u_light) {
                let light = &scene.lights[li];
                if let Some(ls) = light.sample_li(&ctx, u, wl, &scene.shapes) {
                    if ls.pdf > 0.0 && !ls.l.is_black() {
                        let f = bsdf.f(wo, ls.wi, TransportMode::Radiance)
                            * ls.wi.dot(bsdf.frame.n).abs();
                        if !f.is_black() && !scene.occluded(&Ray::spawn_to(si.p, si.ng, ls.p_light))
                        {
                            let light_pdf = pmf * ls.pdf;
                            let w = if ls.is_delta || strategy == PathStrategy::LightOnly {
                                1.0
                            } else {
                                let bsdf_pdf = bsdf.pdf(wo, ls.wi, TransportMode::Radiance);
                                power_heuristic(light_pdf, bsdf_pdf)
                            };
                            l += beta * f * ls.l * (w / light_pdf);
                        }
                    }
                }
            }
        }

        // BSDF sampling.
        let uc = sampler.get_1d();
        let u = sampler.get_2d();
        let Some(bs) = bsdf.sample_f(wo, uc, u, TransportMode::Radiance) else {
            break;
        };
        let cos = bs.wi.dot(bsdf.frame.n).abs();
        beta *= bs.f * (cos / bs.pdf);
        if !beta.is_finite() {
            break;
        }
        prev_pdf = if bs.pdf_is_proportional {
            bsdf.pdf(wo, bs.wi, TransportMode::Radiance)
        } else {
            bs.pdf
        };
        specular_bounce = bs.is_specular();
        if bs.is_transmission() {
            eta_scale *= bs.eta * bs.eta;
        }
        prev_ctx = LightSampleContext { p: si.p, n: si.ng };
        ray = Ray::spawn(si.p, si.ng, bs.wi);

        // Russian roulette on the throughput, corrected for radiance compression at refraction.
        if depth >= settings.rr_depth {
            let q = (beta.max_value() * eta_scale).min(0.95);
            if !(q > 0.0) || sampler.get_1d() >= q {
                break;
            }
            beta /= q;
        }
        if beta.is_black() {
            break;
        }
    }
    // NaN/Inf never reach the film.
    if l.is_finite() {
        l
    } else {
        SampledSpectrum::ZERO
    }
}

/// MIS weight for emission found by BSDF sampling.
#[inline]
fn emitter_hit_weight(
    scene: &Scene,
    light: u32,
    specular_bounce: bool,
    use_nee: bool,
    use_bsdf_hits: bool,
    prev_pdf: f32,
    pdf_li: impl FnOnce() -> f32,
) -> f32 {
    if specular_bounce {
        // Light sampling cannot produce this path (camera ray or delta lobe).
        return 1.0;
    }
    if !use_bsdf_hits {
        return 0.0;
    }
    if !use_nee {
        return 1.0;
    }
    let light_pdf = scene.light_sampler.pmf(light as usize) * pdf_li();
    power_heuristic(prev_pdf, light_pdf)
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
        rr_depth: a.int("rr_depth")? as u32,
        hide_emitters: a.bool("hide_emitters")?,
        aov: None,
    })
}
