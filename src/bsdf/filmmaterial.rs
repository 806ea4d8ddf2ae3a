//! The material behind the four thin-film plugins (`thinfilm`, `roughthinfilm`,
//! `thinfilmconductor`, `roughthinfilmconductor` and the seed's aliases): parameters as
//! textures and spectra, turned into a film BSDF at each shading point. See the BSDF files for
//! the models and parameter tables.

use super::filmfresnel::{FilmFresnel, FilmMode, FilmSamples, THESIS_LAMBDA};
use super::microfacet::{MicrofacetDistribution, MicrofacetType};
use super::roughthinfilm::RoughThinFilmBxdf;
use super::thinfilm::ThinFilmBxdf;
use super::thinfilmconductor::{RoughThinFilmConductorBxdf, ThinFilmConductorBxdf};
use super::Bxdf;
use crate::spectrum::ior::keratin_ior;
use crate::spectrum::{SampledWavelengths, Spectrum};
use crate::texture::{FloatTexture, SpectrumTexture, TexCoord};

/// Default film index (OpenPBR's `thin_film_ior`).
pub const DEFAULT_FILM_IOR: f32 = 1.4;
/// Default film thickness in nm (OpenPBR's `thin_film_thickness`, 0.5 µm).
pub const DEFAULT_FILM_THICKNESS: f32 = 500.0;
/// Film thickness of the seed's plugins when none is given (nm).
pub const SEED_FILM_THICKNESS: f32 = 400.0;

/// A film's index of refraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilmIor {
    /// The same at every wavelength.
    Constant(f32),
    /// Keratin, 1.532 + 5890/λ² (λ in nm).
    Keratin,
}

impl FilmIor {
    /// Index at `lambda` nm.
    pub fn at(&self, lambda: f32) -> f32 {
        match self {
            FilmIor::Constant(n) => *n,
            FilmIor::Keratin => keratin_ior(lambda),
        }
    }
}

/// What lies under the film.
#[derive(Clone, Debug)]
pub enum FilmBase {
    /// A dielectric of real index `int_ior` (light refracts into it).
    Dielectric { int_ior: f32 },
    /// A metal of complex index `eta + i k`.
    Conductor { eta: Spectrum, k: Spectrum },
}

/// Parameters of a film material.
#[derive(Clone, Debug)]
pub struct FilmMaterial {
    pub base: FilmBase,
    pub ext_ior: f32,
    pub film_ior: FilmIor,
    /// Thickness in nm.
    pub thickness: FloatTexture,
    pub mode: FilmMode,
    /// Microfacet distribution and α_u, α_v; `None`: smooth.
    pub rough: Option<(MicrofacetType, FloatTexture, FloatTexture)>,
    pub specular_reflectance: SpectrumTexture,
    /// Unused over a metal.
    pub specular_transmittance: SpectrumTexture,
}

impl FilmMaterial {
    fn samples<const K: usize>(&self, lambda: [f32; K]) -> FilmSamples<K> {
        let (base_n, base_k) = match &self.base {
            FilmBase::Dielectric { int_ior } => ([*int_ior; K], [0.0; K]),
            FilmBase::Conductor { eta, k } => (
                lambda.map(|l| eta.eval(l)),
                // A tabulated k of exactly 0 would make the metal look like a dielectric.
                lambda.map(|l| k.eval(l).max(1e-6)),
            ),
        };
        FilmSamples {
            lambda,
            film: lambda.map(|l| self.film_ior.at(l)),
            base_n,
            base_k,
        }
    }

    /// The film's Fresnel term at a point for the path's wavelengths.
    pub fn fresnel(&self, tc: &TexCoord, wl: &SampledWavelengths) -> FilmFresnel {
        let d = self.thickness.eval(tc);
        FilmFresnel {
            ext: self.ext_ior,
            d_nm: if d.is_finite() { d.max(0.0) } else { 0.0 },
            spectral: self.samples(wl.lambda),
            thesis: self.samples(THESIS_LAMBDA),
            mode: self.mode,
        }
    }

    /// The BSDF at a shading point.
    pub fn eval(&self, tc: &TexCoord, wl: &SampledWavelengths) -> Bxdf {
        let film = self.fresnel(tc, wl);
        let r_s = self.specular_reflectance.eval(tc, wl);
        let t_s = self.specular_transmittance.eval(tc, wl);
        let dist = self
            .rough
            .as_ref()
            .map(|(kind, au, av)| MicrofacetDistribution::new(*kind, au.eval(tc), av.eval(tc)));
        match (&self.base, dist) {
            (FilmBase::Dielectric { int_ior }, None) => {
                Bxdf::ThinFilm(ThinFilmBxdf::new(film, int_ior / self.ext_ior, r_s, t_s))
            }
            (FilmBase::Dielectric { int_ior }, Some(d)) => Bxdf::RoughThinFilm(
                RoughThinFilmBxdf::new(d, film, int_ior / self.ext_ior, r_s, t_s),
            ),
            (FilmBase::Conductor { .. }, None) => {
                Bxdf::ThinFilmConductor(ThinFilmConductorBxdf::new(film, r_s))
            }
            (FilmBase::Conductor { .. }, Some(d)) => {
                Bxdf::RoughThinFilmConductor(RoughThinFilmConductorBxdf::new(d, film, r_s))
            }
        }
    }

    /// Whether every lobe is a Dirac delta.
    pub fn has_delta_only(&self) -> bool {
        self.rough.is_none()
    }

    /// Whether light can pass through.
    pub fn has_transmission(&self) -> bool {
        matches!(self.base, FilmBase::Dielectric { .. })
    }
}
