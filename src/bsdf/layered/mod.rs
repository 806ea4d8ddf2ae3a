//! `multilayered`: a stack of N interfaces (any ophis BSDF) with N − 1 homogeneous media
//! between them, simulated by position-free Monte Carlo (Guo, Hašan, Zhao 2018, "Position-Free
//! Monte Carlo Simulation for Arbitrary Layered BSDFs", TOG 37(6)); see [`walk`]. A smooth
//! dielectric coat over a non-scattering medium over a Lambertian base is evaluated in closed
//! form instead (see [`closed_form`]) unless `closed_form` is false.
//!
//! | XML name        | type        | default | meaning |
//! |-----------------|-------------|---------|---------|
//! | `nb_layers`     | integer     | number of `surface_i` | N, number of interfaces (2–4) |
//! | `surface_0 … surface_{N−1}` | nested bsdf | — | interfaces, top first |
//! | `sigma_t_i`     | spectrum    | 0       | extinction of medium i (between surface i and i+1) = its optical depth (unit thickness) |
//! | `albedo_i`      | spectrum    | 0       | single-scattering albedo of medium i |
//! | `phase_i`       | float, or nested `phase` (`hg` with `g`, `isotropic`) | 0 | Henyey–Greenstein g of medium i |
//! | `closed_form`   | boolean     | true    | use the closed form when the stack allows it |
//! | `max_depth`     | integer     | −1      | safety bound on walk vertices (−1: 256); Russian roulette ends walks |
//! | `pdf`, `diffuse_pdf`, `stoch_pdf_depth`, `pdf_repetitive`, `bidir`, `mis` | — | — | accepted for the seed's scenes and ignored: ophis's `pdf` is the mixture below |
//!
//! Seed names (Mitsuba 0.6, upgraded on load): `nbLayers`, `sigmaT_i`, `maxDepth`,
//! `diffusePdf`. The seed's media were Mitsuba `homogeneous` objects; here they are per-layer
//! parameters.
//!
//! - `sample_f`: exact weight from the analog walk; `pdf_is_proportional` is set (the MIS
//!   density comes from `pdf`), except for all-delta paths (the coat's specular reflection),
//!   which are returned as delta samples.
//! - `f`: an unbiased stochastic estimate; `pdf`: for reflection, ½ entrance-interface pdf +
//!   ½ cosine (only the cosine when the entrance is smooth); for a stack that transmits, half
//!   of the mass goes to a cosine lobe below. Exact for the closed form.
//! - Known limits: at most 4 interfaces; interfaces are horizontal (no per-layer normal maps);
//!   every shading point builds the stack in one heap allocation (the `Bxdf::Layered` box).

pub mod closed_form;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_walk;
pub mod walk;

use super::{BsdfSample, Bxdf, BxdfFlags, TransportMode};
use crate::math::{warp, Pcg32, Vec2, Vec3, INV_PI};
use closed_form::{CoatOptics, CoatedDiffuse};
pub use walk::{Medium, Stack, DEFAULT_MAX_DEPTH, MAX_INTERFACES};

use crate::spectrum::SampledSpectrum;

/// A layered BSDF: the closed form or the random walk.
// One allocation per shading point either way: `Bxdf::Layered` boxes the whole enum.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum LayeredBxdf {
    Closed(CoatedDiffuse),
    Walk(Stack),
}

/// The coat optics of an interface the closed form can handle (a smooth dielectric with unit
/// factors; thin-film coats plug in here).
pub fn coat_optics(b: &Bxdf) -> Option<CoatOptics> {
    match b {
        Bxdf::Dielectric(d) if d.r_s == SampledSpectrum::ONE && d.t_s == SampledSpectrum::ONE => {
            Some(CoatOptics::Dielectric { eta: d.eta })
        }
        _ => None,
    }
}

impl LayeredBxdf {
    /// The stack, in closed form when `allow_closed` and the stack is a smooth coat over a
    /// non-scattering medium over a Lambertian base; `None` for a wrong number of layers.
    pub fn new(
        interfaces: impl IntoIterator<Item = Bxdf>,
        media: &[Medium],
        max_depth: u32,
        allow_closed: bool,
    ) -> Option<LayeredBxdf> {
        let (ifs, n) = walk::inline_interfaces(interfaces)?;
        if allow_closed && n == 2 && media.len() == 1 && !media[0].scatters() {
            if let (Some(coat), Bxdf::Diffuse(base)) = (coat_optics(&ifs[0]), &ifs[1]) {
                return Some(LayeredBxdf::Closed(CoatedDiffuse::new(
                    coat,
                    base.r,
                    media[0].sigma_t,
                )));
            }
        }
        Stack::from_parts(ifs, n, media, max_depth).map(LayeredBxdf::Walk)
    }

    /// Lobe flags.
    pub fn flags(&self) -> BxdfFlags {
        match self {
            LayeredBxdf::Closed(c) => c.flags(),
            LayeredBxdf::Walk(s) => {
                let ifs = s.interfaces();
                let top = ifs[0].flags();
                let mut f = BxdfFlags::REFLECTION;
                if top.is_specular() {
                    f = f | BxdfFlags::SPECULAR_REFLECTION;
                }
                let glossy = ifs.iter().any(|b| b.flags().is_non_specular())
                    || s.media().iter().any(|m| m.scatters());
                if glossy {
                    f = f | BxdfFlags::GLOSSY_REFLECTION;
                }
                if self.transmits() {
                    f = f | BxdfFlags::TRANSMISSION | BxdfFlags(f.0 & (8 | 16));
                }
                f
            }
        }
    }

    /// Whether light can cross the whole stack.
    fn transmits(&self) -> bool {
        match self {
            LayeredBxdf::Closed(_) => false,
            LayeredBxdf::Walk(s) => s
                .interfaces()
                .iter()
                .all(|b| b.flags().intersects(BxdfFlags::TRANSMISSION)),
        }
    }

    /// BSDF value (a stochastic estimate for the walk).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode, rng: &mut Pcg32) -> SampledSpectrum {
        match self {
            LayeredBxdf::Closed(c) => c.f(wo, wi, mode, rng),
            LayeredBxdf::Walk(s) => s.eval(wo, wi, mode, rng),
        }
    }

    /// Sampling density (exact for the closed form, an approximation for MIS otherwise).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode, rng: &mut Pcg32) -> f32 {
        match self {
            LayeredBxdf::Closed(c) => c.pdf(wo, wi, mode, rng),
            LayeredBxdf::Walk(s) => {
                if wo.z == 0.0 || wi.z == 0.0 {
                    return 0.0;
                }
                let t = if self.transmits() { 0.5 } else { 0.0 };
                let cos = wi.z.abs() * INV_PI;
                if (wo.z > 0.0) != (wi.z > 0.0) {
                    return t * cos;
                }
                let ent = if wo.z > 0.0 {
                    0
                } else {
                    s.interfaces().len() - 1
                };
                let b = &s.interfaces()[ent];
                let p = if b.flags().is_non_specular() {
                    0.5 * b.pdf(wo, wi, mode, rng) + 0.5 * cos
                } else {
                    cos
                };
                (1.0 - t) * p
            }
        }
    }

    /// Samples the walk (or the closed form).
    pub fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        let s = match self {
            LayeredBxdf::Closed(c) => return c.sample_f(wo, uc, u, mode, rng),
            LayeredBxdf::Walk(s) => s,
        };
        if wo.z == 0.0 {
            return None;
        }
        let (wi, beta, all_delta, eta) = s.sample_walk(wo, uc, u, mode, rng)?;
        let refl = (wi.z > 0.0) == (wo.z > 0.0);
        let cos = wi.z.abs();
        if all_delta {
            let flags = if refl {
                BxdfFlags::SPECULAR_REFLECTION
            } else {
                BxdfFlags::SPECULAR_TRANSMISSION
            };
            return Some(BsdfSample {
                eta,
                ..BsdfSample::new(beta / cos, wi, 1.0, flags)
            });
        }
        let pdf = self
            .pdf(wo, wi, mode, rng)
            .max(1e-6 * warp::square_to_uniform_sphere_pdf());
        let flags = if refl {
            BxdfFlags::GLOSSY_REFLECTION
        } else {
            BxdfFlags::GLOSSY_TRANSMISSION
        };
        Some(BsdfSample {
            eta,
            pdf_is_proportional: true,
            ..BsdfSample::new(beta * (pdf / cos), wi, pdf, flags)
        })
    }
}
