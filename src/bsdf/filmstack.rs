//! `filmstack`: an interface carrying an interference stack — N thin layers, each with its own
//! index (absorbing allowed) and thickness, between the outside and a dielectric or metal base:
//! Bragg mirrors, the keratin/air or keratin/melanin lamellae of iridescent scales, feathers
//! and beetle cuticle (Land 1972, "The physics and biology of animal reflectors"; Stavenga et
//! al. 2011 on bird and snake keratin). Exact per hero wavelength by the characteristic-matrix
//! method for s and p ([`crate::optics::filmstack`], checked against the `tmm` package), so a
//! stack gives what one film cannot: narrow, saturated reflection bands that move with angle.
//!
//! One plugin, one new Fresnel term ([`StackFresnel`]) for the two surfaces of
//! [`super::smooth`] and [`super::rough`]: smooth unless a roughness (`alpha`, or `alpha_u` and
//! `alpha_v`) is given; over a dielectric (`int_ior`) unless a metal is (`material`, or `eta`
//! and `k`). Sampling, weights and two-sidedness are those surfaces'; a stack of one layer is
//! the single film of `thinfilm` (its reflectance agrees to f32 rounding).
//!
//! Layers are written outside in, either as one string in `ophis thinfilm --stack` syntax —
//! `INDEX:NM` items, comma-separated, a periodic group `(INDEX:NM,…)xCOUNT`, indices a number,
//! `n+ki`, `keratin`, `cauchy(A,B)` or a name — or as indexed parameters `ior_0`,
//! `thickness_0`, `ior_1`, … (a thickness may be a texture), repeated `repeat` times:
//!
//! ```xml
//! <bsdf type="filmstack">                  <!-- a 10-pair Bragg mirror on glass -->
//!     <string name="stack" value="(2.3:59.8, 1.38:99.6)x10"/>
//!     <float name="int_ior" value="1.52"/>
//! </bsdf>
//! <bsdf type="filmstack">                  <!-- keratin lamellae varying from scale to scale -->
//!     <string name="ior_0" value="keratin"/> <float name="thickness_0" value="110"/>
//!     <float name="ior_1" value="1.0"/>      <float name="thickness_1" value="90"/>
//!     <integer name="repeat" value="5"/>
//!     <string name="int_ior" value="keratin"/>
//!     <texture type="per_scale" name="thickness_scale"> … </texture>
//! </bsdf>
//! ```
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `stack` | string | — | — | the layers outside in, `INDEX:NM,…`, groups `(…)xCOUNT` (as `ophis thinfilm --stack`) |
//! | `ior_i` | float or IOR name | — | — | index of layer i (instead of `stack`): a number, `n+ki`, `keratin`, `cauchy(A,B)`, a name |
//! | `thickness_i` | float or texture | required | nm | thickness of layer i; between 0 and 1000000 |
//! | `repeat` | integer | 1 | — | how many times the `ior_i`/`thickness_i` layers repeat; between 1 and 4096 |
//! | `thickness_scale` | float or texture | 1.0 | — | multiplies every thickness (e.g. a `per_scale` texture); between 0 and 1000 |
//! | `int_ior` | float or IOR name | `bk7` | — | a dielectric base: a number, `keratin`, `cauchy(A,B)` or a name |
//! | `material` | string | — | — | a metal base instead: a named metal (`Au`, `Ag`, `Cu`, `Al`, …) |
//! | `eta` | spectrum | — | — | a metal base instead: real part of its index (with `k`) |
//! | `k` | spectrum | — | — | imaginary part of the metal's index |
//! | `ext_ior` | float or IOR name | `air` | — | index of the outside (real) |
//! | `distribution` | string | `beckmann` | — | microfacet normal distribution; one of 'beckmann', 'ggx' |
//! | `alpha` | float or texture | 0.1 | RMS slope | roughness α; between 0 and 10 |
//! | `alpha_u` (0.6: `alphaU`) | float or texture | `alpha` | RMS slope | anisotropic α along ∂p/∂u; between 0 and 10 |
//! | `alpha_v` (0.6: `alphaV`) | float or texture | `alpha` | RMS slope | anisotropic α along ∂p/∂v; between 0 and 10 |
//! | `sample_visible` | boolean | true | — | accepted; visible normals are always sampled |
//! | `specular_reflectance` | spectrum or texture | 1.0 | — | factor on the reflected light (not physical) |
//! | `specular_transmittance` | spectrum or texture | 1.0 | — | factor on the transmitted light (not physical) |
//!
//! Known limits: refraction into the base uses its index at 550 nm (a dispersive base still
//! reflects and transmits exactly per wavelength, only the direction is shared); the outside is
//! lossless; layers are coherent (no incoherent thick layers); the stack is rebuilt at every
//! shading point when a layer's thickness is a texture (use `thickness_scale` to vary a whole
//! stack cheaply).

use super::fresnel::{Fresnel, Transmission};
use super::material::Interface;
use super::params::{surface, FACTORS, ROUGHNESS};
use super::Material;
use crate::optics::filmstack::{FilmStack, Layer, StackItem};
use crate::optics::ior::Ior;
use crate::optics::stackeval::StackEval;
use crate::optics::stackspec::parse_items;
use crate::plugin::{Args, Check, DefaultValue, Info, Param, Plugin, SceneError, Tag, Ty, Value};
use crate::spectrum::{ior as named_ior, SampledSpectrum, SampledWavelengths};
use crate::texture::{FloatTexture, TexCoord};

/// A stack's Fresnel term at one shading point: its constants at the path's wavelengths.
#[derive(Clone, Debug)]
pub struct StackFresnel {
    /// Boxed: the evaluator holds up to eight layers' constants inline (about 2 kB).
    pub eval: Box<StackEval>,
    pub transmission: Transmission,
}

impl Fresnel for StackFresnel {
    #[inline]
    fn reflectance(&self, cos: f32) -> (SampledSpectrum, f32) {
        let r = SampledSpectrum(self.eval.reflectance(cos.abs(), cos < 0.0)).clamp(0.0, 1.0);
        (r, r.average())
    }
    fn transmission(&self) -> Transmission {
        self.transmission
    }
}

/// The layers of a stack as a material holds them: fixed, or rebuilt per shading point when
/// a thickness is a texture.
#[derive(Clone, Debug)]
pub enum StackLayers {
    Fixed(FilmStack),
    /// Layers (index, thickness texture in nm) repeated `repeat` times between `ext` and `base`.
    Textured {
        ext: Ior,
        layers: Vec<(Ior, FloatTexture)>,
        repeat: u32,
        base: Ior,
    },
}

/// A film stack's parameters.
#[derive(Clone, Debug)]
pub struct StackSpec {
    pub layers: StackLayers,
    /// Multiplies every thickness (e.g. a `per_scale` texture).
    pub thickness_scale: FloatTexture,
    /// Relative index the base refracts with (at 550 nm), or `None` for a metal.
    pub refract: Option<f32>,
}

impl StackSpec {
    /// The stack's Fresnel term at a point for the path's wavelengths.
    pub(crate) fn fresnel(&self, tc: &TexCoord, wl: &SampledWavelengths) -> StackFresnel {
        let scale = self.thickness_scale.eval(tc);
        let eval = match &self.layers {
            StackLayers::Fixed(s) => s.prepare(wl.lambda, scale),
            StackLayers::Textured {
                ext,
                layers,
                repeat,
                base,
            } => {
                let period = layers
                    .iter()
                    .map(|(ior, d)| Layer::new(ior.clone(), d.eval(tc).max(0.0) as f64))
                    .collect();
                let item = StackItem::Periodic {
                    period,
                    count: *repeat,
                };
                match FilmStack::new(ext.clone(), vec![item], base.clone()) {
                    Ok(s) => s.prepare(wl.lambda, scale),
                    // Only a non-finite texture value can fail here: fall back to no layers.
                    Err(_) => FilmStack::new(ext.clone(), vec![], base.clone())
                        .expect("a bare interface is valid")
                        .prepare(wl.lambda, scale),
                }
            }
        };
        StackFresnel {
            eval: Box::new(eval),
            transmission: match self.refract {
                Some(eta) => Transmission::Refract { eta },
                None => Transmission::Absorbed,
            },
        }
    }

    /// Whether light can pass through (a dielectric base).
    pub(crate) fn transmits(&self) -> bool {
        self.refract.is_some()
    }
}

/// The `filmstack` plugin.
pub(crate) const PLUGIN: Plugin<Material> = Plugin {
    info: Info {
        name: "filmstack",
        aliases: &[],
        tag: Tag::Bsdf,
        summary:
            "an interference stack of N thin layers on a dielectric or a metal, smooth or rough",
        params: &[STACK, BASE, ROUGHNESS, FACTORS],
        file: file!(),
    },
    load,
};

const STACK: &[Param] = &[
    Param::new("stack", Ty::String, DefaultValue::None).doc(
        "the layers outside in, `INDEX:NM,…`, groups `(…)xCOUNT` (as `ophis thinfilm --stack`)",
    ),
    Param::new("ior_i", Ty::Ior, DefaultValue::None).doc(
        "index of layer i (instead of `stack`): a number, `n+ki`, `keratin`, `cauchy(A,B)`, a name",
    ),
    Param::new("thickness_i", Ty::FloatTexture, DefaultValue::Required)
        .check(Check::Range(0.0, 1e6))
        .unit("nm")
        .doc("thickness of layer i"),
    Param::int("repeat", 1)
        .check(Check::Range(1.0, 4096.0))
        .doc("how many times the `ior_i`/`thickness_i` layers repeat"),
    Param::new(
        "thickness_scale",
        Ty::FloatTexture,
        DefaultValue::Float(1.0),
    )
    .check(Check::Range(0.0, 1e3))
    .doc("multiplies every thickness (e.g. a `per_scale` texture)"),
];

const BASE: &[Param] = &[
    Param::new("int_ior", Ty::Ior, DefaultValue::Str("bk7"))
        .doc("a dielectric base: a number, `keratin`, `cauchy(A,B)` or a name"),
    Param::new("material", Ty::String, DefaultValue::None)
        .doc("a metal base instead: a named metal (`Au`, `Ag`, `Cu`, `Al`, …)"),
    Param::new(
        "eta",
        Ty::Spectrum(crate::plugin::SpectrumKind::Unbounded),
        DefaultValue::None,
    )
    .doc("a metal base instead: real part of its index (with `k`)"),
    Param::new(
        "k",
        Ty::Spectrum(crate::plugin::SpectrumKind::Unbounded),
        DefaultValue::None,
    )
    .doc("imaginary part of the metal's index"),
    Param::new("ext_ior", Ty::Ior, DefaultValue::Str("air")).doc("index of the outside (real)"),
];

/// An index written as a number or a string (`keratin`, `n+ki`, `cauchy(A,B)`, a name).
fn index(a: &Args, name: &str) -> Result<Option<Ior>, SceneError> {
    let v = match a.value(name)? {
        None => return Ok(None),
        Some(Value::Float(v)) => Ior::real(*v),
        Some(Value::Integer(v)) => Ior::real(*v as f64),
        Some(Value::String(s)) => Ior::parse(s),
        Some(_) => return Err(a.error(name, "must be a number or an index such as 'keratin'")),
    };
    v.map(Some).map_err(|e| a.error(name, e))
}

/// The base: a metal (`material`, or `eta` and `k`) or a dielectric (`int_ior`).
fn base(a: &Args) -> Result<(Ior, Option<f32>), SceneError> {
    if a.has("eta") || a.has("k") {
        let (eta, k) = (a.spectrum_opt("eta")?, a.spectrum_opt("k")?);
        let (Some(eta), Some(k)) = (eta, k) else {
            return Err(a.error("eta", "a metal base needs both 'eta' and 'k'"));
        };
        let rows: Vec<(f64, f64, f64)> = (360..=830)
            .step_by(5)
            .map(|l| (l as f64, eta.eval(l as f32) as f64, k.eval(l as f32) as f64))
            .collect();
        let ior = Ior::table(None, &rows).map_err(|e| a.error("eta", e))?;
        return Ok((ior, None));
    }
    if let Some(name) = a.string_opt("material")? {
        let ior = Ior::named(&name).ok_or_else(|| {
            a.error(
                "material",
                format!(
                    "unknown metal '{name}'{} (known: {})",
                    crate::plugin::did_you_mean(
                        &name,
                        named_ior::conductor_names().iter().copied()
                    ),
                    named_ior::conductor_names().join(", ")
                ),
            )
        })?;
        return Ok((ior, None));
    }
    let ior = match index(a, "int_ior")? {
        Some(i) => i,
        None => Ior::named("bk7").expect("bk7 is a named index"),
    };
    let ext = index(a, "ext_ior")?.unwrap_or(Ior::Real(1.000277));
    let eta = (ior.at(550.0).re / ext.at(550.0).re) as f32;
    Ok((ior, Some(eta)))
}

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let ext = index(a, "ext_ior")?.unwrap_or(Ior::Real(1.000277));
    if !ext.is_lossless() {
        return Err(a.error("ext_ior", "the outside must be lossless (a real index)"));
    }
    let (base_ior, refract) = base(a)?;
    let n_indexed = (0..).take_while(|i| a.has(&format!("ior_{i}"))).count();
    let layers = match (a.string_opt("stack")?, n_indexed) {
        (Some(_), n) if n > 0 => {
            return Err(a.error(
                "stack",
                "give 'stack' or 'ior_0', 'thickness_0', …, not both",
            ))
        }
        (Some(spec), _) => {
            let items = parse_items(&spec).map_err(|e| a.error("stack", e))?;
            let s = FilmStack::new(ext, items, base_ior).map_err(|e| a.error("stack", e))?;
            StackLayers::Fixed(s)
        }
        (None, 0) => {
            return Err(SceneError::at(
                &a.node().loc,
                format!(
                    "{} needs its layers: 'stack' (e.g. \"(2.3:60,1.38:100)x10\") or 'ior_0' and \
                     'thickness_0', …",
                    a.describe()
                ),
            ))
        }
        (None, n) => {
            let mut layers = Vec::with_capacity(n);
            for i in 0..n {
                let ior = index(a, &format!("ior_{i}"))?.expect("counted above");
                layers.push((ior, a.float_texture(&format!("thickness_{i}"))?));
            }
            let repeat = a.u32("repeat")?;
            let constant: Option<Vec<Layer>> = layers
                .iter()
                .map(|(ior, d)| match d {
                    FloatTexture::Constant(v) => Some(Layer::new(ior.clone(), *v as f64)),
                    _ => None,
                })
                .collect();
            match constant {
                Some(period) => {
                    let item = StackItem::Periodic {
                        period,
                        count: repeat,
                    };
                    let s = FilmStack::new(ext, vec![item], base_ior)
                        .map_err(|e| a.error("repeat", e))?;
                    StackLayers::Fixed(s)
                }
                None => StackLayers::Textured {
                    ext,
                    layers,
                    repeat,
                    base: base_ior,
                },
            }
        }
    };
    let spec = StackSpec {
        layers,
        thickness_scale: a.float_texture("thickness_scale")?,
        refract,
    };
    let rough = a.has("alpha") || a.has("alpha_u") || a.has("alpha_v");
    surface(a, Interface::Stack(Box::new(spec)), rough)
}
