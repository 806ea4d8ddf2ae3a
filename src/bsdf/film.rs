//! The parameters of a thin film on an interface (what the four film plugins `thinfilm`,
//! `roughthinfilm`, `thinfilmconductor`, `roughthinfilmconductor` and the thesis's plugins
//! share), turned into the film's Fresnel term ([`FilmFresnel`]) at each shading point, and the
//! loader pieces those plugins share.

use super::filmfresnel::{FilmFresnel, FilmMode, FilmSamples, THESIS_LAMBDA};
use crate::plugin::{Args, Check, DefaultValue, Param, SceneError, Ty, Value};
use crate::spectrum::ior::keratin_ior;
use crate::spectrum::{ior as named_ior, SampledWavelengths, Spectrum};
use crate::texture::{FloatTexture, TexCoord};

/// Default film index (OpenPBR's `thin_film_ior`).
pub(crate) const DEFAULT_FILM_IOR: f32 = 1.4;
/// Default film thickness in nm (OpenPBR's `thin_film_thickness`, 0.5 µm).
pub(crate) const DEFAULT_FILM_THICKNESS: f32 = 500.0;
/// Film thickness of the thesis's Mitsuba 0.6 plugins when none is given (nm).
pub(crate) const THESIS_PLUGIN_FILM_THICKNESS: f32 = 400.0;
/// Largest film thickness accepted (nm): 100 µm is far beyond a coherent film already.
pub(crate) const MAX_FILM_THICKNESS: f32 = 1e5;

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

/// A film's parameters (textures not yet looked up).
#[derive(Clone, Debug)]
pub struct FilmSpec {
    pub base: FilmBase,
    pub ext_ior: f32,
    pub film_ior: FilmIor,
    /// Thickness in nm.
    pub thickness: FloatTexture,
    pub mode: FilmMode,
}

impl FilmSpec {
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
    pub(crate) fn fresnel(&self, tc: &TexCoord, wl: &SampledWavelengths) -> FilmFresnel {
        let d = self.thickness.eval(tc);
        FilmFresnel {
            ext: self.ext_ior,
            d_nm: if d.is_finite() { d.max(0.0) } else { 0.0 },
            spectral: self.samples(wl.lambda),
            // Only the thesis mode reads these; a spectral film (made at every shading point)
            // does not evaluate its indices at three more wavelengths.
            thesis: match self.mode {
                FilmMode::Thesis => self.samples(THESIS_LAMBDA),
                FilmMode::Spectral => FilmSamples {
                    lambda: THESIS_LAMBDA,
                    film: [0.0; 3],
                    base_n: [0.0; 3],
                    base_k: [0.0; 3],
                },
            },
            mode: self.mode,
        }
    }

    /// Whether light can pass through (a dielectric base).
    pub(crate) fn transmits(&self) -> bool {
        matches!(self.base, FilmBase::Dielectric { .. })
    }
}

/// `film_ior`: the film's index (a number, `keratin`, or a named dielectric).
pub(crate) const FILM_IOR: Param =
    Param::new("film_ior", Ty::Ior, DefaultValue::Float(DEFAULT_FILM_IOR))
        .also(&["medium_ior"])
        .doc("index of the film; `keratin` = 1.532 + 5890/λ² (λ in nm)");
/// `film_thickness` in nm, a number or a float texture.
pub(crate) const FILM_THICKNESS: Param = Param::new(
    "film_thickness",
    Ty::FloatTexture,
    DefaultValue::Float(DEFAULT_FILM_THICKNESS),
)
.also(&["thickness"])
.check(Check::Range(0.0, MAX_FILM_THICKNESS as f64))
.unit("nm")
.doc("thickness of the film");
/// `mode`: exact spectral film or the thesis's RGB point samples.
pub(crate) const MODE: Param = Param::string("mode", "spectral")
    .check(Check::OneOf(&["spectral", "thesis"]))
    .doc("`thesis`: the thesis's 650/510/475 nm point samples and phase term");
/// The thesis plugins' film index: `mediumIOR`, default BK7.
pub(crate) const THESIS_MEDIUM_IOR: Param = FILM_IOR
    .named("medium_ior")
    .also(&["film_ior"])
    .v06("mediumIOR")
    .default(DefaultValue::Str("bk7"));
/// The thesis plugins' `thickness`, default 400 nm.
pub(crate) const THESIS_THICKNESS: Param = FILM_THICKNESS
    .named("thickness")
    .also(&["film_thickness"])
    .default(DefaultValue::Float(THESIS_PLUGIN_FILM_THICKNESS));

/// Reads a film from a film plugin's node: its index, thickness and mode over `base`.
pub(crate) fn load_film(a: &mut Args, base: FilmBase) -> Result<FilmSpec, SceneError> {
    let film_ior = match a.value("film_ior")? {
        Some(Value::String(s)) if s == "keratin" => FilmIor::Keratin,
        _ => FilmIor::Constant(a.ior("film_ior")?),
    };
    let mode = match a.string("mode")?.as_str() {
        "thesis" => FilmMode::Thesis,
        _ => FilmMode::Spectral,
    };
    Ok(FilmSpec {
        base,
        ext_ior: a.ior("ext_ior")?,
        film_ior,
        thickness: a.float_texture("film_thickness")?,
        mode,
    })
}

/// A metal under a film: `eta` and `k`, or a named `material` (`none` is refused: a perfect
/// mirror has no complex index).
pub(crate) fn load_metal(a: &Args) -> Result<FilmBase, SceneError> {
    if a.has("eta") || a.has("k") {
        return Ok(FilmBase::Conductor {
            eta: a.spectrum("eta")?,
            k: a.spectrum("k")?,
        });
    }
    let name = a.string("material")?;
    let (eta, k) = named_ior::conductor_nk(&name).ok_or_else(|| {
        a.error(
            "material",
            format!(
                "unknown metal '{name}' under the film (known: {}; a perfect mirror 'none' has \
                 no complex index)",
                named_ior::conductor_names().join(", ")
            ),
        )
    })?;
    Ok(FilmBase::Conductor { eta, k })
}

/// A film's parameters (OpenPBR's defaults).
pub(crate) const FILM: &[Param] = &[FILM_IOR, FILM_THICKNESS, MODE];
/// The thesis plugins' film parameters (their names and defaults).
pub(crate) const THESIS_FILM: &[Param] = &[THESIS_MEDIUM_IOR, THESIS_THICKNESS, MODE];
/// The thesis plugins' dielectric base: diamond under air.
pub(crate) const THESIS_DIELECTRIC_IORS: &[Param] = &[
    super::params::INT_IOR.default(DefaultValue::Str("diamond")),
    super::params::EXT_IOR,
];
/// A metal under a film (Mitsuba 0.6's default copper: a film over a perfect mirror has no
/// complex index to work with).
pub(crate) const METAL_UNDER_FILM: &[Param] = &[
    super::params::MATERIAL
        .default(DefaultValue::Str("Cu"))
        .doc("a named metal (`Au`, `Ag`, `Cu`, `Al`, … 71 of Mitsuba's); `none` is refused"),
    super::params::ETA,
    super::params::K,
    super::params::EXT_IOR,
];

/// A film plugin: a film over a dielectric (`int_ior`) or over a metal, smooth or rough.
pub(crate) fn load_film_surface(
    a: &mut Args,
    metal: bool,
    rough: bool,
) -> Result<super::Material, SceneError> {
    let base = if metal {
        load_metal(a)?
    } else {
        FilmBase::Dielectric {
            int_ior: a.ior("int_ior")?,
        }
    };
    let film = load_film(a, base)?;
    super::params::surface(a, super::Interface::Film(Box::new(film)), rough)
}
