//! `multilayered`: a stack of N interfaces (any ophis BSDF) with N − 1 homogeneous media
//! between them, simulated by position-free Monte Carlo (Guo, Hašan, Zhao 2018, "Position-Free
//! Monte Carlo Simulation for Arbitrary Layered BSDFs", TOG 37(6)); see [`walk`]. A smooth
//! dielectric coat over a non-scattering medium over a Lambertian base is evaluated in closed
//! form instead (see [`closed_form`]) unless `closed_form` is false. With `rough_coat` =
//! `plastic`, a rough coat over the same base is too, approximately
//! ([`closed_form::CoatedDiffuse::with_rough`]): against the walk (`tests_rough.rs`), a film
//! coat with GGX α = 0.05 over a dark or grey base is within 0.5 % in directional albedo and
//! 1.6 % in the diffuse value; a bare coat with α = 0.3 over a grey base is 8–12 % brighter.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `nb_layers` (0.6: `nbLayers`) | integer | number of `surface_i` | — | N, the number of interfaces; between 2 and 4 |
//! | `surface_i` | bsdf | required | — | interface i (0 … N − 1), top first |
//! | `sigma_t_i` (0.6: `sigmaT_i`) | spectrum or texture | 0.0 | — | extinction of medium i (between surface i and i + 1) = its optical depth |
//! | `albedo_i` | spectrum or texture | 0.0 | — | single-scattering albedo of medium i |
//! | `phase_i` | float | 0.0 | — | Henyey–Greenstein g of medium i, or a nested `phase` (`hg`, `isotropic`); strictly between -1 and 1 |
//! | `closed_form` | boolean | true | — | use the closed form when the stack allows it |
//! | `rough_coat` | string | `walk` | — | a rough coat over a diffuse base: 'walk' simulates it (exact); 'mixture' simulates it too, but samples directions from the coat's reflection lobe and a cosine lobe and weighs them by the walk's value of the BSDF (less noise under a sky, more work per sample); 'plastic' evaluates it in closed form as `roughplastic` does (microfacet reflection, smooth-coat transmittance), without the walk's noise; one of 'walk', 'mixture', 'plastic' |
//! | `max_depth` (0.6: `maxDepth`) | integer | -1 | — | safety bound on walk vertices (−1: 256); Russian roulette ends walks |
//! | `pdf` | string | — | — |  |
//! | `diffuse_pdf` (0.6: `diffusePdf`) | float | — | — |  |
//! | `stoch_pdf_depth` | integer | — | — |  |
//! | `pdf_repetitive` | integer | — | — |  |
//! | `bidir` | boolean | — | — |  |
//! | `mis` | boolean | — | — |  |
//! | `bidir_use_analog` | boolean | — | — |  |
//! | `max_survival_prob` | float | — | — | (these eight: the thesis's PFMC settings, accepted and ignored) |
//!
//! The thesis's media were Mitsuba `homogeneous` objects; here they are per-layer parameters.
//!
//! - `sample_f`: exact weight from the analog walk; `pdf_is_proportional` is set (the MIS
//!   density comes from `pdf`), except for all-delta paths (the coat's specular reflection),
//!   which are returned as delta samples.
//! - `f`: an unbiased stochastic estimate; `pdf`: for reflection, ½ entrance-interface pdf +
//!   ½ cosine (only the cosine when the entrance is smooth); where the walk reweights its
//!   first choice (a rough coat over a dark base, `Stack::entrance_weight`), the coat's pdf
//!   with that choice plus the rest of the mass as a cosine lobe; for a stack that transmits,
//!   half of the mass goes to a cosine lobe below. Exact for the closed form. Any positive
//!   density gives unbiased MIS; a closer one gives better weights.
//! - `rough_coat` = `mixture`: the walk, its directions drawn from a mixture density of the
//!   coat's reflection lobe and a cosine lobe and weighed by its `f`; `pdf` is that density
//!   (`mixture.rs`).
//! - Random numbers: the walk is the one stochastic BSDF, so it is the one that draws random
//!   numbers. It draws them from a generator seeded by a hash of the seed it was built with
//!   (one per path vertex, from the integrator) and of the directions it is asked about, so `f`
//!   and `pdf` are deterministic functions of (wo, wi) and every call is reproducible.
//! - Known limits: at most 4 interfaces; interfaces are horizontal (no per-layer normal maps);
//!   a walk's stack is built in one heap allocation per shading point (the closed form in
//!   none).

pub mod closed_form;
mod coat;
mod entrance;
mod integrals;
mod mixture;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_entrance;
#[cfg(test)]
mod tests_mixture;
#[cfg(test)]
mod tests_rough;
#[cfg(test)]
mod tests_walk;
pub mod walk;

use super::{BsdfSample, Bxdf, BxdfFlags, TransportMode};
use crate::bsdf::filmfresnel::{FilmFresnel, FilmMode};
use crate::bsdf::microfacet::MicrofacetDistribution;
use crate::math::rng::mix64;
use crate::math::{warp, Pcg32, Vec2, Vec3, INV_PI};
use closed_form::{CoatOptics, CoatedDiffuse};
use mixture::Mixture;
pub use walk::{Medium, Stack, DEFAULT_MAX_DEPTH, MAX_INTERFACES};

use crate::bsdf::material::{LayerMedium, Material};
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Tag, Ty, Value};
use crate::spectrum::SampledSpectrum;

/// Parameters the thesis's `multilayered` takes that ophis accepts and ignores (its `pdf` is
/// ophis's own mixture; its eval is unidirectional).
const IGNORED: [&str; 8] = [
    "pdf",
    "diffuse_pdf",
    "stoch_pdf_depth",
    "pdf_repetitive",
    "bidir",
    "mis",
    "bidir_use_analog",
    "max_survival_prob",
];

declare!(PLUGIN: Material = Bsdf "multilayered" []
    "a stack of interfaces and media, by position-free Monte Carlo"
    [
            &[
                Param::new(
                    "nb_layers",
                    Ty::Integer,
                    DefaultValue::Derived("number of `surface_i`"),
                )
                .v06("nbLayers")
                .check(Check::Range(2.0, MAX_INTERFACES as f64))
                .doc("N, the number of interfaces"),
                Param::new("surface_i", Ty::Bsdf, DefaultValue::Required)
                    .doc("interface i (0 … N − 1), top first"),
                Param::coefficient("sigma_t_i", 0.0)
                .v06("sigmaT_i")
                .doc("extinction of medium i (between surface i and i + 1) = its optical depth"),
                Param::reflectance("albedo_i", 0.0)
                .doc("single-scattering albedo of medium i"),
                Param::new("phase_i", Ty::Float, DefaultValue::Float(0.0))
                    .check(Check::Open(-1.0, 1.0))
                    .doc(
                        "Henyey–Greenstein g of medium i, or a nested `phase` (`hg`, `isotropic`)",
                    ),
                Param::bool("closed_form", true)
                    .doc("use the closed form when the stack allows it"),
                Param::string("rough_coat", "walk")
                    .check(Check::OneOf(&["walk", "mixture", "plastic"]))
                    .doc(
                        "a rough coat over a diffuse base: 'walk' simulates it (exact); \
                         'mixture' simulates it too, but samples directions from the coat's \
                         reflection lobe and a cosine lobe and weighs them by the walk's \
                         value of the BSDF (less noise under a sky, more work per sample); \
                         'plastic' evaluates it in closed form as `roughplastic` does \
                         (microfacet reflection, smooth-coat transmittance), without the \
                         walk's noise",
                    ),
                Param::int("max_depth", -1)
                    .v06("maxDepth")
                    .doc("safety bound on walk vertices (−1: 256); Russian roulette ends walks"),
            ],
            &[
                Param::new("pdf", Ty::String, DefaultValue::None),
                Param::new("diffuse_pdf", Ty::Float, DefaultValue::None).v06("diffusePdf"),
                Param::new("stoch_pdf_depth", Ty::Integer, DefaultValue::None),
                Param::new("pdf_repetitive", Ty::Integer, DefaultValue::None),
                Param::new("bidir", Ty::Boolean, DefaultValue::None),
                Param::new("mis", Ty::Boolean, DefaultValue::None),
                Param::new("bidir_use_analog", Ty::Boolean, DefaultValue::None),
                Param::new("max_survival_prob", Ty::Float, DefaultValue::None)
                    .doc("(these eight: the thesis's PFMC settings, accepted and ignored)"),
            ],
        ] load);

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let node = a.node();
    let named = (0..)
        .take_while(|i| node.child(&format!("surface_{i}")).is_some())
        .count() as i64;
    let n = match a.int_opt("nb_layers")? {
        Some(n) => n,
        None if !(2..=MAX_INTERFACES as i64).contains(&named) => {
            // A 3.x scene that spells it the 0.6 way gets told why it was not read.
            let hint = if node.props.location("nbLayers").is_some() {
                "; 'nbLayers' is Mitsuba 0.6's spelling, read only in scenes of version 0.x \
                 (write 'nb_layers')"
            } else {
                ""
            };
            return Err(SceneError::at(
                &node.loc,
                format!(
                    "{} has {named} nested bsdfs named surface_0, surface_1, …; it needs \
                     between 2 and {MAX_INTERFACES}{hint}",
                    a.describe()
                ),
            ));
        }
        None => named,
    };
    if !(2..=MAX_INTERFACES as i64).contains(&n) {
        return Err(a.error(
            "nb_layers",
            format!("must be between 2 and {MAX_INTERFACES}, got {n}"),
        ));
    }
    let n = n as usize;
    let mut surfaces = Vec::with_capacity(n);
    for i in 0..n {
        let name = format!("surface_{i}");
        let child = node
            .child(&name)
            .filter(|c| c.tag == Tag::Bsdf)
            .ok_or_else(|| {
                SceneError::at(
                    &node.loc,
                    format!(
                        "{} needs a nested bsdf named '{name}' (nb_layers = {n})",
                        a.describe()
                    ),
                )
            })?;
        surfaces.push(a.bsdf(child)?);
    }
    let mut media = Vec::with_capacity(n - 1);
    for i in 0..n - 1 {
        media.push(LayerMedium {
            sigma_t: a.spectrum_texture(&format!("sigma_t_{i}"))?,
            albedo: a.spectrum_texture(&format!("albedo_{i}"))?,
            g: phase_g(a, i)?,
        });
    }
    let max_depth = a.int("max_depth")?;
    let max_depth = if max_depth <= 0 {
        DEFAULT_MAX_DEPTH
    } else {
        max_depth.min(1 << 20) as u32
    };
    let closed_form = a.bool("closed_form")?;
    let rough_coat = match a.string("rough_coat")?.as_str() {
        "plastic" => CoatModel::Plastic,
        "mixture" => CoatModel::Mixture,
        _ => CoatModel::Walk,
    };
    for name in IGNORED {
        a.ignore(name)?;
    }
    Ok(Material::Multilayered {
        surfaces,
        media,
        max_depth,
        closed_form,
        rough_coat,
    })
}

/// How a rough coat over a Lambertian base (through a non-scattering layer) is rendered
/// (`rough_coat`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoatModel {
    /// The random walk, sampled by the walk itself.
    Walk,
    /// The random walk, sampled from a mixture density (`mixture.rs`).
    Mixture,
    /// The closed-form approximation ([`CoatedDiffuse::with_rough`]).
    Plastic,
}

/// `phase_i`: a float (HG g) or a nested `phase` (`hg` with `g`, or `isotropic`).
fn phase_g(a: &mut Args, i: usize) -> Result<f32, SceneError> {
    let name = format!("phase_{i}");
    if let Some(ph) = a.child(&name)?.filter(|c| c.tag == Tag::Phase) {
        return match ph.plugin.as_str() {
            "isotropic" => Ok(0.0),
            "hg" => {
                let g = match ph.props.get("g") {
                    Some((Value::Float(_) | Value::Integer(_), _)) => {
                        ph.props.get_float("g", 0.0)?
                    }
                    Some(_) => return Err(ph.props.type_error("g", "a float")),
                    None => 0.0,
                };
                if g > -1.0 && g < 1.0 {
                    Ok(g)
                } else {
                    Err(SceneError::at(
                        ph.props.location("g").unwrap_or(&ph.loc),
                        format!(
                            "'g' of {} must be strictly between -1 and 1, got {g}",
                            ph.describe()
                        ),
                    ))
                }
            }
            other => Err(SceneError::at(
                &ph.loc,
                format!(
                    "phase '{other}' is not supported in multilayered (use 'hg' or 'isotropic')"
                ),
            )),
        };
    }
    a.float(&name)
}

/// How a layered BSDF is evaluated: the closed form or the random walk.
#[derive(Clone, Debug)]
pub enum LayeredModel {
    /// Inline: a thin-film coat makes one per shading point, without allocating.
    Closed(CoatedDiffuse),
    /// Boxed: the walk holds its interfaces inline (hundreds of bytes).
    Walk(Box<Stack>),
}

/// A layered BSDF and the seed of its random numbers.
#[derive(Clone, Debug)]
pub struct LayeredBxdf {
    pub model: LayeredModel,
    pub seed: u64,
}

/// A generator for one query, from the seed and the query's arguments.
fn query_rng(seed: u64, a: Vec3, b: Vec3, c: f32) -> Pcg32 {
    let bits = |v: Vec3| {
        ((v.x.to_bits() as u64) << 32 | v.y.to_bits() as u64) ^ mix64(v.z.to_bits() as u64)
    };
    let h = mix64(seed ^ mix64(bits(a) ^ mix64(bits(b) ^ c.to_bits() as u64)));
    Pcg32::new(h, seed)
}

/// The coat optics of an interface the closed form can handle (a smooth dielectric with unit
/// factors, or a smooth spectral film on one), with the microfacets of a rough one (the same
/// interfaces, rough) when `rough` allows them.
pub(crate) fn coat_optics(
    b: &Bxdf,
    rough: bool,
) -> Option<(CoatOptics, Option<MicrofacetDistribution>)> {
    let unit = |r: SampledSpectrum, t: SampledSpectrum| {
        r == SampledSpectrum::ONE && t == SampledSpectrum::ONE
    };
    match b {
        Bxdf::Dielectric(d) if unit(d.r_s, d.t_s) => {
            Some((CoatOptics::Dielectric { eta: d.fresnel.eta }, None))
        }
        Bxdf::ThinFilm(t) if unit(t.r_s, t.t_s) => Some((film_coat(&t.fresnel)?, None)),
        Bxdf::RoughDielectric(d) if rough && unit(d.r_s, d.t_s) => Some((
            CoatOptics::Dielectric { eta: d.fresnel.eta },
            Some(d.distrib),
        )),
        Bxdf::RoughThinFilm(t) if rough && unit(t.r_s, t.t_s) => {
            Some((film_coat(&t.fresnel)?, Some(t.distrib)))
        }
        _ => None,
    }
}

/// A film on a dielectric coat, computed exactly (the thesis mode and absorbing or dispersive
/// bases have no closed form here and take the random walk).
fn film_coat(f: &FilmFresnel) -> Option<CoatOptics> {
    let s = &f.spectral;
    if f.mode != FilmMode::Spectral
        || s.base_k.iter().any(|&k| k != 0.0)
        || s.base_n.iter().any(|&n| n != s.base_n[0])
    {
        return None;
    }
    // Indices relative to the outer medium; the vacuum wavelength shrinks with it so that the
    // film's phase 2π n1 d cos θ1 / λ is unchanged.
    let ext = f.ext;
    Some(CoatOptics::Film {
        eta: s.base_n[0] / ext,
        film_ior: s.film.map(|x| x / ext),
        thickness_nm: f.d_nm,
        lambda: s.lambda.map(|l| l / ext),
    })
}

impl LayeredBxdf {
    /// The stack, in closed form when `allow_closed` and the stack is a smooth coat over a
    /// non-scattering medium over a Lambertian base (or a rough coat, when `rough` is
    /// [`CoatModel::Plastic`], the approximation of [`CoatedDiffuse::with_rough`]); else the
    /// walk, sampled from the mixture density where `rough` is [`CoatModel::Mixture`]; `None`
    /// for a wrong number of layers.
    pub fn new(
        interfaces: impl IntoIterator<Item = Bxdf>,
        media: &[Medium],
        max_depth: u32,
        allow_closed: bool,
        rough: CoatModel,
        seed: u64,
    ) -> Option<LayeredBxdf> {
        let mut it = interfaces.into_iter();
        let (top, base) = (it.next(), it.next());
        // The closed form is looked for before the interfaces are gathered for a walk: it
        // needs only the first two, and a render with a film coat makes one per shading point.
        let mut rest = it.peekable();
        if rest.peek().is_none() {
            if let (Some(t), Some(b)) = (&top, &base) {
                if let Some(l) = Self::closed(t, b, media, allow_closed, rough, seed) {
                    return Some(l);
                }
            }
        }
        Stack::boxed(top.into_iter().chain(base).chain(rest), media, max_depth).map(|mut s| {
            s.set_mixture(rough == CoatModel::Mixture);
            LayeredBxdf {
                model: LayeredModel::Walk(s),
                seed,
            }
        })
    }

    /// The two-layer stack `top` over `base` in closed form, where [`LayeredBxdf::new`] would
    /// make it one; `None` where it would take the random walk.
    pub fn closed(
        top: &Bxdf,
        base: &Bxdf,
        media: &[Medium],
        allow_closed: bool,
        rough: CoatModel,
        seed: u64,
    ) -> Option<LayeredBxdf> {
        if !allow_closed || media.len() != 1 || media[0].scatters() {
            return None;
        }
        let Bxdf::Diffuse(base) = base else {
            return None;
        };
        let (coat, rough) = coat_optics(top, rough == CoatModel::Plastic)?;
        let c = CoatedDiffuse::new(coat, base.r, media[0].sigma_t);
        Some(LayeredBxdf {
            model: LayeredModel::Closed(match rough {
                Some(d) => c.with_rough(d),
                None => c,
            }),
            seed,
        })
    }

    /// Lobe flags.
    pub(crate) fn flags(&self) -> BxdfFlags {
        match &self.model {
            LayeredModel::Closed(c) => c.flags(),
            LayeredModel::Walk(s) => {
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
                    // Whatever kinds of lobe reflect also transmit.
                    f = f | BxdfFlags::TRANSMISSION | f.and(BxdfFlags::KINDS);
                }
                f
            }
        }
    }

    /// Whether the walk's samples are drawn from a mixture density (`mixture.rs`): then, like
    /// the closed forms', they carry a smooth environment well ([`Bxdf::samples_smooth_env`]).
    pub(crate) fn mixture_sampled(&self) -> bool {
        match &self.model {
            LayeredModel::Closed(_) => false,
            LayeredModel::Walk(s) => Mixture::applies(s, self.transmits()),
        }
    }

    /// Whether light can cross the whole stack.
    fn transmits(&self) -> bool {
        match &self.model {
            LayeredModel::Closed(_) => false,
            LayeredModel::Walk(s) => s
                .interfaces()
                .iter()
                .all(|b| b.flags().intersects(BxdfFlags::TRANSMISSION)),
        }
    }

    /// BSDF value (a stochastic estimate for the walk).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        match &self.model {
            LayeredModel::Closed(c) => c.f(wo, wi),
            LayeredModel::Walk(s) => s.eval(wo, wi, mode, &mut query_rng(self.seed, wo, wi, 0.0)),
        }
    }

    /// Sampling density (exact for the closed form, an approximation for MIS otherwise).
    pub(crate) fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        match &self.model {
            LayeredModel::Closed(c) => c.pdf(wo, wi),
            LayeredModel::Walk(s) => {
                if wo.z == 0.0 || wi.z == 0.0 {
                    return 0.0;
                }
                if let Some(m) = Mixture::of(s, wo, self.transmits()) {
                    return m.pdf(wo, wi);
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
                let tw = s.entrance_weight();
                let p = if ent == 0 && tw != 1.0 {
                    // The walk's first choice (`Stack::entrance_weight`): the coat's
                    // reflection with its probability P′ at this pair's microfacet, and
                    // roughly cosine-distributed light from below with the rest.
                    match b.pdf_weighted(wo, wi, mode, tw) {
                        (pg, Some(pr)) => pg + (1.0 - pr) * cos,
                        (pg, None) => 0.5 * pg + 0.5 * cos,
                    }
                } else if b.flags().is_non_specular() {
                    0.5 * b.pdf(wo, wi, mode) + 0.5 * cos
                } else {
                    cos
                };
                (1.0 - t) * p
            }
        }
    }

    /// Samples the walk (or the closed form).
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let rng = &mut query_rng(self.seed, wo, Vec3::new(u.x, u.y, 1.0), uc);
        let s = match &self.model {
            LayeredModel::Closed(c) => return c.sample_f(wo, uc, u, rng),
            LayeredModel::Walk(s) => s,
        };
        if wo.z == 0.0 {
            return None;
        }
        if let Some(m) = Mixture::of(s, wo, self.transmits()) {
            let (wi, pdf) = m.sample(wo, uc, u)?;
            return Some(BsdfSample::new(
                self.f(wo, wi, mode),
                wi,
                pdf,
                BxdfFlags::GLOSSY_REFLECTION,
            ));
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
            .pdf(wo, wi, mode)
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
