//! Next-event estimation in lanes: each lane picks a light
//! ([`crate::light::LightSampler::sample_lanes_for`], leaving smooth environments out where
//! its vertex leaves them to the BSDF) and samples a direction to it. Mesh area lights are
//! sampled in lanes; the other lights by their own scalar `sample_li`, lane by lane.

use super::lookup::Groups;
use super::vertex::{eval_spectrum, lanes, Ctx, Scratch, Spec};
use crate::light::LightSampleContext;
use crate::math::warp::uniform_triangle;
use crate::math::Vec2;
use crate::shape::{area_to_solid_angle_lanes, Shape};
use crate::simd::{Float, Int, Mask, V3};

/// A sampled light direction in lanes ([`crate::light::LightLiSample`]).
pub(super) struct LightSample<F: Float> {
    pub(super) valid: F::M,
    pub(super) l: Spec<F>,
    pub(super) wi: V3<F>,
    pub(super) pdf: F,
    pub(super) p_light: V3<F>,
    pub(super) delta: F::M,
    /// The probability of having picked the light.
    pub(super) pmf: F,
}

/// Picks a light for each lane of `m` and samples a direction to it from (p, ng)
/// ([`crate::light::LightSampler::sample_lanes_for`] and [`crate::light::Light::sample_li`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn sample_lights<F: Float>(
    c: &Ctx,
    m: F::M,
    no_env: F::M,
    p: V3<F>,
    ng: V3<F>,
    u_light: F,
    u0: F,
    u1: F,
    lambda: &Spec<F>,
    wl_pdf: &Spec<F>,
    d65: &Spec<F>,
    scratch: &mut Scratch,
) -> LightSample<F> {
    let (scene, prog) = (c.scene, c.prog);
    let zero = F::splat(0.0);
    let no_sample = LightSample {
        valid: F::M::splat(false),
        l: [zero; 4],
        wi: V3::new(zero, zero, zero),
        pdf: zero,
        p_light: V3::new(zero, zero, zero),
        delta: F::M::splat(false),
        pmf: zero,
    };
    let Some((chosen, pmf)) = scene.light_sampler.sample_lanes_for(u_light, no_env) else {
        return no_sample;
    };
    // Lanes left with nothing to choose (only smooth environments, all left out) take no
    // sample, as the scalar `sample_for` returns none.
    let m = m & pmf.gt(zero);
    // Per lane: what depends on the chosen light's own tables.
    let light = &mut scratch.light_index;
    chosen.store(light);
    let (sc, rest) = scratch.light.split_at_mut(13);
    let (tri, rest) = rest.split_at_mut(9);
    let (us, ux) = rest.split_at_mut(2);
    let ux = &mut ux[0];
    u0.store(&mut us[0]);
    u1.store(&mut us[1]);
    // Lane lights: the triangle's corners and the remapped u0 (alias table in f64); other
    // lights: their own scalar sample.
    let mut in_lanes = 0u32;
    let mut sc_ok = 0u32;
    let mut delta = 0u32;
    for i in lanes(m.bits()) {
        let li = light[i] as usize;
        if prog.light_lanes[li] == 1 {
            in_lanes |= 1 << i;
            let Shape::Mesh(mesh) = &scene.shapes[prog.light_shape[li] as usize] else {
                unreachable!("lane lights are meshes")
            };
            let (t, r) = mesh.alias().sample(us[0][i]);
            ux[i] = r;
            let corners = mesh.triangle(t as u32).map(|k| mesh.position(k));
            for (k, q) in corners.iter().enumerate() {
                for a in 0..3 {
                    tri[3 * k + a][i] = q[a];
                }
            }
        } else {
            let ctx = LightSampleContext {
                p: p.lane(i),
                n: ng.lane(i),
            };
            let wl = crate::spectrum::SampledWavelengths {
                lambda: std::array::from_fn(|k| lambda[k].lane(i)),
                pdf: std::array::from_fn(|k| wl_pdf[k].lane(i)),
                d65: std::array::from_fn(|k| d65[k].lane(i)),
            };
            let u = Vec2::new(us[0][i], us[1][i]);
            if let Some(ls) = scene.lights[li].sample_li(&ctx, u, &wl, &scene.shapes) {
                sc_ok |= 1 << i;
                delta |= (ls.is_delta as u32) << i;
                for (row, v) in sc.iter_mut().zip(ls.l.0) {
                    row[i] = v;
                }
                for a in 0..3 {
                    sc[4 + a][i] = ls.wi[a];
                    sc[7 + a][i] = ls.p_light[a];
                }
                sc[10][i] = ls.pdf;
            }
        }
    }

    let mut out = LightSample {
        valid: F::M::from_bits(sc_ok),
        l: spec!(k => F::load(&sc[k])),
        wi: V3::new(F::load(&sc[4]), F::load(&sc[5]), F::load(&sc[6])),
        pdf: F::load(&sc[10]),
        p_light: V3::new(F::load(&sc[7]), F::load(&sc[8]), F::load(&sc[9])),
        delta: F::M::from_bits(delta),
        pmf,
    };
    if in_lanes != 0 {
        // Mesh area lights ([`crate::shape::TriangleMesh::sample_direct`] and
        // [`crate::light::AreaLight::sample_li`]).
        let lm = F::M::from_bits(in_lanes);
        let light = F::I::load(light);
        let (p0, p1, p2) = (
            corner::<F>(tri, 0),
            corner::<F>(tri, 3),
            corner::<F>(tri, 6),
        );
        let (b0, b1) = uniform_triangle(F::load(ux), u1);
        let b2 = F::splat(1.0) - b0 - b1;
        let pos = p0 * b0 + p1 * b1 + p2 * b2;
        let n = (p1 - p0).cross(p2 - p0).normalize();
        let lights = Groups::<F>::new(light, lm);
        let flip = lights.i(&prog.light_flip).eq(F::I::splat(1));
        let n = V3::select(flip, -n, n);
        let pdf = area_to_solid_angle_lanes(lights.f(&prog.light_inv_area), p, pos, n);
        let dd = pos - p;
        let dist2 = dd.length_squared();
        let wi = dd / dist2.sqrt();
        let ok = pdf.gt(zero) & pdf.is_finite() & dist2.gt(zero) & !n.dot(-wi).le(zero);
        let ok = lm & ok;
        let le = eval_spectrum(&prog.spectra, lights.i(&prog.light_spec), lm, lambda, d65);
        out.valid = out.valid | ok;
        for (o, &e) in out.l.iter_mut().zip(&le) {
            *o = F::select(lm, e, *o);
        }
        out.wi = V3::select(lm, wi, out.wi);
        out.pdf = F::select(lm, pdf, out.pdf);
        out.p_light = V3::select(lm, pos, out.p_light);
    }
    out
}

/// The corner whose x, y and z lanes are the tables `tri[k..k + 3]`. (A function, not a
/// closure: a closure is compiled without the caller's instruction set, and its lane loads
/// become calls.)
#[inline(always)]
fn corner<F: Float>(tri: &[[f32; 16]], k: usize) -> V3<F> {
    V3::new(F::load(&tri[k]), F::load(&tri[k + 1]), F::load(&tri[k + 2]))
}
