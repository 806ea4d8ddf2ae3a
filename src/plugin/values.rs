//! Turning typed XML values into renderer quantities: spectra (with Mitsuba's rules for when a
//! colour is a reflectance, an unbounded quantity or an emission), indices of refraction, and
//! checked numbers.

use super::{Node, SceneError, SpectrumValue, Value};
use crate::spectrum::spectra::PiecewiseLinear;
use crate::spectrum::{ior, Spectrum};
use std::path::Path;
use std::sync::Arc;

/// How an RGB or scalar value becomes a spectrum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumKind {
    /// A reflectance in [0, 1] (uplifted with a bounded smooth spectrum).
    Albedo,
    /// A non-negative quantity that may exceed 1 (indices, extinction).
    Unbounded,
    /// An emission: RGB and plain numbers are multiplied by D65 (Mitsuba's spectral variants),
    /// `<spectrum>` and `<blackbody>` are taken as given.
    Illuminant,
}

/// Reads parameter `name` of `node` as a spectrum, or `None` if absent.
pub(crate) fn spectrum_opt(
    node: &Node,
    name: &str,
    kind: SpectrumKind,
) -> Result<Option<Spectrum>, SceneError> {
    let Some((value, loc)) = node.props.get(name) else {
        return Ok(None);
    };
    let s = match value {
        Value::Float(_) | Value::Integer(_) => {
            let v = node.props.get_float(name, 0.0)?;
            match kind {
                SpectrumKind::Illuminant => Spectrum::rgb_illuminant([v; 3]),
                _ => Spectrum::Constant(v),
            }
        }
        Value::Rgb(c) => match kind {
            // Mitsuba refuses such colours too ("Invalid RGB reflectance value").
            _ if c.iter().any(|v| *v < 0.0)
                || (kind == SpectrumKind::Albedo && c.iter().any(|v| *v > 1.0)) =>
            {
                let range = if kind == SpectrumKind::Albedo {
                    "a reflectance in [0, 1]"
                } else {
                    "non-negative"
                };
                return Err(SceneError::at(
                    loc,
                    format!(
                        "parameter '{name}' of {} is rgb {}, {}, {}; expected each component {range}",
                        node.describe(),
                        c[0],
                        c[1],
                        c[2]
                    ),
                ));
            }
            SpectrumKind::Albedo => Spectrum::rgb_albedo(*c),
            SpectrumKind::Unbounded => Spectrum::rgb_unbounded(*c),
            SpectrumKind::Illuminant => Spectrum::rgb_illuminant(*c),
        },
        Value::Spectrum(SpectrumValue::Constant(v)) => Spectrum::Constant(*v),
        Value::Spectrum(SpectrumValue::Pairs(p)) => {
            let (l, v): (Vec<f32>, Vec<f32>) = p.iter().copied().unzip();
            let pl = PiecewiseLinear::new(l, v).ok_or_else(|| {
                SceneError::at(loc, format!("spectrum '{name}': wavelengths must increase strictly and values be finite"))
            })?;
            Spectrum::PiecewiseLinear(Arc::new(pl))
        }
        Value::Spectrum(SpectrumValue::File(path)) => Spectrum::PiecewiseLinear(Arc::new(
            read_spd(path).map_err(|m| SceneError::at(loc, m))?,
        )),
        Value::Blackbody { temperature, scale } => {
            if !(*temperature > 0.0 && temperature.is_finite()) {
                return Err(SceneError::at(
                    loc,
                    format!("blackbody temperature must be positive, got {temperature}"),
                ));
            }
            Spectrum::Blackbody {
                temperature: *temperature,
                scale: *scale,
            }
        }
        _ => {
            return Err(node
                .props
                .type_error(name, "a spectrum (float, rgb, spectrum or blackbody)"))
        }
    };
    if let Some(bad) = negative(&s) {
        return Err(SceneError::at(
            loc,
            format!(
                "parameter '{name}' of {} must not be negative (found {bad})",
                node.describe()
            ),
        ));
    }
    Ok(Some(s))
}

fn negative(s: &Spectrum) -> Option<f32> {
    match s {
        Spectrum::Constant(v) if *v < 0.0 => Some(*v),
        Spectrum::PiecewiseLinear(p) => p.values.iter().copied().find(|v| *v < 0.0),
        _ => None,
    }
}

/// Like [`spectrum_opt`] with a default.
pub fn spectrum(
    node: &Node,
    name: &str,
    kind: SpectrumKind,
    default: Spectrum,
) -> Result<Spectrum, SceneError> {
    Ok(spectrum_opt(node, name, kind)?.unwrap_or(default))
}

/// Reads a Mitsuba `.spd` file: lines of "wavelength value", `#` comments.
pub(crate) fn read_spd(path: &Path) -> Result<PiecewiseLinear, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read spectrum file {}: {e}", path.display()))?;
    let mut l = Vec::new();
    let mut v = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let mut it = line.split_whitespace();
        let parse = |s: Option<&str>| {
            s.and_then(|s| s.parse::<f32>().ok())
                .filter(|x| x.is_finite())
        };
        match (parse(it.next()), parse(it.next())) {
            (Some(a), Some(b)) => {
                l.push(a);
                v.push(b);
            }
            _ => {
                return Err(format!(
                    "{}:{}: expected 'wavelength value', found '{line}'",
                    path.display(),
                    i + 1
                ))
            }
        }
    }
    PiecewiseLinear::new(l, v).ok_or_else(|| {
        format!(
            "{}: empty spectrum or wavelengths not strictly increasing",
            path.display()
        )
    })
}

/// An index of refraction given as a number or a Mitsuba material name (`bk7`, `water`, …).
pub fn ior(node: &Node, name: &str, default: &str) -> Result<f32, SceneError> {
    let loc = node
        .props
        .location(name)
        .cloned()
        .unwrap_or_else(|| node.loc.clone());
    let v = match node.props.get(name) {
        None => ior::dielectric_ior(default).expect("default IOR names are known"),
        Some((Value::Float(_) | Value::Integer(_), _)) => node.props.get_float(name, 1.0)?,
        Some((Value::String(s), _)) => ior::dielectric_ior(s).ok_or_else(|| {
            SceneError::at(
                &loc,
                format!(
                    "unknown index of refraction '{s}' for '{name}' of {}",
                    node.describe()
                ),
            )
        })?,
        Some(_) => return Err(node.props.type_error(name, "a float or an IOR name")),
    };
    if !(v > 0.0 && v.is_finite()) {
        return Err(SceneError::at(
            &loc,
            format!(
                "'{name}' of {} must be a positive index of refraction, got {v}",
                node.describe()
            ),
        ));
    }
    Ok(v)
}
