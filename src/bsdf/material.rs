//! Materials: BSDF parameters as textures, evaluated per shading point into a [`Bxdf`].
//!
//! Each variant mirrors a Mitsuba BSDF plugin (see the plugin's file in this folder for its
//! model and parameter table); the constructors take Mitsuba's parameters and fill in the
//! derived constants (relative index, the diffuse Fresnel average of the plastics). Defaults are
//! Mitsuba 3's and are exposed as constants for the scene loader.

use super::absorption::AbsorptionBxdf;
use super::conductor::ConductorBxdf;
use super::dielectric::DielectricBxdf;
use super::diffuse::DiffuseBxdf;
use super::filmmaterial::FilmMaterial;
use super::fresnel::{fresnel_diffuse_reflectance, ConductorFresnel};
use super::layered::{LayeredBxdf, Medium, MAX_INTERFACES};
use super::microfacet::{MicrofacetDistribution, MicrofacetType};
use super::plastic::PlasticBxdf;
use super::roughconductor::RoughConductorBxdf;
use super::roughdielectric::RoughDielectricBxdf;
use super::roughplastic::RoughPlasticBxdf;
use super::thindielectric::ThinDielectricBxdf;
use super::Bxdf;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use crate::texture::{FloatTexture, SpectrumTexture, TexCoord};

/// Default interior index of `dielectric`/`roughdielectric`/`thindielectric` (BK7).
pub const DEFAULT_INT_IOR: f32 = 1.5046;
/// Default exterior index (air).
pub const DEFAULT_EXT_IOR: f32 = 1.000277;
/// Default interior index of `plastic`/`roughplastic` (polypropylene).
pub const PLASTIC_INT_IOR: f32 = 1.49;
/// Default roughness α of the rough plugins.
pub const DEFAULT_ALPHA: f32 = 0.1;
/// Default microfacet distribution of the rough plugins.
pub const DEFAULT_DISTRIBUTION: MicrofacetType = MicrofacetType::Beckmann;

/// Complex index of refraction of a conductor (absolute; divided by `ext_ior` on evaluation).
#[derive(Clone, Debug)]
pub struct ConductorIor {
    pub eta: Spectrum,
    pub k: Spectrum,
    pub ext_ior: f32,
}

/// A material.
#[derive(Clone, Debug)]
pub enum Material {
    /// `diffuse`.
    Diffuse { reflectance: SpectrumTexture },
    /// `dielectric`; `eta` = int_ior / ext_ior.
    Dielectric {
        eta: f32,
        specular_reflectance: SpectrumTexture,
        specular_transmittance: SpectrumTexture,
    },
    /// `thindielectric`; `eta` = int_ior / ext_ior.
    ThinDielectric {
        eta: f32,
        specular_reflectance: SpectrumTexture,
        specular_transmittance: SpectrumTexture,
    },
    /// `roughdielectric`.
    RoughDielectric {
        distribution: MicrofacetType,
        alpha_u: FloatTexture,
        alpha_v: FloatTexture,
        eta: f32,
        specular_reflectance: SpectrumTexture,
        specular_transmittance: SpectrumTexture,
    },
    /// `conductor`; `ior: None` is a perfect mirror (`material = "none"`).
    Conductor {
        ior: Option<ConductorIor>,
        specular_reflectance: SpectrumTexture,
    },
    /// `roughconductor`.
    RoughConductor {
        distribution: MicrofacetType,
        alpha_u: FloatTexture,
        alpha_v: FloatTexture,
        ior: Option<ConductorIor>,
        specular_reflectance: SpectrumTexture,
    },
    /// `plastic`; build with [`Material::plastic`], which computes `fdr_int`.
    Plastic {
        eta: f32,
        diffuse_reflectance: SpectrumTexture,
        specular_reflectance: SpectrumTexture,
        nonlinear: bool,
        /// Cosine-weighted internal reflectance of the coating, F̄(1/η).
        fdr_int: f32,
    },
    /// `roughplastic`; build with [`Material::rough_plastic`], which computes `fdr_int`.
    RoughPlastic {
        distribution: MicrofacetType,
        alpha: FloatTexture,
        eta: f32,
        diffuse_reflectance: SpectrumTexture,
        specular_reflectance: SpectrumTexture,
        nonlinear: bool,
        fdr_int: f32,
    },
    /// `twosided`: `front` on both sides, or `back` on the back when given.
    TwoSided {
        front: Box<Material>,
        back: Option<Box<Material>>,
    },
    /// `thinfilm`, `roughthinfilm`, `thinfilmconductor`, `roughthinfilmconductor` (and the
    /// seed's aliases).
    ThinFilm(Box<FilmMaterial>),
    /// `bumpmap`: `inner` with its normal displaced by `scale`·`height` (see `bumpmap.rs`).
    BumpMap {
        height: FloatTexture,
        scale: f32,
        inner: Box<Material>,
    },
    /// `normalmap`: a tangent-space normal from an image or a `scales` relief.
    NormalMap {
        source: super::bumpmap::NormalSource,
        strength: f32,
        inner: Box<Material>,
    },
    /// `multilayered`: interfaces top first and the media between them (see
    /// [`super::layered`]).
    Multilayered {
        surfaces: Vec<Material>,
        media: Vec<LayerMedium>,
        max_depth: u32,
        closed_form: bool,
    },
    /// `absorption` (see [`super::absorption`]).
    Absorption {
        reflectance: SpectrumTexture,
        sigma_a: SpectrumTexture,
        thickness: f32,
    },
    /// `null` (for now: black; an index-matched pass-through would be `ThinDielectric` with
    /// η = 1).
    Null,
}

/// A homogeneous medium of a `multilayered` stack (unit thickness: `sigma_t` is the optical
/// depth).
#[derive(Clone, Debug)]
pub struct LayerMedium {
    pub sigma_t: SpectrumTexture,
    pub albedo: SpectrumTexture,
    /// Henyey–Greenstein asymmetry.
    pub g: f32,
}

fn splat(v: f32) -> SpectrumTexture {
    SpectrumTexture::Constant(Spectrum::Constant(v))
}

impl Material {
    /// `diffuse` with the given reflectance (Mitsuba's default is 0.5).
    pub fn diffuse(reflectance: SpectrumTexture) -> Material {
        Material::Diffuse { reflectance }
    }
    /// `diffuse` with Mitsuba's defaults.
    pub fn default_diffuse() -> Material {
        Material::diffuse(splat(0.5))
    }
    /// `dielectric` (Mitsuba defaults: 1.5046, 1.000277, factors 1).
    pub fn dielectric(
        int_ior: f32,
        ext_ior: f32,
        specular_reflectance: SpectrumTexture,
        specular_transmittance: SpectrumTexture,
    ) -> Material {
        Material::Dielectric {
            eta: int_ior / ext_ior,
            specular_reflectance,
            specular_transmittance,
        }
    }
    /// `thindielectric` (same defaults as `dielectric`).
    pub fn thin_dielectric(
        int_ior: f32,
        ext_ior: f32,
        specular_reflectance: SpectrumTexture,
        specular_transmittance: SpectrumTexture,
    ) -> Material {
        Material::ThinDielectric {
            eta: int_ior / ext_ior,
            specular_reflectance,
            specular_transmittance,
        }
    }
    /// `roughdielectric` (defaults: beckmann, α = 0.1, 1.5046, 1.000277, factors 1).
    #[allow(clippy::too_many_arguments)]
    pub fn rough_dielectric(
        distribution: MicrofacetType,
        alpha_u: FloatTexture,
        alpha_v: FloatTexture,
        int_ior: f32,
        ext_ior: f32,
        specular_reflectance: SpectrumTexture,
        specular_transmittance: SpectrumTexture,
    ) -> Material {
        Material::RoughDielectric {
            distribution,
            alpha_u,
            alpha_v,
            eta: int_ior / ext_ior,
            specular_reflectance,
            specular_transmittance,
        }
    }
    /// `conductor` (defaults: mirror, factor 1).
    pub fn conductor(ior: Option<ConductorIor>, specular_reflectance: SpectrumTexture) -> Material {
        Material::Conductor {
            ior,
            specular_reflectance,
        }
    }
    /// `roughconductor` (defaults: beckmann, α = 0.1, mirror, factor 1).
    pub fn rough_conductor(
        distribution: MicrofacetType,
        alpha_u: FloatTexture,
        alpha_v: FloatTexture,
        ior: Option<ConductorIor>,
        specular_reflectance: SpectrumTexture,
    ) -> Material {
        Material::RoughConductor {
            distribution,
            alpha_u,
            alpha_v,
            ior,
            specular_reflectance,
        }
    }
    /// `plastic` (defaults: 1.49, 1.000277, diffuse 0.5, specular 1, linear).
    pub fn plastic(
        int_ior: f32,
        ext_ior: f32,
        diffuse_reflectance: SpectrumTexture,
        specular_reflectance: SpectrumTexture,
        nonlinear: bool,
    ) -> Material {
        let eta = int_ior / ext_ior;
        Material::Plastic {
            eta,
            diffuse_reflectance,
            specular_reflectance,
            nonlinear,
            fdr_int: fresnel_diffuse_reflectance(1.0 / eta),
        }
    }
    /// `roughplastic` (defaults: beckmann, α = 0.1, 1.49, 1.000277, diffuse 0.5, specular 1).
    #[allow(clippy::too_many_arguments)]
    pub fn rough_plastic(
        distribution: MicrofacetType,
        alpha: FloatTexture,
        int_ior: f32,
        ext_ior: f32,
        diffuse_reflectance: SpectrumTexture,
        specular_reflectance: SpectrumTexture,
        nonlinear: bool,
    ) -> Material {
        let eta = int_ior / ext_ior;
        Material::RoughPlastic {
            distribution,
            alpha,
            eta,
            diffuse_reflectance,
            specular_reflectance,
            nonlinear,
            fdr_int: fresnel_diffuse_reflectance(1.0 / eta),
        }
    }
    /// `twosided` around `front`, with an optional different `back`.
    pub fn two_sided(front: Material, back: Option<Material>) -> Material {
        Material::TwoSided {
            front: Box::new(front),
            back: back.map(Box::new),
        }
    }

    /// The BSDF at a shading point, and whether directions below the surface must be mirrored
    /// to the front (`twosided`). `front_side`: whether the ray arrives on the side the
    /// geometric normal points to (selects `back` of a `twosided` with two materials).
    pub fn eval(&self, tc: &TexCoord, wl: &SampledWavelengths, front_side: bool) -> (Bxdf, bool) {
        let sp = |t: &SpectrumTexture| t.eval(tc, wl);
        let dist = |kind: MicrofacetType, au: &FloatTexture, av: &FloatTexture| {
            MicrofacetDistribution::new(kind, au.eval(tc), av.eval(tc))
        };
        let fresnel = |ior: &Option<ConductorIor>| match ior {
            None => ConductorFresnel::Mirror,
            Some(c) => ConductorFresnel::Complex {
                eta: c.eta.sample(wl) / c.ext_ior,
                k: c.k.sample(wl) / c.ext_ior,
            },
        };
        let bxdf = match self {
            Material::Diffuse { reflectance } => {
                Bxdf::Diffuse(DiffuseBxdf::new(sp(reflectance).clamp(0.0, 1.0)))
            }
            Material::Dielectric {
                eta,
                specular_reflectance: r,
                specular_transmittance: t,
            } => Bxdf::Dielectric(DielectricBxdf::new(*eta, sp(r), sp(t))),
            Material::ThinDielectric {
                eta,
                specular_reflectance: r,
                specular_transmittance: t,
            } => Bxdf::ThinDielectric(ThinDielectricBxdf::new(*eta, sp(r), sp(t))),
            Material::RoughDielectric {
                distribution,
                alpha_u,
                alpha_v,
                eta,
                specular_reflectance: r,
                specular_transmittance: t,
            } => Bxdf::RoughDielectric(RoughDielectricBxdf::new(
                dist(*distribution, alpha_u, alpha_v),
                *eta,
                sp(r),
                sp(t),
            )),
            Material::Conductor {
                ior,
                specular_reflectance: r,
            } => Bxdf::Conductor(ConductorBxdf::new(fresnel(ior), sp(r))),
            Material::RoughConductor {
                distribution,
                alpha_u,
                alpha_v,
                ior,
                specular_reflectance: r,
            } => Bxdf::RoughConductor(RoughConductorBxdf::new(
                dist(*distribution, alpha_u, alpha_v),
                fresnel(ior),
                sp(r),
            )),
            Material::Plastic {
                eta,
                diffuse_reflectance: d,
                specular_reflectance: r,
                nonlinear,
                fdr_int,
            } => Bxdf::Plastic(PlasticBxdf::new(
                *eta,
                sp(d).clamp(0.0, 1.0),
                sp(r),
                *fdr_int,
                *nonlinear,
            )),
            Material::RoughPlastic {
                distribution,
                alpha,
                eta,
                diffuse_reflectance: d,
                specular_reflectance: r,
                nonlinear,
                fdr_int,
            } => Bxdf::RoughPlastic(RoughPlasticBxdf::new(
                dist(*distribution, alpha, alpha),
                *eta,
                sp(d).clamp(0.0, 1.0),
                sp(r),
                *fdr_int,
                *nonlinear,
            )),
            Material::TwoSided { front, back } => {
                let m = match back {
                    Some(b) if !front_side => b,
                    _ => front,
                };
                return (m.eval(tc, wl, true).0, true);
            }
            Material::ThinFilm(m) => m.eval(tc, wl),
            // Bump and normal maps change the frame (`shading_frame`), not the BSDF.
            Material::BumpMap { inner, .. } | Material::NormalMap { inner, .. } => {
                return inner.eval(tc, wl, front_side)
            }
            Material::Multilayered {
                surfaces,
                media,
                max_depth,
                closed_form,
            } => {
                let ifs = surfaces.iter().map(|m| m.eval(tc, wl, true).0);
                let med: [Medium; MAX_INTERFACES - 1] =
                    std::array::from_fn(|i| match media.get(i) {
                        Some(m) => Medium {
                            sigma_t: sp(&m.sigma_t).clamp(0.0, f32::MAX),
                            albedo: sp(&m.albedo).clamp(0.0, 1.0),
                            g: m.g,
                        },
                        None => Medium::absorbing(SampledSpectrum::ZERO),
                    });
                let med = &med[..media.len().min(MAX_INTERFACES - 1)];
                match LayeredBxdf::new(ifs, med, *max_depth, *closed_form) {
                    Some(l) => Bxdf::Layered(Box::new(l)),
                    None => Bxdf::Black,
                }
            }
            Material::Absorption {
                reflectance,
                sigma_a,
                thickness,
            } => Bxdf::Absorption(AbsorptionBxdf::new(
                sp(reflectance).clamp(0.0, 1.0),
                sp(sigma_a).clamp(0.0, f32::MAX),
                *thickness,
            )),
            Material::Null => Bxdf::Black,
        };
        (bxdf, false)
    }

    /// Whether every lobe is a Dirac delta (no point in light sampling).
    pub fn has_delta_only(&self) -> bool {
        match self {
            Material::Dielectric { .. }
            | Material::ThinDielectric { .. }
            | Material::Conductor { .. } => true,
            Material::ThinFilm(m) => m.has_delta_only(),
            Material::TwoSided { front, back } => {
                front.has_delta_only() && back.as_ref().is_none_or(|b| b.has_delta_only())
            }
            Material::BumpMap { inner, .. } | Material::NormalMap { inner, .. } => {
                inner.has_delta_only()
            }
            _ => false,
        }
    }

    /// Whether light can pass through (the surface bounds a medium or is see-through).
    pub fn has_transmission(&self) -> bool {
        match self {
            Material::Dielectric { .. }
            | Material::ThinDielectric { .. }
            | Material::RoughDielectric { .. }
            | Material::Null => true,
            Material::ThinFilm(m) => m.has_transmission(),
            Material::Multilayered { surfaces, .. } => {
                surfaces.iter().all(|m| m.has_transmission())
            }
            Material::TwoSided { front, back } => {
                front.has_transmission() || back.as_ref().is_some_and(|b| b.has_transmission())
            }
            Material::BumpMap { inner, .. } | Material::NormalMap { inner, .. } => {
                inner.has_transmission()
            }
            _ => false,
        }
    }
}

impl Default for Material {
    /// Mitsuba's default BSDF: `diffuse` with reflectance 0.5.
    fn default() -> Material {
        Material::default_diffuse()
    }
}
