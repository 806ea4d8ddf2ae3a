//! `multilayered`'s `rough_coat` = `mixture`: the random walk ([`super::walk`]) with its
//! directions drawn from a density of its own instead of by the walk, where the walk reweights
//! its first choice (a rough coat over a Lambertian base through a clear layer, light from
//! above; [`super::walk::Stack::entrance_weight`]).
//!
//! `sample_f` draws wi from a mixture density of its own, the coat's microfacet reflection with
//! probability q (the walk's first-choice probability at the macro-normal with the bare
//! interface's Fresnel term, kept within [0.05, 0.95]) and a cosine lobe otherwise, and weighs
//! it by the walk's estimate `f(wo, wi)`: unbiased (the density is exact and `f`'s estimate
//! is), and the coat's reflection, most of what such a stack returns, then comes from its exact
//! value instead of a sampled branch. `pdf` is that density, exactly, so MIS weights are exact
//! too, and such a stack counts among the BSDFs whose samples carry a smooth sky
//! ([`crate::bsdf::Bxdf::samples_smooth_env`]). An `f` costs more than the walk's own sample (it evaluates
//! every interface it meets and connects), so it is an option: on the thin-film benchmark
//! sphere (`bench/noise.py bench/thinfilm-sphere.xml`, 96², 64 spp, Sobol, 2 pairs, 2026-12-06)
//! 1.27× faster to equal noise over its base of albedo 0.02, 2.18× over 0.1, 1.32× over 0.5
//! (noise per sample 0.0061 → 0.0040, 0.046 → 0.019, 0.19 → 0.13); on the flagship's skins (a
//! film over melanin over a grey base, under a sun and sky, with the scales' bump map; the
//! built-in scene with `rough_coat` set on its three `multilayered`, 320×180, 32 spp, 3 pairs,
//! CPU time) 0.99× (0.97–1.00: noise −7 %, CPU per sample +9 %), so the walk's own sampling
//! stays the default.

use super::walk::Stack;
use crate::bsdf::fresnel::fresnel_dielectric;
use crate::bsdf::rough::weighted_choice;
use crate::bsdf::MicrofacetCoat;
use crate::math::{warp, Vec2, Vec3, INV_PI};

/// The least probability of either lobe.
const MIN: f32 = 0.05;

/// The mixture density of a stack seen from one direction: the coat's reflection lobe with
/// probability `q`, a cosine lobe otherwise.
pub(super) struct Mixture<'a> {
    q: f32,
    coat: MicrofacetCoat<'a>,
}

impl<'a> Mixture<'a> {
    /// Whether `s` (crossed by light from side to side when `transmits`) samples from its
    /// mixture for light from above.
    pub(super) fn applies(s: &Stack, transmits: bool) -> bool {
        s.mixture()
            && s.entrance_weight() != 1.0
            && !transmits
            && s.interfaces()[0].microfacet_coat().is_some()
    }

    /// The density `s` samples from at `wo`, or `None` where it samples by its walk.
    pub(super) fn of(s: &'a Stack, wo: Vec3, transmits: bool) -> Option<Mixture<'a>> {
        if !(wo.z > 0.0) || !Self::applies(s, transmits) {
            return None;
        }
        let top = &s.interfaces()[0];
        // The bare interface's Fresnel reflectance: the film's own (its Airy sum at four
        // wavelengths) only moves the choice and cost 8 % of the benchmark sphere's time.
        let p = fresnel_dielectric(wo.z, top.rough_eta()?);
        Some(Mixture {
            q: weighted_choice(p, s.entrance_weight()).clamp(MIN, 1.0 - MIN),
            coat: top.microfacet_coat()?,
        })
    }

    /// The density of `wi` (0 below the surface).
    pub(super) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if !(wi.z > 0.0) {
            return 0.0;
        }
        self.q * self.coat.reflection_pdf(wo, wi) + (1.0 - self.q) * wi.z * INV_PI
    }

    /// A direction drawn with `uc` choosing the lobe and `u` the direction in it, and its
    /// density; `None` where the reflection leaves below the surface.
    pub(super) fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<(Vec3, f32)> {
        let wi = if uc < self.q {
            self.coat.sample_reflection(wo, u)?
        } else {
            warp::square_to_cosine_hemisphere(u)
        };
        let pdf = self.pdf(wo, wi);
        (wi.z > 0.0 && pdf > 0.0).then_some((wi, pdf))
    }
}
