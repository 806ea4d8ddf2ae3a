//! Scattering functions. A [`Bxdf`] is a BSDF evaluated at one shading point for one set of
//! wavelengths (textures already looked up), working in the local shading frame: z is the shading
//! normal, and `wo`, `wi` both point away from the surface. [`Bsdf`] adds the frame.
//!
//! Conventions (as in pbrt-v4): `f` returns the BSDF value without the cosine; `sample_f` returns
//! `f`, the sampled `wi`, its solid-angle density and flags, so that the path weight is
//! `f · |cos θi| / pdf`. Delta lobes return `pdf = 1` with `f` holding the lobe's weight divided by
//! `|cos θi|`, and are never returned by `f`/`pdf`.

pub mod absorption;
pub mod bumpmap;
pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod film;
pub mod filmfresnel;
pub mod filmstack;
#[cfg(test)]
mod filmstack_tests;
pub mod fresnel;
pub mod layered;
pub mod material;
pub mod microfacet;
pub mod normalmap;
pub mod null;
pub(crate) mod params;
pub mod plastic;
pub mod rough;
pub mod roughconductor;
pub mod roughdielectric;
pub mod roughplastic;
pub mod roughthinfilm;
pub mod roughthinfilmconductor;
pub mod smooth;
pub mod testing;
#[cfg(test)]
mod tests;
pub mod thindielectric;
pub mod thinfilm;
#[cfg(test)]
mod thinfilm_tests;
pub mod thinfilmconductor;
pub mod twosided;

pub use material::{Interface, Material, Surface};

use crate::math::{Frame, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;
use filmfresnel::FilmFresnel;
use filmstack::StackFresnel;
use fresnel::{ConductorFresnel, DielectricFresnel, ThinSheetFresnel};
use rough::Rough;
use smooth::Smooth;

/// Whether radiance (from lights) or importance (from the camera) is being transported; the
/// two differ for refraction, where radiance is scaled by 1/η² and importance is not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    Radiance,
    Importance,
}

/// Lobe classification bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct BxdfFlags(pub u8);

impl BxdfFlags {
    pub const NONE: BxdfFlags = BxdfFlags(0);
    pub const REFLECTION: BxdfFlags = BxdfFlags(1);
    pub const TRANSMISSION: BxdfFlags = BxdfFlags(2);
    pub const DIFFUSE: BxdfFlags = BxdfFlags(4);
    pub const GLOSSY: BxdfFlags = BxdfFlags(8);
    pub const SPECULAR: BxdfFlags = BxdfFlags(16);
    pub const DIFFUSE_REFLECTION: BxdfFlags = BxdfFlags(1 | 4);
    pub const GLOSSY_REFLECTION: BxdfFlags = BxdfFlags(1 | 8);
    pub const SPECULAR_REFLECTION: BxdfFlags = BxdfFlags(1 | 16);
    pub const GLOSSY_TRANSMISSION: BxdfFlags = BxdfFlags(2 | 8);
    pub const SPECULAR_TRANSMISSION: BxdfFlags = BxdfFlags(2 | 16);
    /// The lobes `f` and `pdf` can evaluate.
    pub const NON_SPECULAR: BxdfFlags = BxdfFlags(4 | 8);
    /// The kinds of lobe (diffuse, glossy, specular), without their directions.
    pub const KINDS: BxdfFlags = BxdfFlags(4 | 8 | 16);

    /// Whether all bits of `o` are set.
    #[inline]
    pub fn contains(self, o: BxdfFlags) -> bool {
        self.0 & o.0 == o.0
    }
    /// Whether any bit of `o` is set.
    #[inline]
    pub fn intersects(self, o: BxdfFlags) -> bool {
        self.0 & o.0 != 0
    }
    /// Whether the lobe is a Dirac delta.
    #[inline]
    pub fn is_specular(self) -> bool {
        self.intersects(BxdfFlags::SPECULAR)
    }
    /// Whether there is a non-delta lobe (one that `f` and `pdf` can evaluate).
    #[inline]
    pub fn is_non_specular(self) -> bool {
        self.intersects(BxdfFlags::NON_SPECULAR)
    }
    /// The bits of `self` that `o` also has.
    #[inline]
    pub fn and(self, o: BxdfFlags) -> BxdfFlags {
        BxdfFlags(self.0 & o.0)
    }
}

impl std::ops::BitOr for BxdfFlags {
    type Output = BxdfFlags;
    #[inline]
    fn bitor(self, o: BxdfFlags) -> BxdfFlags {
        BxdfFlags(self.0 | o.0)
    }
}

/// The result of sampling a BSDF.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// BSDF value for the sampled pair (for delta lobes: weight / |cos θi|).
    pub f: SampledSpectrum,
    /// Sampled incident direction (local frame for `Bxdf`, world for `Bsdf`).
    pub wi: Vec3,
    /// Solid-angle density of `wi` (1 for delta lobes).
    pub pdf: f32,
    /// The lobe that was sampled.
    pub flags: BxdfFlags,
    /// Relative index of refraction across the interface for transmission (1 otherwise).
    pub eta: f32,
    /// True when `pdf` is only proportional to the true density (stochastic BSDFs): use
    /// `f·cos/pdf` as the weight but take MIS densities from `pdf()`.
    pub pdf_is_proportional: bool,
}

impl BsdfSample {
    /// A sample from a non-stochastic lobe.
    #[inline]
    pub fn new(f: SampledSpectrum, wi: Vec3, pdf: f32, flags: BxdfFlags) -> BsdfSample {
        BsdfSample {
            f,
            wi,
            pdf,
            flags,
            eta: 1.0,
            pdf_is_proportional: false,
        }
    }
    /// Whether the sampled lobe is a delta.
    #[inline]
    pub fn is_specular(&self) -> bool {
        self.flags.is_specular()
    }
    /// Whether the sample went through the surface.
    #[inline]
    pub fn is_transmission(&self) -> bool {
        self.flags.intersects(BxdfFlags::TRANSMISSION)
    }
}

/// A BSDF evaluated at one shading point (local frame). The interface plugins are two surfaces
/// ([`Smooth`], [`Rough`]) over four Fresnel terms.
#[derive(Clone, Debug)]
pub enum Bxdf {
    Diffuse(diffuse::DiffuseBxdf),
    /// `dielectric`.
    Dielectric(Smooth<DielectricFresnel>),
    /// `thindielectric`.
    ThinDielectric(Smooth<ThinSheetFresnel>),
    /// `conductor`.
    Conductor(Smooth<ConductorFresnel>),
    /// `thinfilm` and `thinfilmconductor`.
    ThinFilm(Smooth<FilmFresnel>),
    /// `roughdielectric`.
    RoughDielectric(Rough<DielectricFresnel>),
    /// `roughconductor`.
    RoughConductor(Rough<ConductorFresnel>),
    /// `roughthinfilm` and `roughthinfilmconductor`.
    RoughThinFilm(Rough<FilmFresnel>),
    /// `filmstack`, smooth.
    FilmStack(Smooth<StackFresnel>),
    /// `filmstack`, rough.
    RoughFilmStack(Rough<StackFresnel>),
    /// `plastic` and `roughplastic`.
    Plastic(plastic::PlasticBxdf),
    Absorption(absorption::AbsorptionBxdf),
    /// `multilayered` (its random walk is boxed, its closed form inline).
    Layered(layered::LayeredBxdf),
    /// Absorbs everything (e.g. the back of a one-sided surface, or `null`).
    Black,
}

/// A microfacet interface seen as a coat ([`Bxdf::microfacet_coat`]): its reflection lobe alone.
#[derive(Clone, Copy)]
pub enum MicrofacetCoat<'a> {
    Dielectric(&'a Rough<DielectricFresnel>),
    Film(&'a Rough<FilmFresnel>),
    Stack(&'a Rough<StackFresnel>),
}

impl MicrofacetCoat<'_> {
    /// See [`Rough::sample_reflection`].
    pub fn sample_reflection(self, wo: Vec3, u: Vec2) -> Option<Vec3> {
        match self {
            MicrofacetCoat::Dielectric(b) => b.sample_reflection(wo, u),
            MicrofacetCoat::Film(b) => b.sample_reflection(wo, u),
            MicrofacetCoat::Stack(b) => b.sample_reflection(wo, u),
        }
    }

    /// See [`Rough::reflection_pdf`].
    pub fn reflection_pdf(self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            MicrofacetCoat::Dielectric(b) => b.reflection_pdf(wo, wi),
            MicrofacetCoat::Film(b) => b.reflection_pdf(wo, wi),
            MicrofacetCoat::Stack(b) => b.reflection_pdf(wo, wi),
        }
    }
}

/// The BxDFs made only of delta lobes (a smooth surface over any Fresnel term), as a pattern:
/// they have no value to evaluate and no density for another technique to find.
macro_rules! smooth {
    () => {
        Bxdf::Dielectric(_)
            | Bxdf::ThinDielectric(_)
            | Bxdf::Conductor(_)
            | Bxdf::ThinFilm(_)
            | Bxdf::FilmStack(_)
    };
}

impl Bxdf {
    /// `dielectric` of relative index `eta` with reflectance and transmittance factors.
    pub fn dielectric(eta: f32, r_s: SampledSpectrum, t_s: SampledSpectrum) -> Bxdf {
        Bxdf::Dielectric(Smooth::new(DielectricFresnel { eta }, r_s, t_s))
    }
    /// `roughdielectric`.
    pub fn rough_dielectric(
        d: microfacet::MicrofacetDistribution,
        eta: f32,
        r_s: SampledSpectrum,
        t_s: SampledSpectrum,
    ) -> Bxdf {
        Bxdf::RoughDielectric(Rough::new(d, DielectricFresnel { eta }, r_s, t_s))
    }
    /// `conductor`.
    pub fn conductor(fresnel: ConductorFresnel, r_s: SampledSpectrum) -> Bxdf {
        Bxdf::Conductor(Smooth::new(fresnel, r_s, SampledSpectrum::ONE))
    }
    /// `roughconductor`.
    pub fn rough_conductor(
        d: microfacet::MicrofacetDistribution,
        fresnel: ConductorFresnel,
        r_s: SampledSpectrum,
    ) -> Bxdf {
        Bxdf::RoughConductor(Rough::new(d, fresnel, r_s, SampledSpectrum::ONE))
    }

    /// Gives a stochastic BSDF a new seed for its random numbers (others are unchanged): its
    /// value at a pair is a deterministic function of the seed, so averaging repeated
    /// evaluations of one pair needs a new seed each time.
    pub fn reseed(&mut self, seed: u64) {
        if let Bxdf::Layered(l) = self {
            l.seed = seed;
        }
    }

    /// The lobes this BSDF has.
    pub fn flags(&self) -> BxdfFlags {
        match self {
            Bxdf::Diffuse(b) => b.flags(),
            Bxdf::Dielectric(b) => b.flags(),
            Bxdf::ThinDielectric(b) => b.flags(),
            Bxdf::Conductor(b) => b.flags(),
            Bxdf::ThinFilm(b) => b.flags(),
            Bxdf::RoughDielectric(b) => b.flags(),
            Bxdf::RoughConductor(b) => b.flags(),
            Bxdf::RoughThinFilm(b) => b.flags(),
            Bxdf::FilmStack(b) => b.flags(),
            Bxdf::RoughFilmStack(b) => b.flags(),
            Bxdf::Plastic(b) => b.flags(),
            Bxdf::Absorption(b) => b.flags(),
            Bxdf::Layered(b) => b.flags(),
            Bxdf::Black => BxdfFlags::NONE,
        }
    }

    /// Whether this BSDF's own samples should carry the light of smooth environments alone,
    /// without light samples ([`crate::light::LightSampler::sample_for`]; measurements in
    /// [`crate::integrator::path`]'s notes), where `other_lights` says whether next-event
    /// estimation has other lights to choose. True for the BSDFs with a glossy or delta lobe
    /// that sample f · cos closely and choose their lobes in proportion to their albedos
    /// (rough conductors, dielectrics, films and stacks, the plastics, closed-form coats); for
    /// the Lambertian surface only beside other lights (its cosine samples carry a smooth sky
    /// about as well as the sky's own light samples do, which are better spent on a sun or a
    /// lamp; with the sky alone they are a second look at its visibility); never for the random
    /// walk, whose own samples are noisy.
    pub fn samples_smooth_env(&self, other_lights: bool) -> bool {
        match self {
            Bxdf::RoughDielectric(_)
            | Bxdf::RoughConductor(_)
            | Bxdf::RoughThinFilm(_)
            | Bxdf::RoughFilmStack(_)
            | Bxdf::Plastic(_) => true,
            Bxdf::Diffuse(_) => other_lights,
            Bxdf::Layered(b) => {
                matches!(b.model, layered::LayeredModel::Closed(_)) || b.mixture_sampled()
            }
            _ => false,
        }
    }

    /// BSDF value (no cosine) for the pair; 0 for delta lobes. Deterministic: a stochastic
    /// BSDF draws its random numbers from a hash of its seed and the pair.
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        match self {
            Bxdf::Diffuse(b) => b.f(wo, wi),
            Bxdf::RoughDielectric(b) => b.f(wo, wi, mode),
            Bxdf::RoughConductor(b) => b.f(wo, wi, mode),
            Bxdf::RoughThinFilm(b) => b.f(wo, wi, mode),
            Bxdf::RoughFilmStack(b) => b.f(wo, wi, mode),
            Bxdf::Plastic(b) => b.f(wo, wi),
            Bxdf::Absorption(b) => b.f(wo, wi),
            Bxdf::Layered(b) => b.f(wo, wi, mode),
            smooth!() | Bxdf::Black => SampledSpectrum::ZERO,
        }
    }

    /// Samples `wi` given `wo`; `uc` chooses a lobe, `u` the direction.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        match self {
            Bxdf::Diffuse(b) => b.sample_f(wo, u),
            Bxdf::Dielectric(b) => b.sample_f(wo, uc, mode),
            Bxdf::ThinDielectric(b) => b.sample_f(wo, uc, mode),
            Bxdf::Conductor(b) => b.sample_f(wo, uc, mode),
            Bxdf::ThinFilm(b) => b.sample_f(wo, uc, mode),
            Bxdf::RoughDielectric(b) => b.sample_f(wo, uc, u, mode),
            Bxdf::RoughConductor(b) => b.sample_f(wo, uc, u, mode),
            Bxdf::RoughThinFilm(b) => b.sample_f(wo, uc, u, mode),
            Bxdf::FilmStack(b) => b.sample_f(wo, uc, mode),
            Bxdf::RoughFilmStack(b) => b.sample_f(wo, uc, u, mode),
            Bxdf::Plastic(b) => b.sample_f(wo, uc, u),
            Bxdf::Absorption(b) => b.sample_f(wo, u),
            Bxdf::Layered(b) => b.sample_f(wo, uc, u, mode),
            Bxdf::Black => None,
        }
    }

    /// `sample_f` with the choice between reflection and transmission scaled by `t_weight`
    /// (the microfacet dielectrics, see [`rough`]; the others ignore it). Used by layered
    /// stacks whose transmitted light is mostly absorbed below.
    pub fn sample_f_weighted(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        t_weight: f32,
    ) -> Option<BsdfSample> {
        match self {
            Bxdf::RoughDielectric(b) => b.sample_f_weighted(wo, uc, u, mode, t_weight),
            Bxdf::RoughThinFilm(b) => b.sample_f_weighted(wo, uc, u, mode, t_weight),
            Bxdf::RoughFilmStack(b) => b.sample_f_weighted(wo, uc, u, mode, t_weight),
            _ => self.sample_f(wo, uc, u, mode),
        }
    }

    /// The density of [`Bxdf::sample_f_weighted`], with its probability of reflection at the
    /// pair's microfacet where it has one (`None` for the BSDFs that ignore `t_weight`).
    pub fn pdf_weighted(
        &self,
        wo: Vec3,
        wi: Vec3,
        mode: TransportMode,
        t_weight: f32,
    ) -> (f32, Option<f32>) {
        let (pdf, p) = match self {
            Bxdf::RoughDielectric(b) => b.pdf_weighted(wo, wi, t_weight),
            Bxdf::RoughThinFilm(b) => b.pdf_weighted(wo, wi, t_weight),
            Bxdf::RoughFilmStack(b) => b.pdf_weighted(wo, wi, t_weight),
            _ => return (self.pdf(wo, wi, mode), None),
        };
        (pdf, Some(p))
    }

    /// A microfacet interface (dielectric, film or film stack) as a coat, `None` for the other
    /// BSDFs.
    pub fn microfacet_coat(&self) -> Option<MicrofacetCoat<'_>> {
        match self {
            Bxdf::RoughDielectric(b) => Some(MicrofacetCoat::Dielectric(b)),
            Bxdf::RoughThinFilm(b) => Some(MicrofacetCoat::Film(b)),
            Bxdf::RoughFilmStack(b) => Some(MicrofacetCoat::Stack(b)),
            _ => None,
        }
    }

    /// The relative index a transmissive microfacet interface refracts into (`None` for the
    /// other BSDFs).
    pub fn rough_eta(&self) -> Option<f32> {
        match self {
            Bxdf::RoughDielectric(b) => b.eta(),
            Bxdf::RoughThinFilm(b) => b.eta(),
            Bxdf::RoughFilmStack(b) => b.eta(),
            _ => None,
        }
    }

    /// Solid-angle density with which `sample_f` picks `wi` (non-delta lobes only).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        match self {
            Bxdf::Diffuse(b) => b.pdf(wo, wi),
            Bxdf::RoughDielectric(b) => b.pdf(wo, wi),
            Bxdf::RoughConductor(b) => b.pdf(wo, wi),
            Bxdf::RoughThinFilm(b) => b.pdf(wo, wi),
            Bxdf::RoughFilmStack(b) => b.pdf(wo, wi),
            Bxdf::Plastic(b) => b.pdf(wo, wi),
            Bxdf::Absorption(b) => b.pdf(wo, wi),
            Bxdf::Layered(b) => b.pdf(wo, wi, mode),
            smooth!() | Bxdf::Black => 0.0,
        }
    }
}

/// A [`Bxdf`] placed in a shading frame; optionally two-sided (Mitsuba's `twosided`: directions
/// below the surface are mirrored to the front before evaluation).
#[derive(Clone, Debug)]
pub struct Bsdf {
    pub frame: Frame,
    pub bxdf: Bxdf,
    pub two_sided: bool,
}

impl Bsdf {
    #[inline]
    fn local(&self, w: Vec3) -> Vec3 {
        self.frame.to_local(w)
    }

    #[inline]
    fn side(&self, wo: Vec3) -> f32 {
        if self.two_sided && wo.z < 0.0 {
            -1.0
        } else {
            1.0
        }
    }

    /// Lobe flags.
    pub fn flags(&self) -> BxdfFlags {
        self.bxdf.flags()
    }

    /// The pair in the local frame, mirrored to the front when a two-sided BSDF is seen from
    /// below.
    #[inline]
    fn local_pair(&self, wo: Vec3, wi: Vec3) -> (Vec3, Vec3) {
        let (mut wo, mut wi) = (self.local(wo), self.local(wi));
        let s = self.side(wo);
        wo.z *= s;
        wi.z *= s;
        (wo, wi)
    }

    /// [`Bxdf::samples_smooth_env`].
    pub fn samples_smooth_env(&self, other_lights: bool) -> bool {
        self.bxdf.samples_smooth_env(other_lights)
    }

    /// BSDF value for world-space directions.
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        let (wo, wi) = self.local_pair(wo, wi);
        self.bxdf.f(wo, wi, mode)
    }

    /// Samples a world-space incident direction.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let mut wo = self.local(wo);
        let s = self.side(wo);
        wo.z *= s;
        let mut bs = self.bxdf.sample_f(wo, uc, u, mode)?;
        if !(bs.pdf > 0.0) || !bs.f.is_finite() || bs.wi.z == 0.0 {
            return None;
        }
        bs.wi.z *= s;
        bs.wi = self.frame.to_world(bs.wi);
        Some(bs)
    }

    /// Density of sampling world-space `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        let (wo, wi) = self.local_pair(wo, wi);
        self.bxdf.pdf(wo, wi, mode)
    }
}
