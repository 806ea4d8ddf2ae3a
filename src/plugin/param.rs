//! Parameter declarations: what a plugin reads, written once.
//!
//! A [`Param`] names a parameter (its XML name, other accepted spellings, its Mitsuba 0.6
//! spelling), says how it is written ([`Ty`]), what it defaults to ([`Default`]), what values
//! are allowed ([`Check`]), its unit and one line of documentation. [`super::Args`] reads
//! through it; `ophis plugins` prints it; the manuals are checked against it.

use super::values::SpectrumKind;
use super::{Args, SceneError, Tag};
use std::fmt::Write as _;

/// How a parameter is written in a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    Float,
    Integer,
    Boolean,
    String,
    Point,
    Vector,
    Transform,
    /// A `<float>`, `<rgb>`, `<spectrum>` or `<blackbody>` value of the given kind.
    Spectrum(SpectrumKind),
    /// A spectrum value or a nested/referenced texture.
    SpectrumTexture(SpectrumKind),
    /// A float or a nested/referenced texture.
    FloatTexture,
    /// A positive number or a named index of refraction (`bk7`, `water`, …).
    Ior,
    /// A nested or referenced BSDF.
    Bsdf,
    /// A nested or referenced texture (no plain value).
    Texture,
    /// A nested object of another kind (`phase`, `film`, …).
    Object(Tag),
}

impl Ty {
    /// How the manual names the type.
    pub fn describe(self) -> &'static str {
        match self {
            Ty::Float => "float",
            Ty::Integer => "integer",
            Ty::Boolean => "boolean",
            Ty::String => "string",
            Ty::Point => "point",
            Ty::Vector => "vector",
            Ty::Transform => "transform",
            Ty::Spectrum(_) => "spectrum",
            Ty::SpectrumTexture(_) => "spectrum or texture",
            Ty::FloatTexture => "float or texture",
            Ty::Ior => "float or IOR name",
            Ty::Bsdf => "bsdf",
            Ty::Texture => "texture",
            Ty::Object(t) => t.as_str(),
        }
    }
}

/// A parameter's default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DefaultValue {
    /// Optional; absent means "not given" (the loader decides, the manual says how).
    None,
    /// Must be given.
    Required,
    Float(f32),
    Int(i64),
    Bool(bool),
    /// A point, (x, y, z).
    Point([f32; 3]),
    /// A string, or the name of an index of refraction for [`Ty::Ior`].
    Str(&'static str),
    /// Documented only: the value follows from other parameters (e.g. "`alpha`").
    Derived(&'static str),
}

impl DefaultValue {
    /// How the manual writes the default.
    pub fn describe(&self) -> String {
        match self {
            DefaultValue::None => "—".into(),
            DefaultValue::Required => "required".into(),
            DefaultValue::Float(v) => format_float(*v),
            DefaultValue::Int(v) => v.to_string(),
            DefaultValue::Bool(v) => v.to_string(),
            DefaultValue::Point([x, y, z]) => format!("({x}, {y}, {z})"),
            DefaultValue::Str(s) => format!("`{s}`"),
            DefaultValue::Derived(s) => (*s).into(),
        }
    }
}

fn format_float(v: f32) -> String {
    let s = format!("{v}");
    if s.contains('e') || s.contains('.') || s.contains("inf") || s.contains("NaN") {
        s
    } else {
        format!("{s}.0")
    }
}

/// Which values a numeric or string parameter accepts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Check {
    /// Any finite value (strings: any).
    Any,
    /// Finite and > 0.
    Positive,
    /// Finite and ≥ 0.
    NonNegative,
    /// In `lo..=hi`.
    Range(f64, f64),
    /// In `lo < v < hi`.
    Open(f64, f64),
    /// In `lo < v ≤ hi`.
    OpenClosed(f64, f64),
    /// In `lo ≤ v < hi`.
    ClosedOpen(f64, f64),
    /// One of these strings.
    OneOf(&'static [&'static str]),
}

impl Check {
    /// Whether a number passes.
    pub fn accepts(&self, v: f64) -> bool {
        match *self {
            Check::Any | Check::OneOf(_) => v.is_finite(),
            Check::Positive => v > 0.0 && v.is_finite(),
            Check::NonNegative => v >= 0.0 && v.is_finite(),
            Check::Range(lo, hi) => (lo..=hi).contains(&v),
            Check::Open(lo, hi) => v > lo && v < hi,
            Check::OpenClosed(lo, hi) => v > lo && v <= hi,
            Check::ClosedOpen(lo, hi) => v >= lo && v < hi,
        }
    }

    /// What the check asks for, as the end of "must be …"; `None` when anything finite goes.
    pub fn describe(&self) -> Option<String> {
        Some(match *self {
            Check::Any => return None,
            Check::Positive => "positive".into(),
            Check::NonNegative => "non-negative".into(),
            Check::Range(lo, hi) => format!("between {lo} and {hi}"),
            Check::Open(lo, hi) => format!("strictly between {lo} and {hi}"),
            Check::OpenClosed(lo, hi) => format!("in ({lo}, {hi}]"),
            Check::ClosedOpen(lo, hi) => format!("in [{lo}, {hi})"),
            Check::OneOf(v) => {
                let q: Vec<String> = v.iter().map(|s| format!("'{s}'")).collect();
                format!("one of {}", q.join(", "))
            }
        })
    }
}

/// One declared parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    /// The XML name (Mitsuba 3 spelling, snake_case).
    pub name: &'static str,
    /// Other accepted spellings (e.g. the seed plugins' names); giving two of them is an error.
    pub also: &'static [&'static str],
    /// How Mitsuba 0.6 scenes write it, when that differs from `name` (0.6 scenes are upgraded
    /// from camelCase on load, so this is for the manual).
    pub v06: &'static str,
    pub ty: Ty,
    pub default: DefaultValue,
    pub check: Check,
    pub unit: &'static str,
    pub doc: &'static str,
}

impl Param {
    /// A parameter of type `ty` with default `default` (no check, unit or doc yet).
    pub const fn new(name: &'static str, ty: Ty, default: DefaultValue) -> Param {
        Param {
            name,
            also: &[],
            v06: "",
            ty,
            default,
            check: Check::Any,
            unit: "",
            doc: "",
        }
    }
    /// A float with a default.
    pub const fn float(name: &'static str, default: f32) -> Param {
        Param::new(name, Ty::Float, DefaultValue::Float(default))
    }
    /// A point in the shape's own coordinates, with a default; read by
    /// [`Args::point`](super::Args::point).
    pub const fn object_point(name: &'static str, default: [f32; 3]) -> Param {
        Param::new(name, Ty::Point, DefaultValue::Point(default)).unit("object space")
    }
    /// A positive distance in world units, with a default.
    pub const fn length(name: &'static str, default: f32) -> Param {
        Param::float(name, default)
            .check(Check::Positive)
            .unit("world units")
    }
    /// An angle written in degrees, with a default (degrees); read in radians by
    /// [`Args::angle`](super::Args::angle).
    pub const fn angle(name: &'static str, default: f32) -> Param {
        Param::float(name, default).unit("degrees")
    }
    /// A float in (0, `hi`], in `unit` (world units, pixels, or a fraction of something: the
    /// unit says of what), with a default.
    pub const fn up_to(name: &'static str, default: f32, hi: f64, unit: &'static str) -> Param {
        Param::float(name, default)
            .check(Check::OpenClosed(0.0, hi))
            .unit(unit)
    }
    /// A fraction in [0, 1], with a default.
    pub const fn fraction(name: &'static str, default: f32) -> Param {
        Param::float(name, default).check(Check::Range(0.0, 1.0))
    }
    /// An integer with a default.
    pub const fn int(name: &'static str, default: i64) -> Param {
        Param::new(name, Ty::Integer, DefaultValue::Int(default))
    }
    /// An integer between 0 and 2³² − 1 (a seed, an index), with a default; read by
    /// [`Args::u32`](super::Args::u32).
    pub const fn u32(name: &'static str, default: u32) -> Param {
        Param::int(name, default as i64).check(Check::Range(0.0, u32::MAX as f64))
    }
    /// A boolean with a default.
    pub const fn bool(name: &'static str, default: bool) -> Param {
        Param::new(name, Ty::Boolean, DefaultValue::Bool(default))
    }
    /// A string with a default.
    pub const fn string(name: &'static str, default: &'static str) -> Param {
        Param::new(name, Ty::String, DefaultValue::Str(default))
    }
    /// An emitted quantity: a spectrum read as an illuminant (RGB and plain numbers are times
    /// D65, as in Mitsuba's spectral variants), 1 by default.
    pub const fn emission(name: &'static str) -> Param {
        Param::new(
            name,
            Ty::Spectrum(SpectrumKind::Illuminant),
            DefaultValue::Float(1.0),
        )
    }
    /// A reflectance in [0, 1]: a colour, a number or a texture, with a default.
    pub const fn reflectance(name: &'static str, default: f32) -> Param {
        Param::new(
            name,
            Ty::SpectrumTexture(SpectrumKind::Albedo),
            DefaultValue::Float(default),
        )
    }
    /// A colour in [0, 1] (no texture), with a default.
    pub const fn colour(name: &'static str, default: f32) -> Param {
        Param::new(
            name,
            Ty::Spectrum(SpectrumKind::Albedo),
            DefaultValue::Float(default),
        )
    }
    /// A non-negative spectral coefficient (absorption, extinction): a spectrum, a number or a
    /// texture, with a default.
    pub const fn coefficient(name: &'static str, default: f32) -> Param {
        Param::new(
            name,
            Ty::SpectrumTexture(SpectrumKind::Unbounded),
            DefaultValue::Float(default),
        )
    }
    /// Other accepted spellings.
    pub const fn also(mut self, names: &'static [&'static str]) -> Param {
        self.also = names;
        self
    }
    /// The Mitsuba 0.6 spelling, for the manual.
    pub const fn v06(mut self, name: &'static str) -> Param {
        self.v06 = name;
        self
    }
    /// Accepted values.
    pub const fn check(mut self, check: Check) -> Param {
        self.check = check;
        self
    }
    /// The unit, for the manual ("nm", "world units", "degrees", …).
    pub const fn unit(mut self, unit: &'static str) -> Param {
        self.unit = unit;
        self
    }
    /// One line of documentation.
    pub const fn doc(mut self, doc: &'static str) -> Param {
        self.doc = doc;
        self
    }
    /// The same parameter under another name (a variant's spelling), without its other
    /// spellings.
    pub const fn named(mut self, name: &'static str) -> Param {
        self.name = name;
        self.also = &[];
        self
    }
    /// A different default (for plugin variants sharing a declaration).
    pub const fn default(mut self, default: DefaultValue) -> Param {
        self.default = default;
        self
    }

    /// All names this parameter may be written under.
    pub fn names(&self) -> impl Iterator<Item = &'static str> + '_ {
        std::iter::once(self.name).chain(self.also.iter().copied())
    }
}

/// What a plugin is: its names, kind, one-line summary, declared parameters and source file.
#[derive(Clone, Copy, Debug)]
pub struct Info {
    /// The `type` written in scenes.
    pub name: &'static str,
    /// Other names that load the same plugin with the same parameters.
    pub aliases: &'static [&'static str],
    /// The element it appears as.
    pub tag: Tag,
    /// One line for listings.
    pub summary: &'static str,
    /// Declared parameters, in groups (so that groups several plugins share — roughness,
    /// indices — are declared once), in the order the manual lists them.
    pub params: &'static [&'static [Param]],
    /// The source file whose `//!` header is the plugin's manual (`file!()`).
    pub file: &'static str,
}

impl Info {
    /// A plugin called `name` appearing as `tag`, declared in `file` (`file!()`), with no aliases.
    pub const fn new(
        tag: Tag,
        name: &'static str,
        summary: &'static str,
        params: &'static [&'static [Param]],
        file: &'static str,
    ) -> Info {
        Info {
            name,
            aliases: &[],
            tag,
            summary,
            params,
            file,
        }
    }

    /// Other names that load the same plugin.
    pub const fn aliases(mut self, aliases: &'static [&'static str]) -> Info {
        self.aliases = aliases;
        self
    }

    /// The declared parameter under any of its spellings; an indexed declaration `x_i`
    /// matches `x_0`, `x_1`, ….
    pub(crate) fn param(&self, name: &str) -> Option<&'static Param> {
        let indexed = |n: &str| {
            n.strip_suffix("_i").is_some_and(|prefix| {
                name.strip_prefix(prefix)
                    .and_then(|rest| rest.strip_prefix('_'))
                    .is_some_and(|i| !i.is_empty() && i.bytes().all(|b| b.is_ascii_digit()))
            })
        };
        self.all_params()
            .find(|p| p.names().any(|n| n == name || indexed(n)))
    }

    /// Every declared parameter, in manual order.
    pub fn all_params(&self) -> impl Iterator<Item = &'static Param> + '_ {
        self.params.iter().flat_map(|g| g.iter())
    }

    /// Whether `name` (or an alias) names this plugin.
    pub(crate) fn is_called(&self, name: &str) -> bool {
        self.name == name || self.aliases.contains(&name)
    }

    /// The parameter table as Markdown (the format of the manuals and the README).
    pub fn markdown_table(&self) -> String {
        let mut s = String::from(
            "| parameter | type | default | unit | meaning |\n|---|---|---|---|---|\n",
        );
        for p in self.all_params() {
            let mut names = format!("`{}`", p.name);
            for a in p.also {
                write!(names, ", `{a}`").unwrap();
            }
            if !p.v06.is_empty() {
                write!(names, " (0.6: `{}`)", p.v06).unwrap();
            }
            let mut meaning = p.doc.to_string();
            if let Some(c) = p.check.describe() {
                if !meaning.is_empty() {
                    meaning.push_str("; ");
                }
                meaning.push_str(&c);
            }
            writeln!(
                s,
                "| {names} | {} | {} | {} | {meaning} |",
                p.ty.describe(),
                p.default.describe(),
                if p.unit.is_empty() { "—" } else { p.unit },
            )
            .unwrap();
        }
        s
    }
}

/// A plugin: its [`Info`] and its loader, which builds a `T` from a node (with a request `C`,
/// e.g. whether a texture is wanted as a colour or a number).
pub struct Plugin<T: 'static, C: 'static = ()> {
    pub info: Info,
    pub load: fn(&mut Args, C) -> Result<T, SceneError>,
}

impl<T: 'static, C: 'static> Plugin<T, C> {
    /// A plugin from its description and loader.
    pub const fn new(info: Info, load: fn(&mut Args, C) -> Result<T, SceneError>) -> Self {
        Plugin { info, load }
    }
}
