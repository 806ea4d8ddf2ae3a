//! [`Args`]: a plugin loader's view of its node, read through the plugin's declaration.
//!
//! Every getter names a declared [`Param`]; the value comes from the node under any of the
//! parameter's spellings, or from the declared default, and is checked against the declared
//! [`super::Check`]. Errors name the file, line and column of the value (or of the element when
//! the value is missing) and say what was expected.

use super::param::{Check, DefaultValue, Info, Param, Ty};
use super::values::{self, SpectrumKind};
use super::{registry, Node, SceneError, Tag, Value, Warning};
use crate::bsdf::Material;
use crate::math::{Transform, Vec3};
use crate::spectrum::Spectrum;
use crate::texture::{FloatTexture, SpectrumTexture, Want};
use std::path::PathBuf;
use std::sync::Arc;

/// A loader's access to its node.
pub struct Args<'a> {
    node: &'a Node,
    info: &'static Info,
    warnings: &'a mut Vec<Warning>,
}

impl<'a> Args<'a> {
    /// Reads `node` as the plugin `info` describes.
    pub fn new(node: &'a Node, info: &'static Info, warnings: &'a mut Vec<Warning>) -> Self {
        Args {
            node,
            info,
            warnings,
        }
    }

    /// The node being read.
    pub fn node(&self) -> &'a Node {
        self.node
    }

    /// The plugin being loaded.
    pub fn info(&self) -> &'static Info {
        self.info
    }

    /// "bsdf 'diffuse' (id 'red')", for messages.
    pub fn describe(&self) -> String {
        self.node.describe()
    }

    /// A warning at the element.
    pub fn warn(&mut self, message: impl Into<String>) {
        self.warnings.push(Warning {
            loc: self.node.loc.clone(),
            message: message.into(),
        });
    }

    /// Warnings gathered so far (for loaders that build nested objects themselves).
    pub fn warnings(&mut self) -> &mut Vec<Warning> {
        self.warnings
    }

    /// The declaration of `name`; an undeclared name is a bug in the loader, reported as an
    /// error rather than a panic.
    fn param(&self, name: &str) -> Result<&'static Param, SceneError> {
        self.info.param(name).ok_or_else(|| {
            debug_assert!(
                false,
                "{}: parameter '{name}' is not declared",
                self.info.name
            );
            SceneError::at(
                &self.node.loc,
                format!(
                    "internal error: {} reads parameter '{name}', which it does not declare",
                    self.info.name
                ),
            )
        })
    }

    /// The spellings of `p` when read as `requested` (an indexed declaration such as
    /// `sigma_t_i` read as `sigma_t_0` gives the concrete names).
    fn spellings(p: &Param, requested: &str) -> Vec<String> {
        match (p.name.strip_suffix("_i"), requested.rsplit_once('_')) {
            (Some(_), Some((_, idx))) if requested != p.name => p
                .names()
                .map(|n| format!("{}_{idx}", n.strip_suffix("_i").unwrap_or(n)))
                .collect(),
            _ => p.names().map(String::from).collect(),
        }
    }

    /// The spelling of `p` (read as `requested`) present in the node, as a value or a named
    /// child; two spellings at once are an error.
    fn present(&self, p: &Param, requested: &str) -> Result<Option<String>, SceneError> {
        let mut found: Option<String> = None;
        // A named child counts only for parameters that can be nested objects: a `snake`'s
        // BSDF named `eyes` is not its boolean `eyes`.
        let nests = matches!(
            p.ty,
            Ty::SpectrumTexture(_) | Ty::FloatTexture | Ty::Bsdf | Ty::Texture | Ty::Object(_)
        );
        for n in Self::spellings(p, requested) {
            if self.node.props.contains(&n) || (nests && self.node.child(&n).is_some()) {
                if let Some(first) = &found {
                    let loc = self.node.props.location(&n).unwrap_or(&self.node.loc);
                    return Err(SceneError::at(
                        loc,
                        format!(
                            "{}: give '{first}' or '{n}', not both (they are the same parameter)",
                            self.describe()
                        ),
                    ));
                }
                found = Some(n);
            }
        }
        Ok(found)
    }

    /// Whether `name` (under any spelling) is given.
    pub fn has(&self, name: &str) -> bool {
        self.param(name)
            .ok()
            .and_then(|p| self.present(p, name).ok().flatten())
            .is_some()
    }

    /// An error about parameter `name`, at its value (or at the element).
    pub fn error(&self, name: &str, message: impl std::fmt::Display) -> SceneError {
        let loc = self
            .info
            .param(name)
            .into_iter()
            .flat_map(|p| Self::spellings(p, name))
            .find_map(|n| {
                self.node
                    .props
                    .location(&n)
                    .or_else(|| self.node.child(&n).map(|c| &c.loc))
            })
            .unwrap_or(&self.node.loc);
        SceneError::at(loc, format!("'{name}' of {}: {message}", self.describe()))
    }

    fn check_number(&self, p: &Param, written: &str, v: f64) -> Result<(), SceneError> {
        if p.check.accepts(v) {
            return Ok(());
        }
        let what = p.check.describe().unwrap_or_else(|| "finite".into());
        Err(self.error(written, format!("must be {what}, got {v}")))
    }

    fn missing(&self, p: &Param, name: &str) -> SceneError {
        // An indexed declaration (`thickness_i`) is named as it was asked for (`thickness_0`).
        let name = if p.name.ends_with("_i") { name } else { p.name };
        SceneError::at(
            &self.node.loc,
            format!("{} needs '{name}'", self.describe()),
        )
    }

    /// The declared default of `p` as `pick` takes it (`None`: no default of that kind), with
    /// the name it is checked under; an error when the parameter is required.
    fn declared<T>(
        &self,
        p: &Param,
        name: &str,
        pick: impl Fn(DefaultValue) -> Option<T>,
    ) -> Result<Option<(T, String)>, SceneError> {
        match p.default {
            DefaultValue::Required => Err(self.missing(p, name)),
            d => Ok(pick(d).map(|v| (v, p.name.to_string()))),
        }
    }

    /// A number read (or defaulted) as `v`, after the declared check.
    fn checked<T: Copy>(
        &self,
        p: &Param,
        v: Option<(T, String)>,
        as_f64: fn(T) -> f64,
    ) -> Result<Option<T>, SceneError> {
        if let Some((x, n)) = &v {
            self.check_number(p, n, as_f64(*x))?;
        }
        Ok(v.map(|(x, _)| x))
    }

    /// `v`, or the error of a parameter that must be given (it has no default of its kind).
    fn given<T>(&self, name: &str, v: Option<T>) -> Result<T, SceneError> {
        v.ok_or_else(|| {
            self.missing(
                self.info.param(name).expect("declared: param() succeeded"),
                name,
            )
        })
    }

    /// A float (integers accepted), or `None` when absent and the default is not a number.
    pub(crate) fn float_opt(&self, name: &str) -> Result<Option<f32>, SceneError> {
        let p = self.param(name)?;
        let v = match self.present(p, name)? {
            Some(n) => match self.node.props.get_float_opt(&n)? {
                Some(v) => Some((v, n)),
                None => return Err(self.node.props.type_error(&n, "a float")),
            },
            None => self.declared(p, name, |d| match d {
                DefaultValue::Float(v) => Some(v),
                _ => None,
            })?,
        };
        self.checked(p, v, f64::from)
    }

    /// A float; the declaration must give a numeric default or require the value.
    pub fn float(&self, name: &str) -> Result<f32, SceneError> {
        self.given(name, self.float_opt(name)?)
    }

    /// An angle declared by [`Param::angle`](super::Param::angle), in radians.
    pub fn angle(&self, name: &str) -> Result<f32, SceneError> {
        Ok(self.float(name)?.to_radians())
    }

    /// An integer, or `None` when absent without a default.
    pub(crate) fn int_opt(&self, name: &str) -> Result<Option<i64>, SceneError> {
        let p = self.param(name)?;
        let v = match self.present(p, name)? {
            Some(n) => self.node.props.get_int_opt(&n)?.map(|v| (v, n)),
            None => self.declared(p, name, |d| match d {
                DefaultValue::Int(v) => Some(v),
                _ => None,
            })?,
        };
        self.checked(p, v, |v| v as f64)
    }

    /// An integer with a declared default.
    pub fn int(&self, name: &str) -> Result<i64, SceneError> {
        self.given(name, self.int_opt(name)?)
    }

    /// An integer declared by [`Param::u32`](super::Param::u32) (or in a narrower range).
    pub fn u32(&self, name: &str) -> Result<u32, SceneError> {
        let v = self.int(name)?;
        u32::try_from(v)
            .map_err(|_| self.error(name, format!("must be between 0 and {}, got {v}", u32::MAX)))
    }

    /// A boolean (declared default when absent).
    pub fn bool(&self, name: &str) -> Result<bool, SceneError> {
        let p = self.param(name)?;
        match self.present(p, name)? {
            Some(n) => Ok(self.node.props.get_bool_opt(&n)?.unwrap_or(false)),
            None => match p.default {
                DefaultValue::Bool(b) => Ok(b),
                _ => Err(self.missing(p, name)),
            },
        }
    }

    /// A string, or `None` when absent without a default; checked against `OneOf`.
    pub(crate) fn string_opt(&self, name: &str) -> Result<Option<String>, SceneError> {
        let p = self.param(name)?;
        let v = match self.present(p, name)? {
            Some(n) => self.node.props.get_string_opt(&n)?.map(|s| (s, n)),
            None => self.declared(p, name, |d| match d {
                DefaultValue::Str(s) => Some(s.to_string()),
                _ => None,
            })?,
        };
        if let (Some((s, _)), Check::OneOf(allowed)) = (&v, p.check) {
            if !allowed.contains(&s.as_str()) {
                let near = super::suggest::did_you_mean(s, allowed.iter().copied());
                let what = p.check.describe().unwrap_or_default();
                return Err(self.error(name, format!("must be {what}, got '{s}'{near}")));
            }
        }
        Ok(v.map(|(s, _)| s))
    }

    /// A string with a declared default.
    pub fn string(&self, name: &str) -> Result<String, SceneError> {
        self.given(name, self.string_opt(name)?)
    }

    /// A file name resolved against the folder of the file that declared it.
    pub fn path(&self, name: &str) -> Result<Option<PathBuf>, SceneError> {
        let p = self.param(name)?;
        match self.present(p, name)? {
            Some(n) => self.node.props.get_path_opt(&n),
            None if p.default == DefaultValue::Required => Err(self.missing(p, name)),
            None => Ok(None),
        }
    }

    /// A transform (identity when absent).
    pub fn transform(&self, name: &str) -> Result<Transform, SceneError> {
        let p = self.param(name)?;
        match self.present(p, name)? {
            Some(n) => self.node.props.get_transform(&n, Transform::IDENTITY),
            None => Ok(Transform::IDENTITY),
        }
    }

    /// A point (a vector is accepted too); the declared default when absent.
    pub fn point(&self, name: &str) -> Result<Vec3, SceneError> {
        let p = self.param(name)?;
        let v = match self.present(p, name)? {
            Some(n) => self.node.props.get_point_opt(&n)?,
            None => self
                .declared(p, name, |d| match d {
                    DefaultValue::Point(v) => Some(Vec3::from(v)),
                    _ => None,
                })?
                .map(|(v, _)| v),
        };
        self.given(name, v)
    }

    /// A point (a vector is accepted too), or `None` if absent.
    pub(crate) fn point_opt(&self, name: &str) -> Result<Option<Vec3>, SceneError> {
        let p = self.param(name)?;
        match self.present(p, name)? {
            Some(n) => self.node.props.get_point_opt(&n),
            None => Ok(None),
        }
    }

    /// A vector (a point is accepted too), or `None` if absent.
    pub(crate) fn vector_opt(&self, name: &str) -> Result<Option<Vec3>, SceneError> {
        let p = self.param(name)?;
        match self.present(p, name)? {
            Some(n) => self.node.props.get_vector_opt(&n),
            None => Ok(None),
        }
    }

    /// An index of refraction: a positive number or a named one (declared default otherwise).
    pub fn ior(&self, name: &str) -> Result<f32, SceneError> {
        let p = self.param(name)?;
        let written = self.present(p, name)?;
        let default = match p.default {
            DefaultValue::Str(s) => s,
            DefaultValue::Float(v) if written.is_none() => return Ok(v),
            DefaultValue::Required if written.is_none() => return Err(self.missing(p, name)),
            _ => "air",
        };
        values::ior(self.node, written.as_deref().unwrap_or(p.name), default)
    }

    fn kind(p: &Param) -> SpectrumKind {
        match p.ty {
            Ty::Spectrum(k) | Ty::SpectrumTexture(k) => k,
            _ => SpectrumKind::Unbounded,
        }
    }

    fn default_spectrum(p: &Param) -> Option<Spectrum> {
        match p.default {
            DefaultValue::Float(v) => Some(match Self::kind(p) {
                SpectrumKind::Illuminant => Spectrum::rgb_illuminant([v; 3]),
                _ => Spectrum::Constant(v),
            }),
            _ => None,
        }
    }

    /// A spectrum value of the declared kind, or `None` when absent without a default.
    pub(crate) fn spectrum_opt(&self, name: &str) -> Result<Option<Spectrum>, SceneError> {
        let p = self.param(name)?;
        match self.present(p, name)? {
            Some(n) => values::spectrum_opt(self.node, &n, Self::kind(p)),
            None if p.default == DefaultValue::Required => Err(self.missing(p, name)),
            None => Ok(Self::default_spectrum(p)),
        }
    }

    /// A spectrum value read as `kind` (for textures, whose users decide how a colour is
    /// uplifted), with the declared default.
    pub(crate) fn spectrum_as(
        &self,
        name: &str,
        kind: SpectrumKind,
    ) -> Result<Spectrum, SceneError> {
        let p = self.param(name)?;
        let mut as_kind = *p;
        as_kind.ty = Ty::Spectrum(kind);
        match self.present(p, name)? {
            Some(n) => values::spectrum_opt(self.node, &n, kind)?,
            None => Self::default_spectrum(&as_kind),
        }
        .ok_or_else(|| self.missing(p, name))
    }

    /// A spectrum value with a declared default.
    pub fn spectrum(&self, name: &str) -> Result<Spectrum, SceneError> {
        self.given(name, self.spectrum_opt(name)?)
    }

    /// The nested or referenced texture given as `name`, if any.
    fn texture_child(&self, p: &Param, name: &str) -> Result<Option<&'a Arc<Node>>, SceneError> {
        Ok(self
            .present(p, name)?
            .and_then(|n| self.node.child(&n))
            .filter(|c| c.tag == Tag::Texture))
    }

    /// A colour: a nested or referenced texture, or a value (declared default when absent).
    pub(crate) fn spectrum_texture(&mut self, name: &str) -> Result<SpectrumTexture, SceneError> {
        let p = self.param(name)?;
        if let Some(tex) = self.texture_child(p, name)? {
            return registry::spectrum_texture(tex, Self::kind(p), self.warnings);
        }
        Ok(SpectrumTexture::Constant(self.spectrum(name)?))
    }

    /// A scalar: a nested or referenced texture, or a checked float (declared default).
    pub(crate) fn float_texture(&mut self, name: &str) -> Result<FloatTexture, SceneError> {
        let p = self.param(name)?;
        if let Some(tex) = self.texture_child(p, name)? {
            return registry::float_texture(tex, self.warnings);
        }
        Ok(FloatTexture::Constant(self.float(name)?))
    }

    /// A texture for a parameter declared [`Ty::Texture`], requested as `want`.
    pub fn texture(
        &mut self,
        name: &str,
        want: Want,
    ) -> Result<crate::texture::Texture, SceneError> {
        let p = self.param(name)?;
        match self.texture_child(p, name)? {
            Some(tex) => registry::texture(tex, want, self.warnings),
            None => Err(self.missing(p, name)),
        }
    }

    /// The nested objects with this tag, named or not, in document order.
    pub fn children(&self, tag: Tag) -> Vec<&'a Arc<Node>> {
        self.node.children_with_tag(tag).collect()
    }

    /// The nested object given as `name` (a declared parameter), if any.
    pub fn child(&self, name: &str) -> Result<Option<&'a Arc<Node>>, SceneError> {
        let p = self.param(name)?;
        // Asked for a nested object explicitly (a `phase_i` given as a number or as a
        // `<phase>`): any spelling's child counts, whatever the value type.
        Ok(Self::spellings(p, name)
            .iter()
            .find_map(|n| self.node.child(n)))
    }

    /// Builds a nested BSDF.
    pub fn bsdf(&mut self, node: &Arc<Node>) -> Result<Material, SceneError> {
        registry::bsdf(node, self.warnings)
    }

    /// Builds a nested texture.
    pub(crate) fn texture_node(
        &mut self,
        node: &Arc<Node>,
        want: Want,
    ) -> Result<crate::texture::Texture, SceneError> {
        registry::texture(node, want, self.warnings)
    }

    /// Marks a parameter as read without using it (accepted and ignored, documented as such).
    pub fn ignore(&self, name: &str) -> Result<(), SceneError> {
        let p = self.param(name)?;
        for n in Self::spellings(p, name) {
            self.node.props.mark_queried(&n);
        }
        Ok(())
    }

    /// Reads the raw value of a parameter (for loaders that accept several value types).
    pub fn value(&self, name: &str) -> Result<Option<&'a Value>, SceneError> {
        let p = self.param(name)?;
        Ok(self
            .present(p, name)?
            .and_then(|n| self.node.props.get(&n))
            .map(|(v, _)| v))
    }

    /// The spelling under which `name` was written (or its declared name).
    pub fn written(&self, name: &str) -> Result<String, SceneError> {
        let p = self.param(name)?;
        Ok(self.present(p, name)?.unwrap_or_else(|| name.to_string()))
    }
}
