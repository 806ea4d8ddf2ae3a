//! The BSDFs of the lanes: `diffuse`, smooth `dielectric`, smooth `conductor` and GGX
//! `roughconductor`, each lane holding its own material's parameters. These are
//! [`crate::bsdf::diffuse`], [`crate::bsdf::smooth`] and [`crate::bsdf::rough`] (with the
//! [`crate::bsdf::Bsdf`] wrapper's checks) rewritten over lanes, operation for operation; a
//! chunk whose lanes hold several kinds evaluates each kind present and blends.

use super::lookup::Groups;
use super::program::{
    MaterialTable, Program, SpectrumTable, MAT_CONDUCTOR, MAT_DIELECTRIC, MAT_DIFFUSE,
    MAT_ROUGH_CONDUCTOR,
};
use super::vertex::{eval_spectrum, is_black, is_finite, Spec};
use crate::bsdf::fresnel::{fresnel_conductor_lanes, fresnel_dielectric_lanes};
use crate::bsdf::microfacet::GgxL;
use crate::math::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use crate::math::INV_PI;
use crate::simd::{Float, Int, Mask, V3};

/// The BSDFs at a chunk's shading points, in their local frames.
pub(super) struct LaneBsdf<F: Float> {
    diffuse: F::M,
    dielectric: F::M,
    conductor: F::M,
    rough: F::M,
    /// Diffuse: the reflectance; the others: the specular reflectance factor.
    r: Spec<F>,
    /// Dielectric: the transmittance factor.
    t_s: Spec<F>,
    /// Dielectric: the relative index.
    eta: F,
    /// Conductors: the complex index (relative to the exterior).
    n: Spec<F>,
    k: Spec<F>,
    mirror: F::M,
    ggx: GgxL<F>,
}

/// A sampled direction ([`crate::bsdf::BsdfSample`]), in the local frame.
pub(super) struct Sampled<F: Float> {
    /// Lanes with a sample (the others return `None` in the scalar code).
    pub ok: F::M,
    pub f: Spec<F>,
    pub wi: V3<F>,
    pub pdf: F,
    pub specular: F::M,
    pub transmission: F::M,
    pub eta: F,
}

impl<F: Float> LaneBsdf<F> {
    /// The materials `mat` of the lanes of `m` at the given wavelengths.
    #[inline(always)]
    pub fn new(prog: &Program, m: F::M, mat: F::I, lambda: &Spec<F>, d65: &Spec<F>) -> Self {
        let t: &MaterialTable = &prog.mats;
        let mats = Groups::<F>::new(mat, m);
        let kind = mats.i(&t.kind);
        let is = |k: u32| m & kind.eq(F::I::splat(k as i32));
        let (diffuse, dielectric) = (is(MAT_DIFFUSE), is(MAT_DIELECTRIC));
        let (smooth_c, rough) = (is(MAT_CONDUCTOR), is(MAT_ROUGH_CONDUCTOR));
        let conductor = smooth_c | rough;
        let spectra: &SpectrumTable = &prog.spectra;
        let entry = |k: usize| mats.i(&t.spec[k]);
        let num = |k: usize| mats.f(&t.num[k]);
        let r = eval_spectrum(spectra, entry(0), m, lambda, d65);
        // `diffuse` clamps its reflectance to [0, 1].
        let mut r = r;
        if diffuse.any() {
            for x in &mut r {
                *x = F::select(diffuse, x.clamp(0.0, 1.0), *x);
            }
        }
        let zero = F::splat(0.0);
        let mut out = LaneBsdf {
            diffuse,
            dielectric,
            conductor,
            rough,
            r,
            t_s: [zero; 4],
            eta: F::splat(1.0),
            n: [zero; 4],
            k: [zero; 4],
            mirror: F::M::splat(false),
            ggx: GgxL {
                ax: F::splat(1.0),
                ay: F::splat(1.0),
            },
        };
        if dielectric.any() {
            out.t_s = eval_spectrum(spectra, entry(1), dielectric, lambda, d65);
            out.eta = num(0);
        }
        if conductor.any() {
            let ext = num(0);
            out.mirror = conductor & num(1).eq(F::splat(1.0));
            let metal = conductor.and_not(out.mirror);
            if metal.any() {
                let n = eval_spectrum(spectra, entry(1), metal, lambda, d65);
                let k = eval_spectrum(spectra, entry(2), metal, lambda, d65);
                for j in 0..4 {
                    out.n[j] = n[j] / ext;
                    out.k[j] = k[j] / ext;
                }
            }
            if rough.any() {
                out.ggx = GgxL {
                    ax: num(2),
                    ay: num(3),
                };
            }
        }
        out
    }

    /// Lanes whose BSDF has no lobe (a black `diffuse`).
    #[inline(always)]
    pub fn none(&self) -> F::M {
        self.diffuse & is_black(&self.r)
    }

    /// Lanes with a lobe that `f` and `pdf` evaluate (not only Dirac deltas).
    /// The lanes whose BSDF is glossy (the rough conductor).
    #[inline(always)]
    pub fn glossy(&self) -> F::M {
        self.rough
    }

    /// The lanes whose BSDF is Lambertian.
    #[inline(always)]
    pub fn lambertian(&self) -> F::M {
        self.diffuse
    }

    #[inline(always)]
    pub fn non_specular(&self) -> F::M {
        self.diffuse | self.rough
    }

    /// The conductors' Fresnel reflectance at `cos` ([`crate::bsdf::fresnel::ConductorFresnel`]).
    #[inline(always)]
    fn conductor_fresnel(&self, cos: F) -> Spec<F> {
        let one = F::splat(1.0);
        let mut out = [one; 4];
        for (j, o) in out.iter_mut().enumerate() {
            *o = F::select(
                self.mirror,
                one,
                fresnel_conductor_lanes(cos, self.n[j], self.k[j]),
            );
        }
        out
    }

    /// BSDF value (no cosine) and sampling density for the local pair (wo, wi), for the lanes
    /// with a non-specular lobe.
    #[inline(always)]
    pub fn f_pdf(&self, wo: V3<F>, wi: V3<F>) -> (Spec<F>, F) {
        let zero = F::splat(0.0);
        let mut f = [zero; 4];
        let mut pdf = zero;
        if self.diffuse.any() {
            // `wo.z <= 0 || wi.z <= 0` gives 0 (a NaN passes, as in the scalar code).
            let up = self.diffuse.and_not(wo.z.le(zero) | wi.z.le(zero));
            for (j, x) in f.iter_mut().enumerate() {
                *x = F::select(up, self.r[j] * F::splat(INV_PI), *x);
            }
            pdf = F::select(up, cosine_hemisphere_pdf(wi.z), pdf);
        }
        if self.rough.any() {
            let (fr, pr) = self.rough_f_pdf(wo, wi);
            for (x, y) in f.iter_mut().zip(fr) {
                *x = F::select(self.rough, y, *x);
            }
            pdf = F::select(self.rough, pr, pdf);
        }
        (f, pdf)
    }

    /// The rough conductor's value and density ([`crate::bsdf::rough::Rough::f`] and
    /// `pdf_weighted` for a reflector).
    #[inline(always)]
    fn rough_f_pdf(&self, wo: V3<F>, wi: V3<F>) -> (Spec<F>, F) {
        let zero = F::splat(0.0);
        let wm = wo + wi;
        let ok = wo.z.gt(zero) & wi.z.gt(zero) & wm.length_squared().gt(zero);
        let wm = wm.normalize();
        let d = self.ggx.d(wm);
        let g = self.ggx.g(wo, wi);
        let cos = wo.dot(wm);
        let fr = self.conductor_fresnel(cos);
        let s = d * g / (F::splat(4.0) * wo.z * wi.z);
        let mut f = [zero; 4];
        for (j, x) in f.iter_mut().enumerate() {
            *x = F::select(ok, self.r[j] * fr[j] * s, zero);
        }
        let pdf = F::select(ok, self.ggx.pdf(wo, wm) / (F::splat(4.0) * cos), zero);
        (f, pdf)
    }

    /// Samples an incident direction for the lanes of `m` (radiance transport), with the
    /// checks of [`crate::bsdf::Bsdf::sample_f`].
    #[inline(always)]
    pub fn sample(&self, m: F::M, wo: V3<F>, uc: F, u0: F, u1: F) -> Sampled<F> {
        let zero = F::splat(0.0);
        let one = F::splat(1.0);
        let mut s = Sampled {
            ok: F::M::splat(false),
            f: [zero; 4],
            wi: V3::new(zero, zero, one),
            pdf: one,
            specular: F::M::splat(false),
            transmission: F::M::splat(false),
            eta: one,
        };
        let mirror_dir = V3::new(-wo.x, -wo.y, wo.z);
        let fine = wo.z.ne(zero) & wo.z.is_finite();
        if (m & self.diffuse).any() {
            let d = m & self.diffuse;
            let wi = cosine_hemisphere(u0, u1);
            let pdf = cosine_hemisphere_pdf(wi.z);
            let ok = d.and_not(wo.z.le(zero)) & pdf.gt(zero);
            s.ok = s.ok | ok;
            s.wi = V3::select(d, wi, s.wi);
            s.pdf = F::select(d, pdf, s.pdf);
            for (x, &r) in s.f.iter_mut().zip(&self.r) {
                *x = F::select(d, r * F::splat(INV_PI), *x);
            }
        }
        if (m & self.dielectric).any() {
            let d = m & self.dielectric;
            let eta = self.eta;
            let p = fresnel_dielectric_lanes(wo.z, eta);
            let etap = F::select(wo.z.gt(zero), eta, one / eta);
            let sin2_t = (one - wo.z * wo.z).max(zero) / (etap * etap);
            let reflect = uc.lt(p) | p.ge(one) | sin2_t.ge(one);
            let tir = p.ge(one) | sin2_t.ge(one);
            // Reflection: weight R/P, exactly 1 for a Fresnel reflectance in (0, 1] (R itself
            // where P or total internal reflection gives 1).
            let wr = F::select(p.gt(zero), one, zero);
            let w_refl = F::select(tir, p, wr);
            // Refraction: weight (1 − R)/(1 − P) = 1, over η'² in radiance transport.
            let wt = F::select(p.lt(one), one, zero);
            let cos_t = (one - sin2_t).sqrt() * -one.copysign(wo.z);
            let wi_t = V3::new(-wo.x / etap, -wo.y / etap, cos_t).normalize();
            let abs_o = wo.z.abs();
            let abs_t = wi_t.z.abs();
            let e2 = etap * etap;
            for j in 0..4 {
                let fr = self.r[j] * w_refl / abs_o;
                let ft = self.t_s[j] * wt / e2 / abs_t;
                s.f[j] = F::select(d, F::select(reflect, fr, ft), s.f[j]);
            }
            s.ok = s.ok | (d & fine);
            s.wi = V3::select(d, V3::select(reflect, mirror_dir, wi_t), s.wi);
            s.pdf = F::select(d, one, s.pdf);
            s.specular = s.specular | d;
            s.transmission = s.transmission | d.and_not(reflect);
            s.eta = F::select(d.and_not(reflect), etap, s.eta);
        }
        if (m & self.conductor.and_not(self.rough)).any() {
            let d = m & self.conductor.and_not(self.rough);
            let fr = self.conductor_fresnel(wo.z);
            let abs_o = wo.z.abs();
            for ((x, &r), &fr) in s.f.iter_mut().zip(&self.r).zip(&fr) {
                *x = F::select(d, r * fr / abs_o, *x);
            }
            s.ok = s.ok | (d & fine).and_not(wo.z.lt(zero));
            s.wi = V3::select(d, mirror_dir, s.wi);
            s.pdf = F::select(d, one, s.pdf);
            s.specular = s.specular | d;
        }
        if (m & self.rough).any() {
            let d = m & self.rough;
            let wm = self.ggx.sample_wm(wo, u0, u1);
            // reflect(wo, wm) = 2 (wo·wm) wm − wo
            let wi = wm * (F::splat(2.0) * wo.dot(wm)) - wo;
            let (f, pdf) = self.rough_f_pdf(wo, wi);
            let ok = (d & fine).and_not(wo.z.lt(zero)).and_not(wi.z.le(zero));
            let ok = ok.and_not(pdf.is_nan() | pdf.le(zero));
            s.ok = s.ok | ok;
            s.wi = V3::select(d, wi, s.wi);
            s.pdf = F::select(d, pdf, s.pdf);
            for (x, y) in s.f.iter_mut().zip(f) {
                *x = F::select(d, y, *x);
            }
        }
        // The `Bsdf` wrapper: a positive density, a finite value and wi off the surface.
        s.ok = s.ok & s.pdf.gt(zero) & is_finite(&s.f) & s.wi.z.ne(zero);
        s
    }
}
