//! Materials: BSDF parameters as textures, evaluated per shading point into a [`Bxdf`].
//!
//! The plugins build these (each plugin's file in this folder has its model, manual and
//! loader); the nine interface plugins are all a [`Surface`]: an [`Interface`] (dielectric,
//! thin sheet, conductor or thin film) that is smooth or has a [`Roughness`].

use super::absorption::AbsorptionBxdf;
use super::diffuse::DiffuseBxdf;
use super::film::FilmSpec;
use super::fresnel::{DielectricFresnel, ThinSheetFresnel};
use super::layered::{CoatModel, LayeredBxdf, Medium, MAX_INTERFACES};
use super::microfacet::{MicrofacetDistribution, MicrofacetType};
use super::params::conductor_fresnel;
use super::plastic::PlasticBxdf;
use super::rough::Rough;
use super::smooth::Smooth;
use super::Bxdf;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use crate::texture::{FloatTexture, SpectrumTexture, TexCoord};

/// Complex index of refraction of a conductor (absolute; divided by `ext_ior` on evaluation).
#[derive(Clone, Debug)]
pub struct ConductorIor {
    pub eta: Spectrum,
    pub k: Spectrum,
    pub ext_ior: f32,
}

/// A microfacet roughness: distribution and α along u and v.
#[derive(Clone, Debug)]
pub struct Roughness {
    pub distribution: MicrofacetType,
    pub alpha_u: FloatTexture,
    pub alpha_v: FloatTexture,
}

impl Roughness {
    fn eval(&self, tc: &TexCoord) -> MicrofacetDistribution {
        MicrofacetDistribution::new(
            self.distribution,
            self.alpha_u.eval(tc),
            self.alpha_v.eval(tc),
        )
    }
}

/// What an interface is made of.
#[derive(Clone, Debug)]
pub enum Interface {
    /// Two dielectrics of relative index `eta` = interior / exterior.
    Dielectric { eta: f32 },
    /// A thin sheet of relative index `eta` (light passes straight through).
    ThinSheet { eta: f32 },
    /// A metal; `None` is a perfect mirror (`material = "none"`).
    Conductor(Option<ConductorIor>),
    /// A thin film over a dielectric or a metal.
    Film(Box<FilmSpec>),
    /// An interference stack over a dielectric or a metal.
    Stack(Box<super::filmstack::StackSpec>),
}

/// A smooth or rough interface with its non-physical factors.
#[derive(Clone, Debug)]
pub struct Surface {
    pub interface: Interface,
    /// `None`: smooth.
    pub rough: Option<Roughness>,
    pub specular_reflectance: SpectrumTexture,
    /// Unused where the interface absorbs what it does not reflect.
    pub specular_transmittance: SpectrumTexture,
}

impl Surface {
    /// The BSDF at a shading point.
    pub fn eval(&self, tc: &TexCoord, wl: &SampledWavelengths) -> Bxdf {
        let r_s = self.specular_reflectance.eval(tc, wl);
        let t_s = self.specular_transmittance.eval(tc, wl);
        let d = self.rough.as_ref().map(|r| r.eval(tc));
        match (&self.interface, d) {
            (Interface::Dielectric { eta }, None) => {
                Bxdf::Dielectric(Smooth::new(DielectricFresnel { eta: *eta }, r_s, t_s))
            }
            (Interface::Dielectric { eta }, Some(d)) => {
                Bxdf::RoughDielectric(Rough::new(d, DielectricFresnel { eta: *eta }, r_s, t_s))
            }
            (Interface::ThinSheet { eta }, _) => {
                Bxdf::ThinDielectric(Smooth::new(ThinSheetFresnel { eta: *eta }, r_s, t_s))
            }
            (Interface::Conductor(ior), None) => {
                Bxdf::Conductor(Smooth::new(conductor_fresnel(ior, wl), r_s, t_s))
            }
            (Interface::Conductor(ior), Some(d)) => {
                Bxdf::RoughConductor(Rough::new(d, conductor_fresnel(ior, wl), r_s, t_s))
            }
            (Interface::Film(f), None) => Bxdf::ThinFilm(Smooth::new(f.fresnel(tc, wl), r_s, t_s)),
            (Interface::Film(f), Some(d)) => {
                Bxdf::RoughThinFilm(Rough::new(d, f.fresnel(tc, wl), r_s, t_s))
            }
            (Interface::Stack(f), None) => {
                Bxdf::FilmStack(Smooth::new(f.fresnel(tc, wl), r_s, t_s))
            }
            (Interface::Stack(f), Some(d)) => {
                Bxdf::RoughFilmStack(Rough::new(d, f.fresnel(tc, wl), r_s, t_s))
            }
        }
    }

    /// Whether light can pass through.
    pub fn transmits(&self) -> bool {
        match &self.interface {
            Interface::Dielectric { .. } | Interface::ThinSheet { .. } => true,
            Interface::Conductor(_) => false,
            Interface::Film(f) => f.transmits(),
            Interface::Stack(f) => f.transmits(),
        }
    }
}

/// `plastic` / `roughplastic` parameters.
#[derive(Clone, Debug)]
pub struct PlasticMaterial {
    /// The coat's distribution and α; `None`: smooth.
    pub rough: Option<(MicrofacetType, FloatTexture)>,
    pub eta: f32,
    pub diffuse_reflectance: SpectrumTexture,
    pub specular_reflectance: SpectrumTexture,
    pub nonlinear: bool,
    /// Cosine-weighted internal reflectance of the coating, F̄(1/η).
    pub fdr_int: f32,
}

/// A material.
#[derive(Clone, Debug)]
pub enum Material {
    /// `diffuse`.
    Diffuse { reflectance: SpectrumTexture },
    /// The interface plugins: `dielectric`, `roughdielectric`, `thindielectric`, `conductor`,
    /// `roughconductor`, `thinfilm`, `roughthinfilm`, `thinfilmconductor`,
    /// `roughthinfilmconductor` (and the thesis's aliases).
    Surface(Box<Surface>),
    /// `plastic`, `roughplastic`.
    Plastic(Box<PlasticMaterial>),
    /// `twosided`: `front` on both sides, or `back` on the back when given.
    TwoSided {
        front: Box<Material>,
        back: Option<Box<Material>>,
    },
    /// `bumpmap`: `inner` with its normal displaced by `scale`·`height` (see `bumpmap.rs`).
    BumpMap {
        height: FloatTexture,
        scale: f32,
        inner: Box<Material>,
    },
    /// `normalmap`: a tangent-space normal from an image or a `scales` relief.
    NormalMap {
        source: crate::texture::NormalSource,
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
        /// `rough_coat`: how a rough coat over a diffuse base is rendered.
        rough_coat: CoatModel,
    },
    /// `absorption` (see [`super::absorption`]).
    Absorption {
        reflectance: SpectrumTexture,
        sigma_a: SpectrumTexture,
        thickness: f32,
    },
    /// `null`: the surface only marks a boundary; paths pass through it unchanged.
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

impl Material {
    /// `diffuse` with the given reflectance (Mitsuba's default is 0.5).
    pub fn diffuse(reflectance: SpectrumTexture) -> Material {
        Material::Diffuse { reflectance }
    }
    /// `diffuse` with Mitsuba's defaults.
    pub fn default_diffuse() -> Material {
        Material::diffuse(SpectrumTexture::Constant(Spectrum::Constant(0.5)))
    }

    /// The BSDF at a shading point, and whether directions below the surface must be mirrored
    /// to the front (`twosided`). `front_side`: whether the ray arrives on the side the
    /// geometric normal points to (selects `back` of a `twosided` with two materials). `seed`
    /// feeds the random numbers of stochastic BSDFs (the layered walk), which hash it with the
    /// directions they are asked about; it should differ from vertex to vertex and path to path.
    pub fn eval(
        &self,
        tc: &TexCoord,
        wl: &SampledWavelengths,
        front_side: bool,
        seed: u64,
    ) -> (Bxdf, bool) {
        (self.bxdf(tc, wl, front_side, seed), self.is_two_sided())
    }

    /// Whether directions below the surface are mirrored to the front (`twosided`, possibly
    /// under a bump or normal map): the second half of [`Material::eval`].
    pub fn is_two_sided(&self) -> bool {
        match self {
            Material::TwoSided { .. } => true,
            Material::BumpMap { inner, .. } | Material::NormalMap { inner, .. } => {
                inner.is_two_sided()
            }
            _ => false,
        }
    }

    /// The BSDF at a shading point: the first half of [`Material::eval`]. The integrators call
    /// this and [`Material::is_two_sided`] rather than `eval`, so that the `Bxdf` (168 bytes)
    /// is built where it is stored: moving it through `eval`'s tuple and the layered stack's
    /// iterator cost 6 % of a render of the thin-film benchmark sphere in `memmove`.
    pub fn bxdf(
        &self,
        tc: &TexCoord,
        wl: &SampledWavelengths,
        front_side: bool,
        seed: u64,
    ) -> Bxdf {
        let sp = |t: &SpectrumTexture| t.eval(tc, wl);
        match self {
            Material::Diffuse { reflectance } => {
                Bxdf::Diffuse(DiffuseBxdf::new(sp(reflectance).clamp(0.0, 1.0)))
            }
            Material::Surface(s) => s.eval(tc, wl),
            Material::Plastic(p) => Bxdf::Plastic(PlasticBxdf::new(
                p.rough.as_ref().map(|(kind, a)| {
                    let a = a.eval(tc);
                    MicrofacetDistribution::new(*kind, a, a)
                }),
                p.eta,
                sp(&p.diffuse_reflectance).clamp(0.0, 1.0),
                sp(&p.specular_reflectance),
                p.fdr_int,
                p.nonlinear,
            )),
            Material::TwoSided { front, back } => {
                let m = match back {
                    Some(b) if !front_side => b,
                    _ => front,
                };
                m.bxdf(tc, wl, true, seed)
            }
            // Bump and normal maps change the frame (`shading_frame`), not the BSDF.
            Material::BumpMap { inner, .. } | Material::NormalMap { inner, .. } => {
                inner.bxdf(tc, wl, front_side, seed)
            }
            Material::Multilayered {
                surfaces,
                media,
                max_depth,
                closed_form,
                rough_coat,
            } => {
                let layer = |i: usize, m: &Material| m.bxdf(tc, wl, true, seed ^ (i as u64 + 1));
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
                let (cf, coat) = (*closed_form, *rough_coat);
                let stack = if let [top, base] = &surfaces[..] {
                    // Two layers, the closed form's case: evaluated in place and read by
                    // reference (see `bxdf`'s note on copies).
                    let (top, base) = (layer(0, top), layer(1, base));
                    match LayeredBxdf::closed(&top, &base, med, cf, coat, seed) {
                        Some(l) => Some(l),
                        None => LayeredBxdf::new([top, base], med, *max_depth, false, coat, seed),
                    }
                } else {
                    let ifs = surfaces.iter().enumerate().map(|(i, m)| layer(i, m));
                    LayeredBxdf::new(ifs, med, *max_depth, cf, coat, seed)
                };
                match stack {
                    Some(l) => Bxdf::Layered(l),
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
        }
    }

    /// Whether every lobe is a Dirac delta (no point in light sampling).
    pub fn has_delta_only(&self) -> bool {
        match self {
            Material::Surface(s) => s.rough.is_none(),
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
            Material::Surface(s) => s.transmits(),
            Material::Null => true,
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

impl std::default::Default for Material {
    /// Mitsuba's default BSDF: `diffuse` with reflectance 0.5.
    fn default() -> Material {
        Material::default_diffuse()
    }
}
