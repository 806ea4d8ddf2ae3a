//! Parameters and loader pieces that several BSDF plugins share (declared once here, so that
//! every plugin that takes `int_ior` documents and reads it the same way).

use super::fresnel::ConductorFresnel;
use super::material::{ConductorIor, Interface, Material, Roughness, Surface};
use super::microfacet::MicrofacetType;
use crate::plugin::{Args, Check, DefaultValue, Param, SceneError, SpectrumKind, Ty};
use crate::spectrum::{ior as named_ior, SampledWavelengths, Spectrum};
use crate::texture::SpectrumTexture;

/// Interior index of the dielectric plugins (BK7).
pub(crate) const INT_IOR: Param = Param::new("int_ior", Ty::Ior, DefaultValue::Str("bk7"))
    .v06("intIOR")
    .doc("index of the interior");
/// Exterior index (air).
pub(crate) const EXT_IOR: Param = Param::new("ext_ior", Ty::Ior, DefaultValue::Str("air"))
    .v06("extIOR")
    .doc("index of the exterior");
/// A metal's exterior index: Mitsuba 0.6 called it `extEta`.
pub(crate) const EXT_IOR_METAL: Param = Param::new("ext_ior", Ty::Ior, DefaultValue::Str("air"))
    .also(&["ext_eta"])
    .v06("extEta")
    .doc("index of the medium outside the metal");
/// Non-physical factor on reflection.
pub(crate) const SPECULAR_REFLECTANCE: Param = Param::reflectance("specular_reflectance", 1.0)
    .doc("factor on the reflected light (not physical)");
/// Non-physical factor on transmission.
pub(crate) const SPECULAR_TRANSMITTANCE: Param = SPECULAR_REFLECTANCE
    .named("specular_transmittance")
    .doc("factor on the transmitted light (not physical)");
/// Microfacet distribution.
pub(crate) const DISTRIBUTION: Param = Param::string("distribution", "beckmann")
    .check(Check::OneOf(&["beckmann", "ggx"]))
    .doc("microfacet normal distribution");
/// Isotropic roughness.
pub(crate) const ALPHA: Param = Param::new("alpha", Ty::FloatTexture, DefaultValue::Float(0.1))
    .check(Check::Range(0.0, 10.0))
    .unit("RMS slope")
    .doc("roughness α");
/// Roughness along the tangent.
pub(crate) const ALPHA_U: Param = Param::new(
    "alpha_u",
    Ty::FloatTexture,
    DefaultValue::Derived("`alpha`"),
)
.check(Check::Range(0.0, 10.0))
.v06("alphaU")
.unit("RMS slope")
.doc("anisotropic α along ∂p/∂u");
/// Roughness along the bitangent.
pub(crate) const ALPHA_V: Param = ALPHA_U
    .named("alpha_v")
    .v06("alphaV")
    .doc("anisotropic α along ∂p/∂v");
/// Visible-normal sampling is always on; accepted for Mitsuba's scenes.
pub(crate) const SAMPLE_VISIBLE: Param =
    Param::bool("sample_visible", true).doc("accepted; visible normals are always sampled");
/// A named metal, or `none` for a perfect mirror.
pub(crate) const MATERIAL: Param = Param::string("material", "none")
    .doc("a named metal (`Au`, `Ag`, `Cu`, `Al`, … 71 of Mitsuba's) or `none` (a perfect mirror)");
/// Real part of a metal's index.
pub(crate) const ETA: Param = Param::new(
    "eta",
    Ty::Spectrum(SpectrumKind::Unbounded),
    DefaultValue::Float(0.0),
)
.doc("real part of the metal's index (with `k`, instead of `material`)");
/// Imaginary part of a metal's index.
pub(crate) const K: Param = ETA
    .named("k")
    .default(DefaultValue::Float(1.0))
    .doc("imaginary part (extinction) of the metal's index");

/// `distribution` and `alpha`, or `alpha_u` + `alpha_v` (floats or textures).
pub(crate) fn roughness(a: &mut Args) -> Result<Roughness, SceneError> {
    let distribution = match a.string("distribution")?.as_str() {
        "ggx" => MicrofacetType::Ggx,
        _ => MicrofacetType::Beckmann,
    };
    a.bool("sample_visible")?;
    let alpha = a.float_texture("alpha")?;
    let (alpha_u, alpha_v) = if a.has("alpha_u") || a.has("alpha_v") {
        let au = if a.has("alpha_u") {
            a.float_texture("alpha_u")?
        } else {
            alpha.clone()
        };
        let av = if a.has("alpha_v") {
            a.float_texture("alpha_v")?
        } else {
            alpha
        };
        (au, av)
    } else {
        (alpha.clone(), alpha)
    };
    Ok(Roughness {
        distribution,
        alpha_u,
        alpha_v,
    })
}

/// A conductor's complex index: `eta` and `k`, or a named `material` (`None`: a mirror).
pub(crate) fn conductor_ior(a: &Args) -> Result<Option<ConductorIor>, SceneError> {
    let ext_ior = a.ior("ext_ior")?;
    if a.has("eta") || a.has("k") {
        return Ok(Some(ConductorIor {
            eta: a.spectrum("eta")?,
            k: a.spectrum("k")?,
            ext_ior,
        }));
    }
    let name = a.string("material")?;
    if name == "none" {
        return Ok(None);
    }
    let (eta, k) = named_ior::conductor_nk(&name).ok_or_else(|| {
        let near = crate::plugin::nearest(&name, named_ior::conductor_names().iter().copied());
        let hint = match near.first() {
            Some(n) => format!(" (did you mean '{n}'?)"),
            None => String::new(),
        };
        a.error(
            "material",
            format!(
                "unknown conductor '{name}'{hint}; known: none, {}",
                named_ior::conductor_names().join(", ")
            ),
        )
    })?;
    Ok(Some(ConductorIor { eta, k, ext_ior }))
}

/// The Fresnel term of a conductor at the path's wavelengths.
pub(crate) fn conductor_fresnel(
    ior: &Option<ConductorIor>,
    wl: &SampledWavelengths,
) -> ConductorFresnel {
    match ior {
        None => ConductorFresnel::Mirror,
        Some(c) => ConductorFresnel::Complex {
            eta: c.eta.sample(wl) / c.ext_ior,
            k: c.k.sample(wl) / c.ext_ior,
        },
    }
}

/// The indices of a dielectric boundary.
pub(crate) const DIELECTRIC_IORS: &[Param] = &[INT_IOR, EXT_IOR];
/// Both non-physical factors.
pub(crate) const FACTORS: &[Param] = &[SPECULAR_REFLECTANCE, SPECULAR_TRANSMITTANCE];
/// The reflection factor of surfaces that only reflect.
pub(crate) const REFLECTION_FACTOR: &[Param] = &[SPECULAR_REFLECTANCE];
/// A microfacet roughness.
pub(crate) const ROUGHNESS: &[Param] = &[DISTRIBUTION, ALPHA, ALPHA_U, ALPHA_V, SAMPLE_VISIBLE];
/// A metal (Mitsuba 3's default: a perfect mirror).
pub(crate) const METAL: &[Param] = &[MATERIAL, ETA, K, EXT_IOR_METAL];

/// A [`Surface`] material from `interface`, rough when `rough`, with the factors the plugin
/// declares (transmission factor 1 when it declares none).
pub(crate) fn surface(
    a: &mut Args,
    interface: Interface,
    rough: bool,
) -> Result<Material, SceneError> {
    let rough = if rough { Some(roughness(a)?) } else { None };
    let specular_transmittance = if a.info().param("specular_transmittance").is_some() {
        a.spectrum_texture("specular_transmittance")?
    } else {
        SpectrumTexture::Constant(Spectrum::Constant(1.0))
    };
    Ok(Material::Surface(Box::new(Surface {
        interface,
        rough,
        specular_reflectance: a.spectrum_texture("specular_reflectance")?,
        specular_transmittance,
    })))
}

/// The relative index `int_ior / ext_ior` of a dielectric boundary.
pub(crate) fn relative_ior(a: &Args) -> Result<f32, SceneError> {
    Ok(a.ior("int_ior")? / a.ior("ext_ior")?)
}
