//! Direct illumination (Mitsuba's `direct` integrator): emission seen along the camera ray plus
//! light arriving at the first surface straight from the emitters, by `emitter_samples` light
//! samples and `bsdf_samples` BSDF samples combined with the power heuristic over the sample
//! counts (Veach 1997, §9.2: weights w_e = (N p_e)² / ((N p_e)² + (M p_b)²) for N light and M
//! BSDF samples). Indirect light is not followed.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `shading_samples` (0.6: `shadingSamples`) | integer | 1 | — | sets both counts below (give it or them, not both); between 0 and 65536 |
//! | `emitter_samples` (0.6: `emitterSamples`) | integer | `shading_samples` | — | light samples per camera sample (N); between 0 and 65536 |
//! | `bsdf_samples` (0.6: `bsdfSamples`) | integer | `shading_samples` | — | BSDF samples per camera sample (M); between 0 and 65536 |
//! | `hide_emitters` (0.6: `hideEmitters`) | boolean | false | — | do not show emitters seen directly from the camera |
//!
//! As in Mitsuba, light sampling is skipped at purely specular surfaces, and a BSDF sample
//! (specular ones included) counts the emitter it reaches: a mirror shows the lights it reflects,
//! a glass sphere does not show what lies behind it. `--strategy light` / `bsdf` render with
//! M = 0 / N = 0.
//!
//! Differences from Mitsuba: with `hide_emitters` an emitter seen directly is shaded like any
//! other surface (Mitsuba looks through it); `null` surfaces are looked through before shading;
//! a delta light's N samples are averaged (Mitsuba weights each by 1, so N > 1 brightens point
//! and directional lights N-fold).

use crate::bsdf::{Bsdf, Material, TransportMode};
use crate::light::LightSampleContext;
use crate::math::{power_heuristic, Ray};
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Ty};
use crate::sampler::Sampler;
use crate::scene::{IntegratorKind, IntegratorSettings, Scene};
use crate::shape::SurfaceInteraction;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::TexCoord;

/// Most light or BSDF samples per camera sample.
const MAX_SAMPLES: f64 = (1 << 16) as f64;

declare!(PLUGIN: IntegratorSettings = Integrator "direct" []
    "direct illumination: light and BSDF samples at the first surface, combined by MIS"
    [&[
        Param::int("shading_samples", 1)
            .v06("shadingSamples")
            .check(Check::Range(0.0, MAX_SAMPLES))
            .doc("sets both counts below (give it or them, not both)"),
        Param::new("emitter_samples", Ty::Integer, DefaultValue::Derived("`shading_samples`"))
            .v06("emitterSamples")
            .check(Check::Range(0.0, MAX_SAMPLES))
            .doc("light samples per camera sample (N)"),
        Param::new("bsdf_samples", Ty::Integer, DefaultValue::Derived("`shading_samples`"))
            .v06("bsdfSamples")
            .check(Check::Range(0.0, MAX_SAMPLES))
            .doc("BSDF samples per camera sample (M)"),
        super::path::HIDE_EMITTERS,
    ]] load);

fn load(a: &mut Args, _: ()) -> Result<IntegratorSettings, SceneError> {
    if a.has("shading_samples") && (a.has("emitter_samples") || a.has("bsdf_samples")) {
        return Err(SceneError::at(
            &a.node().loc,
            "integrator 'direct': found 'shading_samples' and 'emitter_samples' or \
             'bsdf_samples'; expected either the first or the others",
        ));
    }
    let all = a.int("shading_samples")?;
    let emitter_samples = a.int_opt("emitter_samples")?.unwrap_or(all) as u32;
    let bsdf_samples = a.int_opt("bsdf_samples")?.unwrap_or(all) as u32;
    if emitter_samples + bsdf_samples == 0 {
        return Err(SceneError::at(
            &a.node().loc,
            "integrator 'direct': found no emitter or BSDF samples; expected at least one",
        ));
    }
    Ok(IntegratorSettings {
        kind: IntegratorKind::Direct {
            emitter_samples,
            bsdf_samples,
        },
        hide_emitters: a.bool("hide_emitters")?,
        ..IntegratorSettings::default()
    })
}

/// Null surfaces crossed before giving up (a stack of them cannot be infinite).
const MAX_NULL_CROSSINGS: u32 = 1024;

/// The first non-null surface along `ray`, adding the emission of null surfaces crossed (and,
/// if `show`, of the surface found) to `l`; `None` when the ray escapes, after adding the
/// infinite lights if `show`.
fn first_surface(
    scene: &Scene,
    mut ray: Ray,
    wl: &SampledWavelengths,
    show: bool,
    l: &mut SampledSpectrum,
) -> Option<SurfaceInteraction> {
    for _ in 0..MAX_NULL_CROSSINGS {
        let Some((_, si)) = scene.intersect(&ray) else {
            if show {
                for &li in &scene.infinite_lights {
                    *l += scene.lights[li as usize].le(ray.d, wl);
                }
            }
            return None;
        };
        if show {
            if let Some(li) = scene.shape_light[si.shape as usize] {
                *l += scene.lights[li as usize].l(&si, -ray.d, wl);
            }
        }
        let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
        if !matches!(material, Material::Null) {
            return Some(si);
        }
        ray = Ray::spawn(si.p, si.ng, ray.d);
    }
    None
}

/// Emission reaching `p` along a BSDF-sampled ray (`None`: it reached no emitter), with the
/// light index and what light sampling needs for its pdf.
fn emitter_along(
    scene: &Scene,
    ray: &Ray,
    wl: &SampledWavelengths,
) -> Vec<(u32, SampledSpectrum, Option<SurfaceInteraction>)> {
    match scene.intersect(ray) {
        Some((_, si)) => match scene.shape_light[si.shape as usize] {
            Some(li) => {
                let le = scene.lights[li as usize].l(&si, -ray.d, wl);
                vec![(li, le, Some(si))]
            }
            None => Vec::new(),
        },
        None => scene
            .infinite_lights
            .iter()
            .map(|&li| (li, scene.lights[li as usize].le(ray.d, wl), None))
            .collect(),
    }
}

/// Estimates the directly lit radiance along a camera ray with `n` light and `m` BSDF
/// samples (not both zero).
pub fn radiance(
    scene: &Scene,
    ray: Ray,
    wl: &SampledWavelengths,
    sampler: &mut Sampler,
    (n, m): (u32, u32),
) -> SampledSpectrum {
    let mut l = SampledSpectrum::ZERO;
    let show = !scene.integrator.hide_emitters;
    let Some(si) = first_surface(scene, ray, wl, show, &mut l) else {
        return l;
    };
    let wo = -ray.d;
    let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
    let front = si.ng.dot(wo) >= 0.0;
    let tc = TexCoord { uv: si.uv, p: si.p };
    let bsdf = Bsdf {
        frame: material.shading_frame(&si, wo, scene.camera.footprint(scene.height, si.t)),
        bxdf: material.bxdf(&tc, wl, front, sampler.vertex_seed()),
        two_sided: material.is_two_sided(),
    };
    let flags = bsdf.flags();
    if flags.0 == 0 {
        return l;
    }
    let ctx = LightSampleContext { p: si.p, n: si.ng };
    let (nf, mf) = (n as f32, m as f32);

    if flags.is_non_specular() {
        for _ in 0..n {
            sampler.start_set();
            let u = sampler.get_2d();
            let u_light = sampler.get_1d();
            let Some((li, pmf)) = scene.light_sampler.sample(u_light) else {
                break;
            };
            let Some(ls) = scene.lights[li].sample_li(&ctx, u, wl, &scene.shapes) else {
                continue;
            };
            if !(ls.pdf > 0.0) || ls.l.is_black() {
                continue;
            }
            let f = bsdf.f(wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(bsdf.frame.n).abs();
            if f.is_black() || scene.occluded(&Ray::spawn_to(si.p, si.ng, ls.p_light)) {
                continue;
            }
            let light_pdf = pmf * ls.pdf;
            let w = if ls.is_delta || m == 0 {
                1.0
            } else {
                let bsdf_pdf = bsdf.pdf(wo, ls.wi, TransportMode::Radiance);
                power_heuristic(nf * light_pdf, mf * bsdf_pdf)
            };
            l += f * ls.l * (w / (nf * light_pdf));
        }
    }

    for _ in 0..m {
        sampler.start_set();
        let u = sampler.get_2d();
        let uc = sampler.get_1d();
        let Some(bs) = bsdf.sample_f(wo, uc, u, TransportMode::Radiance) else {
            continue;
        };
        let beta = bs.f * (bs.wi.dot(bsdf.frame.n).abs() / bs.pdf);
        if beta.is_black() || !beta.is_finite() {
            continue;
        }
        let bsdf_pdf = if bs.pdf_is_proportional {
            bsdf.pdf(wo, bs.wi, TransportMode::Radiance)
        } else {
            bs.pdf
        };
        let ray = Ray::spawn(si.p, si.ng, bs.wi);
        for (li, le, hit) in emitter_along(scene, &ray, wl) {
            if le.is_black() {
                continue;
            }
            let w = if bs.is_specular() || n == 0 {
                1.0
            } else {
                let light = &scene.lights[li as usize];
                let light_pdf = scene.light_sampler.pmf(li as usize)
                    * light.pdf_li(&ctx, bs.wi, &scene.shapes, hit.as_ref());
                power_heuristic(mf * bsdf_pdf, nf * light_pdf)
            };
            l += beta * le * (w / mf);
        }
    }
    if l.is_finite() {
        l
    } else {
        SampledSpectrum::ZERO
    }
}
