//! Closed form of a smooth coat over a non-scattering absorbing slab over a Lambertian base —
//! the zero-variance fast path of [`super::LayeredBxdf`] and the oracle of its random walk.
//!
//! Derivation (research/layered.md §3.1; the τ = 0 case is the `nonlinear` plastic of
//! Weidlich & Wilkie 2007 / Kelemen & Szirmay-Kalos 2001). The Lambertian base turns every
//! direction into a cosine distribution, so light inside the coat forms a geometric series:
//! with η the coat's relative index, F(μ) the coat's reflectance seen from outside, F_int(μ′)
//! from inside (1 beyond the critical angle), μ′(μ) = √(1 − (1 − μ²)/η²) the refracted cosine,
//! ρ the base albedo and τ the slab's optical depth,
//!
//! - escape fraction  E   = ∫₀¹ 2μ′ e^{−τ/μ′} (1 − F_int(μ′)) dμ′,
//! - return fraction  R_r = ∫₀¹ 2μ′ e^{−2τ/μ′} F_int(μ′) dμ′,
//! - diffuse part     f   = (1 − F(μo))(1 − F(μi)) e^{−τ/μ′o} e^{−τ/μ′i} ρ / (π η² (1 − ρ R_r)),
//! - albedo           R(μ) = F(μ) + (1 − F(μ)) e^{−τ/μ′} ρ E / (1 − ρ R_r),
//!
//! plus a delta reflection of weight F(μ). (Flux leaving the base is cosine-distributed inside;
//! étendue η² μ′ dω′ = μ dω maps it outside, and 1 − F_int(μ′) = 1 − F(μ) for a lossless coat.)
//! The same formulas hold per wavelength for a thin-film coat (research/layered.md §3.2) with F
//! the film stack's Airy reflectance ([`crate::optics::thinfilm::film_rt`]).
//! f is symmetric, so radiance and importance modes agree.
//!
//! Sampling (exact pdf, §3.3 with the λ-averaged coat): the delta lobe with probability
//! P = F̄(μo)/R̄(μo), its share of the directional albedo (means over the path's wavelengths,
//! weight F_λ/P), so that over a dark base the visible reflection gets the samples (choosing
//! it with F̄ alone gave it ~4 % of them, and a constant sky seen in it a relative variance of
//! ~1/F̄ per sample); otherwise a direction with density
//! p(ωi) = (1 − P) T̄(μi) μi / (π K), K = ∫₀¹ 2μ T̄(μ) dμ, T̄ = 1 − F̄, drawn by cosine
//! sampling and accepting with probability T̄(μi) (acceptance ≈ 0.9 for η = 1.5).
//!
//! A rough coat (`rough_coat` = `plastic`, [`CoatedDiffuse::with_rough`]) keeps the diffuse
//! part and its sampling and replaces the delta lobe, chosen with the same probability P, by
//! the microfacet reflection F(wo·wm) D G / (4 μo μi), sampled by visible normals; the pdf is
//! the mixture P · D_wo(wm) / (4 wo·wm) + (1 − P) p(ωi). This is the plastic approximation of
//! Weidlich & Wilkie 2007 (Mitsuba's `roughplastic`), not exact (see [`super`]).
//!
//! The coat's reflectance is in `coat.rs`, the integrals' quadratures and table in
//! `integrals.rs`.
//! Known limits: coat factors `specular_reflectance`/`specular_transmittance` must be 1 (other
//! stacks use the random walk). A plain coat's quadrature (48 nodes) is memoised per thread for
//! the last 8 (coat, τ); a film coat's integrals change with the path's wavelengths and come
//! from a per-thread table or, for a dispersive film or a coloured slab, a smaller 4-lane
//! quadrature per shading point.

pub use super::coat::CoatOptics;
use super::integrals::{critical_cosines, film_integrals, kinked_nodes, refracted_cos};
use crate::bsdf::microfacet::MicrofacetDistribution;
use crate::bsdf::{BsdfSample, BxdfFlags};
use crate::math::{reflect, warp, Pcg32, Vec2, Vec3, INV_PI};
use crate::spectrum::{SampledSpectrum, N};
use std::cell::Cell;

/// The smooth coat + absorbing slab + Lambertian base, evaluated in closed form.
#[derive(Clone, Debug)]
pub struct CoatedDiffuse {
    pub coat: CoatOptics,
    /// Base albedo ρ.
    pub rho: SampledSpectrum,
    /// Optical depth τ of the slab.
    pub tau: SampledSpectrum,
    /// Escape fraction E per wavelength.
    pub escape: SampledSpectrum,
    /// Return fraction R_r per wavelength.
    pub ret: SampledSpectrum,
    /// Sampling normalisation K = ∫ 2μ T̄(μ) dμ.
    pub k_norm: f32,
    /// A rough coat's microfacets (`None`: smooth). See [`CoatedDiffuse::with_rough`].
    pub rough: Option<MicrofacetDistribution>,
    /// A film coat's reflectance at the first cosine asked (see [`CoatedDiffuse::outside`]).
    memo: FirstAnswer,
}

/// A rough coat's microfacet normal for a pair of directions and the coat's reflectance at it
/// (`None` for a smooth coat).
type Facet = Option<(Vec3, SampledSpectrum)>;

/// One remembered (cosine, reflectance) pair, in cells. Its cosine's bits are all ones while
/// empty, a NaN no caller asks about.
#[derive(Clone, Debug)]
struct FirstAnswer {
    mu: Cell<u32>,
    r: Cell<SampledSpectrum>,
}

impl CoatedDiffuse {
    /// Precomputes the internal-reflection integrals for this coat, base and slab. The
    /// integrals do not depend on ρ; the last few (coat, τ) of each thread are memoised, so a
    /// material with constant parameters pays the quadrature once rather than per shading point.
    pub fn new(coat: CoatOptics, rho: SampledSpectrum, tau: SampledSpectrum) -> CoatedDiffuse {
        type Entry = Option<(
            CoatOptics,
            SampledSpectrum,
            SampledSpectrum,
            SampledSpectrum,
            f32,
        )>;
        thread_local! {
            static MEMO: std::cell::RefCell<([Entry; 8], usize)> =
                const { std::cell::RefCell::new(([None; 8], 0)) };
        }
        let (escape, ret, k_norm) = if let CoatOptics::Film { .. } = coat {
            film_integrals(coat, tau)
        } else {
            let hit = MEMO.with(|m| {
                m.borrow()
                    .0
                    .iter()
                    .flatten()
                    .find(|e| e.0 == coat && e.1 == tau)
                    .copied()
            });
            match hit {
                Some((_, _, e, r, k)) => (e, r, k),
                None => {
                    let v = Self::integrals(coat, tau);
                    MEMO.with(|m| {
                        let mut m = m.borrow_mut();
                        let slot = m.1;
                        m.0[slot] = Some((coat, tau, v.0, v.1, v.2));
                        m.1 = (slot + 1) % 8;
                    });
                    v
                }
            }
        };
        CoatedDiffuse {
            coat,
            rho,
            tau,
            escape,
            ret,
            k_norm,
            rough: None,
            memo: FirstAnswer {
                mu: Cell::new(u32::MAX),
                r: Cell::new(SampledSpectrum::ZERO),
            },
        }
    }

    /// The coat's reflectance for light from outside at cosine `mu`. A film coat's answer
    /// (four Airy sums) at the first cosine this instance is asked is remembered: every call
    /// at a vertex — `f` for the light sample, `sample_f`, `pdf` for MIS — asks μo first, and
    /// `sample_f` passes its other answers on to the value and density it computes
    /// (`f_with`, `pdf_with`). One slot, so the BSDF (inline in [`crate::bsdf::Bxdf`], copied
    /// at every vertex) stays as small as it was; a thread-local memo keyed by coat,
    /// wavelengths and cosine cost 7 % of a render of the thin-film benchmark sphere.
    #[inline]
    fn outside(&self, mu: f32) -> SampledSpectrum {
        if let CoatOptics::Dielectric { .. } = self.coat {
            return self.coat.outside(mu);
        }
        let (bits, m) = (mu.to_bits(), &self.memo);
        if m.mu.get() == bits {
            return m.r.get();
        }
        let r = self.coat.outside(mu);
        if m.mu.get() == u32::MAX {
            m.mu.set(bits);
            m.r.set(r);
        }
        r
    }

    /// The same stack under a rough coat, approximated as Mitsuba's `roughplastic` is
    /// (Weidlich & Wilkie 2007): the delta reflection becomes the microfacet reflection
    /// F(wo·wm) D G / (4 μo μi), F the coat's (film's) reflectance at the microfacet, and
    /// the diffuse part keeps the smooth coat's transmittances. Exact as α → 0; for larger α it
    /// ignores the light the rough interface scatters into and out of the base at other
    /// angles (and the lobe's own shadowing loss), see the module doc of
    /// [`super`] for the measured difference from the random walk.
    pub fn with_rough(mut self, d: MicrofacetDistribution) -> CoatedDiffuse {
        self.rough = Some(d);
        self
    }

    /// E, R_r per wavelength and the sampling normalisation K, by quadrature.
    fn integrals(
        coat: CoatOptics,
        tau: SampledSpectrum,
    ) -> (SampledSpectrum, SampledSpectrum, f32) {
        let eta = coat.eta() as f64;
        let (mu_c_in, mu_c_out) = critical_cosines(eta);
        let mut escape = [0.0f64; N];
        let mut ret = [0.0f64; N];
        for (mu, w) in kinked_nodes(mu_c_in) {
            // F_int once per node for all wavelengths.
            let f_int = coat.inside(mu as f32);
            for i in 0..N {
                let t = tau[i] as f64;
                let (e1, e2) = if mu > 0.0 {
                    ((-t / mu).exp(), (-2.0 * t / mu).exp())
                } else {
                    (0.0, 0.0)
                };
                let fi = (f_int[i] as f64).clamp(0.0, 1.0);
                escape[i] += w * 2.0 * mu * e1 * (1.0 - fi);
                ret[i] += w * 2.0 * mu * e2 * fi;
            }
        }
        let k_norm = kinked_nodes(mu_c_out)
            .map(|(mu, w)| w * 2.0 * mu * (1.0 - coat.outside(mu as f32).average() as f64))
            .sum::<f64>() as f32;
        (
            SampledSpectrum(escape.map(|v| v as f32)),
            SampledSpectrum(ret.map(|v| v as f32)),
            k_norm,
        )
    }

    /// Lobes: a delta reflection off the coat and the diffuse part.
    pub(crate) fn flags(&self) -> BxdfFlags {
        let coat = match self.rough {
            None => BxdfFlags::SPECULAR_REFLECTION,
            Some(_) => BxdfFlags::GLOSSY_REFLECTION,
        };
        coat | BxdfFlags::DIFFUSE_REFLECTION
    }

    /// Slab transmittance e^{−τ/μ′} for an outside cosine `mu`.
    fn slab(&self, mu: f32) -> SampledSpectrum {
        let mt = refracted_cos(mu, self.coat.eta());
        if mt <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        // No slab (τ = 0, as when `multilayered` is given no medium): e^0 without four `expf`
        // calls (3 % of a render of the thin-film benchmark sphere).
        if self.tau == SampledSpectrum::ZERO {
            return SampledSpectrum::ONE;
        }
        (-self.tau / mt).exp()
    }

    /// The diffuse part's constant ρ / (π η² (1 − ρ R_r)).
    fn diffuse_scale(&self) -> SampledSpectrum {
        let eta = self.coat.eta();
        self.rho * INV_PI / ((SampledSpectrum::ONE - self.rho * self.ret) * (eta * eta))
    }

    /// Directional albedo R(μ) including the delta reflection (of the smooth coat; a rough
    /// coat's reflection has the same albedo only in the limit α → 0).
    pub fn albedo(&self, mu: f32) -> SampledSpectrum {
        let f = self.outside(mu);
        f + self.diffuse_albedo(f, mu)
    }

    /// The diffuse part's share of the albedo at μ, given the coat's reflectance `f` there.
    fn diffuse_albedo(&self, f: SampledSpectrum, mu: f32) -> SampledSpectrum {
        (SampledSpectrum::ONE - f) * self.slab(mu) * self.rho * self.escape
            / (SampledSpectrum::ONE - self.rho * self.ret)
    }

    /// The diffuse part of the BSDF (no cosine).
    pub fn f(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let f_o = self.outside(wo.z);
        let (f_i, facet) = self.answers(wo, wi);
        self.f_with(wo, wi, f_o, f_i, facet)
    }

    /// The coat's reflectance at μi and, for a rough coat, the microfacet normal of (wo, wi)
    /// with the coat's reflectance there: for a film coat, both in one pass of eight lanes
    /// ([`CoatOptics::outside2`]), which took 15 % of a render of the thin-film benchmark
    /// sphere as two passes of four.
    fn answers(&self, wo: Vec3, wi: Vec3) -> (SampledSpectrum, Facet) {
        match self.microfacet(wo, wi) {
            Some((wm, _)) => {
                let (f_i, f_m) = self.coat.outside2(wi.z, wo.dot(wm));
                (f_i, Some((wm, f_m)))
            }
            None => (self.outside(wi.z), None),
        }
    }

    /// [`CoatedDiffuse::f`] for directions above, given the coat's reflectance at μo and μi
    /// and the microfacet's answer ([`CoatedDiffuse::answers`]).
    fn f_with(
        &self,
        wo: Vec3,
        wi: Vec3,
        f_o: SampledSpectrum,
        f_i: SampledSpectrum,
        facet: Facet,
    ) -> SampledSpectrum {
        let t_o = SampledSpectrum::ONE - f_o;
        let t_i = SampledSpectrum::ONE - f_i;
        let diffuse = t_o * t_i * self.slab(wo.z) * self.slab(wi.z) * self.diffuse_scale();
        match (facet, &self.rough) {
            (Some((wm, f_m)), Some(d)) => {
                let spec = d.d(wm) * d.g(wo, wi) / (4.0 * wo.z * wi.z);
                diffuse + f_m * spec
            }
            _ => diffuse,
        }
    }

    /// A rough coat's microfacet normal for the reflection pair (wo, wi), both above.
    fn microfacet(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, &MicrofacetDistribution)> {
        let d = self.rough.as_ref()?;
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return None;
        }
        Some((wm.normalize(), d))
    }

    /// The probability of the delta lobe at μo: F̄/R̄ (module doc), F̄ itself where the
    /// albedo is not positive.
    fn spec_choice(&self, f_o: SampledSpectrum, mu: f32) -> f32 {
        let f = f_o.average();
        let r = f + self.diffuse_albedo(f_o, mu).average();
        let p = if r > 0.0 { f / r } else { f };
        if p.is_finite() {
            p.clamp(0.0, 1.0)
        } else {
            f
        }
    }

    /// Exact density of the non-delta samples.
    pub(crate) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        self.pdf_with(wo, wi, self.outside(wo.z), self.outside(wi.z))
    }

    /// [`CoatedDiffuse::pdf`] for directions above, given the coat's reflectance at μo and μi.
    fn pdf_with(&self, wo: Vec3, wi: Vec3, f_o: SampledSpectrum, f_i: SampledSpectrum) -> f32 {
        if self.k_norm <= 0.0 {
            return 0.0;
        }
        let p_spec = self.spec_choice(f_o, wo.z);
        let t_bar = 1.0 - f_i.average();
        let diffuse = (1.0 - p_spec) * t_bar * wi.z * INV_PI / self.k_norm;
        match self.microfacet(wo, wi) {
            Some((wm, d)) => diffuse + p_spec * d.pdf(wo, wm) / (4.0 * wo.dot(wm)),
            None => diffuse,
        }
    }

    /// Samples the delta lobe or the diffuse part (see the module doc).
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, rng: &mut Pcg32) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let f_o = self.outside(wo.z);
        let p_spec = self.spec_choice(f_o, wo.z);
        if let (true, Some(d)) = (uc < p_spec, &self.rough) {
            let wi = reflect(wo, d.sample_wm(wo, u));
            if wi.z <= 0.0 {
                return None;
            }
            let (f_i, facet) = self.answers(wo, wi);
            let pdf = self.pdf_with(wo, wi, f_o, f_i);
            if pdf.is_nan() || pdf <= 0.0 {
                return None;
            }
            let f = self.f_with(wo, wi, f_o, f_i, facet);
            return Some(BsdfSample::new(f, wi, pdf, BxdfFlags::GLOSSY_REFLECTION));
        }
        if uc < p_spec {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample::new(
                f_o / (p_spec * wi.z),
                wi,
                1.0,
                BxdfFlags::SPECULAR_REFLECTION,
            ));
        }
        let mut uu = u;
        for _ in 0..64 {
            let wi = warp::square_to_cosine_hemisphere(uu);
            // The microfacet's answer comes with μi's (one pass), used if the sample is
            // accepted (nine times in ten).
            let (f_i, facet) = self.answers(wo, wi);
            let t_bar = 1.0 - f_i.average();
            if wi.z > 0.0 && rng.next_f32() < t_bar {
                let pdf = self.pdf_with(wo, wi, f_o, f_i);
                if pdf.is_nan() || pdf <= 0.0 {
                    return None;
                }
                let f = self.f_with(wo, wi, f_o, f_i, facet);
                return Some(BsdfSample::new(f, wi, pdf, BxdfFlags::DIFFUSE_REFLECTION));
            }
            uu = rng.next_vec2();
        }
        None
    }
}
