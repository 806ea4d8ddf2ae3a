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
pub mod filmfresnel;
pub mod filmmaterial;
pub mod fresnel;
pub mod inspect;
pub mod layered;
pub mod material;
pub mod microfacet;
pub mod plastic;
pub mod roughconductor;
pub mod roughdielectric;
pub mod roughplastic;
pub mod roughthinfilm;
pub mod testing;
#[cfg(test)]
mod tests;
pub mod thindielectric;
pub mod thinfilm;
#[cfg(test)]
mod thinfilm_tests;
pub mod thinfilmconductor;

pub use material::Material;

use crate::math::{Frame, Pcg32, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

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
        self.intersects(BxdfFlags(4 | 8))
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

/// A BSDF evaluated at one shading point (local frame).
#[derive(Clone, Debug)]
pub enum Bxdf {
    Diffuse(diffuse::DiffuseBxdf),
    Dielectric(dielectric::DielectricBxdf),
    ThinDielectric(thindielectric::ThinDielectricBxdf),
    RoughDielectric(roughdielectric::RoughDielectricBxdf),
    Conductor(conductor::ConductorBxdf),
    RoughConductor(roughconductor::RoughConductorBxdf),
    Plastic(plastic::PlasticBxdf),
    RoughPlastic(roughplastic::RoughPlasticBxdf),
    ThinFilm(thinfilm::ThinFilmBxdf),
    RoughThinFilm(roughthinfilm::RoughThinFilmBxdf),
    ThinFilmConductor(thinfilmconductor::ThinFilmConductorBxdf),
    RoughThinFilmConductor(thinfilmconductor::RoughThinFilmConductorBxdf),
    Absorption(absorption::AbsorptionBxdf),
    /// `multilayered` (boxed: it holds its interfaces inline).
    Layered(Box<layered::LayeredBxdf>),
    /// Absorbs everything (e.g. the back of a one-sided surface, or `null`).
    Black,
}

macro_rules! dispatch {
    ($s:expr, $b:ident => $e:expr, $black:expr) => {
        match $s {
            Bxdf::Diffuse($b) => $e,
            Bxdf::Dielectric($b) => $e,
            Bxdf::ThinDielectric($b) => $e,
            Bxdf::RoughDielectric($b) => $e,
            Bxdf::Conductor($b) => $e,
            Bxdf::RoughConductor($b) => $e,
            Bxdf::Plastic($b) => $e,
            Bxdf::RoughPlastic($b) => $e,
            Bxdf::ThinFilm($b) => $e,
            Bxdf::RoughThinFilm($b) => $e,
            Bxdf::ThinFilmConductor($b) => $e,
            Bxdf::RoughThinFilmConductor($b) => $e,
            Bxdf::Absorption($b) => $e,
            Bxdf::Layered($b) => $e,
            Bxdf::Black => $black,
        }
    };
}

impl Bxdf {
    /// The lobes this BSDF has.
    pub fn flags(&self) -> BxdfFlags {
        dispatch!(self, b => b.flags(), BxdfFlags::NONE)
    }

    /// BSDF value (no cosine) for the pair; 0 for delta lobes.
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode, rng: &mut Pcg32) -> SampledSpectrum {
        dispatch!(self, b => b.f(wo, wi, mode, rng), SampledSpectrum::ZERO)
    }

    /// Samples `wi` given `wo`; `uc` chooses a lobe, `u` the direction.
    pub fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        dispatch!(self, b => b.sample_f(wo, uc, u, mode, rng), None)
    }

    /// Solid-angle density with which `sample_f` picks `wi` (non-delta lobes only).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode, rng: &mut Pcg32) -> f32 {
        dispatch!(self, b => b.pdf(wo, wi, mode, rng), 0.0)
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

    /// BSDF value for world-space directions.
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode, rng: &mut Pcg32) -> SampledSpectrum {
        let (mut wo, mut wi) = (self.local(wo), self.local(wi));
        let s = self.side(wo);
        wo.z *= s;
        wi.z *= s;
        self.bxdf.f(wo, wi, mode, rng)
    }

    /// Samples a world-space incident direction.
    pub fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        let mut wo = self.local(wo);
        let s = self.side(wo);
        wo.z *= s;
        let mut bs = self.bxdf.sample_f(wo, uc, u, mode, rng)?;
        if !(bs.pdf > 0.0) || !bs.f.is_finite() || bs.wi.z == 0.0 {
            return None;
        }
        bs.wi.z *= s;
        bs.wi = self.frame.to_world(bs.wi);
        Some(bs)
    }

    /// Density of sampling world-space `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode, rng: &mut Pcg32) -> f32 {
        let (mut wo, mut wi) = (self.local(wo), self.local(wi));
        let s = self.side(wo);
        wo.z *= s;
        wi.z *= s;
        self.bxdf.pdf(wo, wi, mode, rng)
    }
}
