//! One path vertex for a chunk of consecutive paths, in lanes.
//!
//! This is [`PathState::escape`] / [`PathState::scatter`] of [`crate::integrator::path`]
//! rewritten over [`Float`] lanes for the hits that [`Program`] marks as lane hits, with the
//! same operations in the same order, so each lane ends with the bits the scalar code would
//! give it. Lanes die where the scalar code returns: a mask (`alive`) follows them, every
//! sampler draw and every store is made only for the lanes the scalar code would draw or
//! store for. The other paths of the chunk (escaped rays, other materials) run the scalar
//! code itself, one after the other.
//!
//! Parts that need a different table per lane (a triangle's corners and UVs, the light picked,
//! a point on its triangle) are fetched lane by lane; the arithmetic runs in lanes.

use super::bsdf::LaneBsdf;
use super::lookup::Groups;
use super::nee::sample_lights;
use super::pool::{Col, Pool, Spectra, MISS};
use super::program::{
    Program, SpectrumTable, SPEC_ALBEDO, SPEC_CONSTANT, SPEC_CURVE, SPEC_ILLUMINANT, SPEC_UNBOUNDED,
};
use super::{surface, Shadows};
use crate::integrator::path::{PathConfig, PathStrategy};
use crate::math::frame::FrameL;
use crate::math::power_heuristic_lanes;
use crate::math::ray::{spawn_origin, spawn_to};
use crate::sampler::{Sampler, SamplerKind};
use crate::scene::Scene;
use crate::shape::area_to_solid_angle_lanes;
pub(super) use crate::simd::lanes;
use crate::simd::{Float, Int, Mask, V3};
use crate::spectrum::rgb2spec::sigmoid_poly_lanes;
use crate::spectrum::SampledSpectrum;

/// What every chunk of a tile shares.
pub(super) struct Ctx<'a> {
    pub scene: &'a Scene,
    pub prog: &'a Program,
    pub cfg: PathConfig,
    pub kind: SamplerKind,
}

/// Lane tables filled lane by lane and then loaded as lanes, kept from chunk to chunk so
/// that they are not cleared each time (lanes a chunk does not write are masked off).
pub(super) struct Scratch {
    /// The surface's rows (see `surface`).
    pub surface: [[f32; 16]; 16],
    /// The light sample's rows (see `sample_lights`).
    pub light: [[f32; 16]; 25],
    /// The chosen light of each lane.
    pub light_index: [u32; 16],
}

impl Scratch {
    pub fn new() -> Box<Scratch> {
        Box::new(Scratch {
            surface: [[0.0; 16]; 16],
            light: [[0.0; 16]; 25],
            light_index: [0; 16],
        })
    }
}

/// A spectrum at the path's four wavelengths, in lanes.
pub(super) type Spec<F> = [F; 4];

#[inline(always)]
fn load3<F: Float>(a: &[Col<f32>; 3], base: usize) -> V3<F> {
    V3::new(
        F::load_at(&a[0][..], base),
        F::load_at(&a[1][..], base),
        F::load_at(&a[2][..], base),
    )
}

/// Rows `k .. k + 3` of a lane table as vectors.
#[inline(always)]
pub(super) fn load_v3<F: Float>(w: &[[f32; 16]], k: usize) -> V3<F> {
    V3::new(F::load(&w[k]), F::load(&w[k + 1]), F::load(&w[k + 2]))
}

#[inline(always)]
fn store_masked<F: Float>(a: &mut [f32], base: usize, m: F::M, v: F) {
    let old = F::load_at(a, base);
    F::select(m, v, old).store_at(a, base);
}

#[inline(always)]
fn store_masked_int<F: Float>(a: &mut [u32], base: usize, m: F::M, v: F::I) {
    let old = F::I::load_at(a, base);
    F::I::select(m, v, old).store_at(a, base);
}

#[inline(always)]
fn store3_masked<F: Float>(a: &mut [Col<f32>; 3], base: usize, m: F::M, v: V3<F>) {
    store_masked(&mut a[0][..], base, m, v.x);
    store_masked(&mut a[1][..], base, m, v.y);
    store_masked(&mut a[2][..], base, m, v.z);
}

#[inline(always)]
fn load_spec<F: Float>(a: &Spectra, base: usize) -> Spec<F> {
    spec!(k => F::load_at(&a[k][..], base))
}

#[inline(always)]
fn store_spec_masked<F: Float>(a: &mut Spectra, base: usize, m: F::M, v: Spec<F>) {
    for k in 0..4 {
        store_masked(&mut a[k][..], base, m, v[k]);
    }
}

/// Whether every component is zero, per lane ([`SampledSpectrum::is_black`]).
#[inline(always)]
pub(super) fn is_black<F: Float>(s: &Spec<F>) -> F::M {
    let z = F::splat(0.0);
    s[0].eq(z) & s[1].eq(z) & s[2].eq(z) & s[3].eq(z)
}

/// Whether every component is finite, per lane.
#[inline(always)]
pub(super) fn is_finite<F: Float>(s: &Spec<F>) -> F::M {
    s[0].is_finite() & s[1].is_finite() & s[2].is_finite() & s[3].is_finite()
}

/// Next sampler value of each lane in `m` (others 0): the independent sampler's PCG32 in
/// lanes, the others lane by lane.
#[inline(always)]
fn draw<F: Float>(pool: &mut Pool, base: usize, m: F::M, kind: SamplerKind) -> F {
    if kind == SamplerKind::Independent {
        let u = F::pcg_next_f32(&mut pool.rng_state[base..], &pool.rng_inc[base..], m);
        let dim = F::I::load_at(&pool.dim[..], base);
        store_masked_int::<F>(&mut pool.dim[..], base, m, dim + F::I::splat(1));
        return u;
    }
    let mut u = [0.0f32; 16];
    for i in lanes(m.bits()) {
        let mut st = pool.sampler_state(base + i);
        u[i] = st.next_1d(kind);
        pool.set_sampler_state(base + i, &st);
    }
    F::load(&u)
}

/// The next three sampler values of each lane in `m` (others 0), as three [`draw`]s give
/// them; for Sobol samples each lane's state is rebuilt once for the three, so values from
/// one set of the sequence are computed once.
#[inline(always)]
fn draw3<F: Float>(pool: &mut Pool, base: usize, m: F::M, kind: SamplerKind) -> [F; 3] {
    // No `array::from_fn` or `map` here: generic helpers outside this kernel's target features
    // are not inlined into it, and their lanes go through memory (cornell-box lost 20 %).
    if kind == SamplerKind::Independent {
        let a = draw::<F>(pool, base, m, kind);
        let b = draw::<F>(pool, base, m, kind);
        let c = draw::<F>(pool, base, m, kind);
        return [a, b, c];
    }
    let mut u = [[0.0f32; 16]; 3];
    for i in lanes(m.bits()) {
        let mut st = pool.sampler_state(base + i);
        for row in &mut u {
            row[i] = st.next_1d(kind);
        }
        pool.set_sampler_state(base + i, &st);
    }
    [F::load(&u[0]), F::load(&u[1]), F::load(&u[2])]
}

/// [`crate::sampler::SamplerState::start_set`] for the lanes in `m`: each skips to its next
/// set of four dimensions. (A lane's Sobol cache is rebuilt on its next draw either way.)
#[inline(always)]
fn start_set<F: Float>(pool: &mut Pool, base: usize, m: F::M) {
    let dim = F::I::load_at(&pool.dim[..], base);
    let up = (dim + F::I::splat(3)) & F::I::splat(!3);
    store_masked_int::<F>(&mut pool.dim[..], base, m, up);
}

/// Table spectra at the lanes' wavelengths ([`crate::spectrum::Spectrum::sample`]), for the
/// lanes of `m` (the others are 0); `d65` is D65 at those wavelengths.
#[inline(always)]
pub(super) fn eval_spectrum<F: Float>(
    t: &SpectrumTable,
    idx: F::I,
    m: F::M,
    lambda: &Spec<F>,
    d65: &Spec<F>,
) -> Spec<F> {
    let g = Groups::<F>::new(idx, m);
    let mode = g.i(&t.mode);
    let (c0, c1, c2) = (g.f(&t.c0), g.f(&t.c1), g.f(&t.c2));
    let scale = g.f(&t.scale);
    let constant = mode.eq(F::I::splat(SPEC_CONSTANT as i32));
    let albedo = mode.eq(F::I::splat(SPEC_ALBEDO as i32));
    let unbounded = mode.eq(F::I::splat(SPEC_UNBOUNDED as i32));
    let illuminant = mode.eq(F::I::splat(SPEC_ILLUMINANT as i32));
    let any_illuminant = illuminant.any();
    // A loop, not `spec`: this body is too large for a closure to be inlined.
    let mut out = [c0; 4];
    for ((o, &l), &d) in out.iter_mut().zip(lambda).zip(d65) {
        let s = sigmoid_poly_lanes(c0, c1, c2, l);
        let mut v = F::select(unbounded, s * scale, s);
        if any_illuminant {
            v = F::select(illuminant, scale * s * d, v);
        }
        let v = F::select(albedo, s, v);
        *o = F::select(constant, c0, v);
    }
    let curves = mode.eq(F::I::splat(SPEC_CURVE as i32));
    if curves.any() {
        // Tabulated curves, one distinct curve at a time.
        let curve = g.i(&t.curve);
        let mut todo = curves.bits();
        while todo != 0 {
            let c = curve.lane(todo.trailing_zeros() as usize);
            let this = curves & curve.eq(F::I::splat(c));
            let pl = &t.curves[c as usize];
            for (o, &l) in out.iter_mut().zip(lambda) {
                *o = F::select(this, pl.eval_lanes(l), *o);
            }
            todo &= !this.bits();
        }
    }
    out
}

/// Shades the paths `base .. base + F::LANES` (those below `pool.n`) that hit something or
/// escaped this round; see the module header.
#[inline(always)]
pub(super) fn shade_chunk<F: Float>(
    c: &Ctx,
    pool: &mut Pool,
    base: usize,
    shadows: &mut Shadows,
    scratch: &mut Scratch,
) {
    let n = pool.n - base;
    let active = F::M::from_bits(if n >= 32 { u32::MAX } else { (1u32 << n) - 1 });
    let shape = F::I::load_at(&pool.h_shape[..], base);
    let miss = shape.eq(F::I::splat(MISS as i32));
    let shape = F::I::select(miss, F::I::splat(0), shape);
    let shapes = Groups::<F>::new(shape, active.and_not(miss));
    let in_lanes = shapes.i(&c.prog.shape_lanes).eq(F::I::splat(1));
    let vector = active.and_not(miss) & in_lanes;
    let mut scalar = active.and_not(vector);
    if c.scene.infinite_lights.is_empty() {
        // Escaped rays see nothing and end.
        let escaped = active & miss;
        store_masked_int::<F>(&mut pool.alive[..], base, escaped, F::I::splat(0));
        scalar = scalar.and_not(escaped);
    }
    for i in lanes(scalar.bits()) {
        scalar_vertex(c, pool, base + i, shadows);
    }
    if vector.any() {
        vector_vertex::<F>(c, pool, base, vector, &shapes, shadows, scratch);
    }
}

/// The scalar estimator for path `i`.
fn scalar_vertex(c: &Ctx, pool: &mut Pool, i: usize, shadows: &mut Shadows) {
    let mut path = pool.load_path(i);
    let wl = pool.wavelengths(i);
    let alive = match pool.hit[i] {
        None => {
            path.escape(c.scene, &c.cfg, &wl);
            false
        }
        Some(h) => {
            let si = c.scene.bvh.raw_interaction(&c.scene.shapes, &h, &path.ray);
            let mut sampler = Sampler::resume(c.kind, c.scene.sampler.seed, pool.sampler_state(i));
            let (alive, shadow) = path.scatter(c.scene, &c.cfg, &wl, &si, &mut sampler);
            pool.set_sampler_state(i, &sampler.state());
            if let Some(s) = shadow {
                shadows.push(i as u32, s.ray, s.contribution);
            }
            alive
        }
    };
    pool.store_path(i, &path);
    pool.alive[i] = alive as u32;
}

/// The vertex in lanes for the lanes of `m` (all of which hit a shape of `shape`).
#[inline(always)]
fn vector_vertex<F: Float>(
    c: &Ctx,
    pool: &mut Pool,
    base: usize,
    m: F::M,
    shapes: &Groups<F>,
    shadows: &mut Shadows,
    scratch: &mut Scratch,
) {
    let (prog, cfg) = (c.prog, &c.cfg);
    let zero = F::splat(0.0);
    let one = F::splat(1.0);
    let d = load3::<F>(&pool.d, base);
    let wo = -d;
    let lambda = load_spec::<F>(&pool.lambda, base);
    let d65 = load_spec::<F>(&pool.d65, base);
    let mut beta = load_spec::<F>(&pool.beta, base);
    let mut l = load_spec::<F>(&pool.l, base);

    let surface::Surface { p, ng, ns, dpdu } =
        surface::surfaces::<F>(c, pool, base, m, shapes, &mut scratch.surface);
    let t = F::load_at(&pool.h_t[..], base);
    let path_length = F::load_at(&pool.path_length[..], base) + t;
    store_masked(&mut pool.path_length[..], base, m, path_length);

    // Emission from an area light that the path hit.
    let depth = F::I::load_at(&pool.depth[..], base);
    let specular = F::I::load_at(&pool.specular[..], base).eq(F::I::splat(1));
    let prev_pdf = F::load_at(&pool.prev_pdf[..], base);
    let emit1 = shapes.i(&prog.shape_emit);
    let mut emit = m.and_not(emit1.eq(F::I::splat(0)));
    if cfg.hide_emitters {
        emit = emit.and_not(depth.eq(F::I::splat(0)));
    }
    if emit.any() {
        let light = F::I::select(emit, emit1 - F::I::splat(1), F::I::splat(0));
        let lights = Groups::<F>::new(light, emit);
        let front = ng.dot(wo).gt(zero);
        let le = eval_spectrum(
            &prog.spectra,
            lights.i(&prog.light_spec),
            emit,
            &lambda,
            &d65,
        );
        let le = spec!(k => F::select(front, le[k], zero));
        let shows = emit.and_not(is_black(&le));
        if shows.any() {
            let w = if !cfg.use_bsdf_hits {
                zero
            } else if !cfg.use_nee {
                one
            } else {
                let prev_p = load3::<F>(&pool.prev_p, base);
                let pdf_li =
                    area_to_solid_angle_lanes(lights.f(&prog.light_inv_area), prev_p, p, ng);
                let no_env = F::I::load_at(&pool.env_by_bsdf[..], base).eq(F::I::splat(1));
                let pmf = F::select(
                    no_env,
                    lights.f(&prog.light_pmf_no_env),
                    lights.f(&prog.light_pmf),
                );
                power_heuristic_lanes(prev_pdf, pmf * pdf_li)
            };
            let w = F::select(specular, one, w);
            for k in 0..4 {
                l[k] = F::select(shows, l[k] + beta[k] * le[k] * w, l[k]);
            }
        }
    }

    let depth = depth + F::I::splat(1);
    store_masked_int::<F>(&mut pool.depth[..], base, m, depth);
    let mut alive = m.and_not(depth.gt(F::I::splat(cfg.max_depth as i32 - 1)));

    // The BSDF at the hit.
    let mat = shapes.i(&prog.shape_mat);
    let frame = FrameL::from_normal_tangent(ns, dpdu);
    let bsdf = LaneBsdf::new(prog, alive, mat, &lambda, &d65);
    alive = alive.and_not(bsdf.none());
    let wo_l = frame.to_local(wo);

    // Next-event estimation. The light sample's set of dimensions is drawn at every vertex.
    start_set::<F>(pool, base, alive);
    let [u0, u1, u_light] = draw3::<F>(pool, base, alive, c.kind);
    let nee = alive & bsdf.non_specular();
    // [`PathState::scatter`]'s `env_by_bsdf`: of the lane BSDFs, the rough conductor, and the
    // Lambertian one beside other lights.
    let env_by_bsdf = if cfg.env_to_bsdf {
        if cfg.other_lights {
            nee & (bsdf.glossy() | bsdf.lambertian())
        } else {
            nee & bsdf.glossy()
        }
    } else {
        F::M::splat(false)
    };
    if cfg.use_nee && nee.any() {
        let wl_pdf = load_spec::<F>(&pool.wl_pdf, base);
        let ls = sample_lights(
            c,
            nee,
            env_by_bsdf,
            p,
            ng,
            u_light,
            u0,
            u1,
            &lambda,
            &wl_pdf,
            &d65,
            scratch,
        );
        let wi_l = frame.to_local(ls.wi);
        let (f, bsdf_pdf) = bsdf.f_pdf(wo_l, wi_l);
        let cos = ls.wi.dot(frame.n).abs();
        let f = spec!(k => f[k] * cos);
        let ok = nee & ls.valid & ls.pdf.gt(zero);
        let ok = ok.and_not(is_black(&ls.l)).and_not(is_black(&f));
        if ok.any() {
            let light_pdf = ls.pmf * ls.pdf;
            let w = if cfg.strategy == PathStrategy::LightOnly {
                one
            } else {
                F::select(ls.delta, one, power_heuristic_lanes(light_pdf, bsdf_pdf))
            };
            let (so, sd, st) = spawn_to(p, ng, ls.p_light);
            let contrib: Spec<F> = spec!(k => beta[k] * f[k] * ls.l[k] * (w / light_pdf));
            // Every lane table stored once, then read lane by lane.
            let w = &mut scratch.light;
            for (row, v) in w.iter_mut().zip([
                so.x, so.y, so.z, sd.x, sd.y, sd.z, st, contrib[0], contrib[1], contrib[2],
                contrib[3],
            ]) {
                v.store(row);
            }
            for i in lanes(ok.bits()) {
                let ray = crate::math::Ray {
                    o: crate::math::Vec3::new(w[0][i], w[1][i], w[2][i]),
                    d: crate::math::Vec3::new(w[3][i], w[4][i], w[5][i]),
                    t_max: w[6][i],
                };
                let c = SampledSpectrum([w[7][i], w[8][i], w[9][i], w[10][i]]);
                shadows.push((base + i) as u32, ray, c);
            }
        }
    }

    // BSDF sampling (its set: 2D point, lobe choice, Russian roulette).
    start_set::<F>(pool, base, alive);
    let [u0, u1, uc] = draw3::<F>(pool, base, alive, c.kind);
    let bs = bsdf.sample(alive, wo_l, uc, u0, u1);
    alive = alive & bs.ok;
    let wi = frame.to_world(bs.wi);
    let cos = wi.dot(frame.n).abs();
    for (b, &f) in beta.iter_mut().zip(&bs.f) {
        *b = F::select(alive, *b * (f * (cos / bs.pdf)), *b);
    }
    alive = alive & is_finite(&beta);
    let specular_i = F::I::select(bs.specular, F::I::splat(1), F::I::splat(0));
    let eta_scale = F::load_at(&pool.eta_scale[..], base);
    let eta_scale = F::select(bs.transmission, eta_scale * (bs.eta * bs.eta), eta_scale);
    store_masked(&mut pool.eta_scale[..], base, alive, eta_scale);
    store_masked(&mut pool.prev_pdf[..], base, alive, bs.pdf);
    let env_i = F::I::select(env_by_bsdf, F::I::splat(1), F::I::splat(0));
    store_masked_int::<F>(&mut pool.env_by_bsdf[..], base, alive, env_i);
    store_masked_int::<F>(&mut pool.specular[..], base, alive, specular_i);
    store3_masked(&mut pool.prev_p, base, alive, p);
    store3_masked(&mut pool.prev_n, base, alive, ng);
    store3_masked(&mut pool.o, base, alive, spawn_origin(p, ng, wi));
    store3_masked(&mut pool.d, base, alive, wi);
    store_masked(&mut pool.t_max[..], base, alive, F::splat(f32::INFINITY));

    // Russian roulette on the throughput, corrected for radiance compression at refraction.
    let roulette = alive & depth.gt(F::I::splat(cfg.rr_depth as i32 - 1));
    if roulette.any() {
        let max = F::splat(f32::NEG_INFINITY)
            .max(beta[0])
            .max(beta[1])
            .max(beta[2])
            .max(beta[3]);
        let q = (max * eta_scale).min(F::splat(0.95));
        // `!(q > 0) || u >= q`: no number is drawn when q is not positive.
        let u = draw::<F>(pool, base, roulette & q.gt(zero), c.kind);
        let out = roulette & (!q.gt(zero) | u.ge(q));
        alive = alive.and_not(out);
        let keep = roulette.and_not(out);
        for b in &mut beta {
            *b = F::select(keep, *b / q, *b);
        }
    }
    alive = alive.and_not(is_black(&beta));

    store_spec_masked(&mut pool.beta, base, m, beta);
    store_spec_masked(&mut pool.l, base, m, l);
    let alive_i = F::I::select(alive, F::I::splat(1), F::I::splat(0));
    store_masked_int::<F>(&mut pool.alive[..], base, m, alive_i);
}
