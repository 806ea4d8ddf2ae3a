//! Parsing of attribute text: numbers, lists, colours, spectra, temperatures, versions, `$name`
//! substitution and the 0.6 → 3 name upgrade. Errors are "found …, expected …" phrases; the
//! reader adds the file position and the element.

use std::collections::HashMap;

use super::SpectrumValue;

/// A finite decimal number within the range of an f32 (everything downstream is f32, so a
/// larger one would become infinity later), nothing else but surrounding blanks.
pub(crate) fn parse_float(s: &str) -> Result<f64, String> {
    let t = s.trim();
    // Rust's parser also accepts "inf", "infinity" and "nan"; scene files must not.
    let looks_numeric = t
        .bytes()
        .all(|b| b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E'));
    match t.parse::<f64>() {
        Ok(x) if looks_numeric && x.abs() <= f32::MAX as f64 => Ok(x),
        Ok(_) if looks_numeric => Err(format!(
            "'{t}', which overflows; expected a magnitude below 3.4e38"
        )),
        Ok(_) => Err(format!(
            "'{t}'; expected a finite decimal number (NaN and infinity are not allowed)"
        )),
        Err(_) => Err(format!("'{t}'; expected a decimal number")),
    }
}

/// A decimal integer.
pub(crate) fn parse_int(s: &str) -> Result<i64, String> {
    let t = s.trim();
    t.parse::<i64>()
        .map_err(|_| format!("'{t}'; expected an integer"))
}

/// `true` or `false` (any letter case).
pub(crate) fn parse_bool(s: &str) -> Result<bool, String> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("true") {
        Ok(true)
    } else if t.eq_ignore_ascii_case("false") {
        Ok(false)
    } else {
        Err(format!("'{t}'; expected 'true' or 'false'"))
    }
}

/// Splits a list separated by commas and/or blanks; an empty item between commas is an error.
pub(crate) fn split_list(s: &str) -> Result<Vec<&str>, String> {
    let mut out = Vec::new();
    if s.trim().is_empty() {
        return Ok(out);
    }
    for part in s.split(',') {
        if part.trim().is_empty() {
            return Err(format!(
                "'{}', which has an empty item; expected a list",
                s.trim()
            ));
        }
        out.extend(part.split_whitespace());
    }
    Ok(out)
}

/// A list of finite numbers.
pub fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    split_list(s)?.into_iter().map(parse_float).collect()
}

/// Exactly `n` numbers, as f32.
pub(crate) fn parse_n<const N: usize>(s: &str) -> Result<[f32; N], String> {
    let v = parse_list(s)?;
    if v.len() != N {
        return Err(format!(
            "'{}' ({} numbers); expected {N} numbers",
            s.trim(),
            v.len()
        ));
    }
    Ok(std::array::from_fn(|i| v[i] as f32))
}

/// A 3-vector from one number (used for all three) or three.
pub(crate) fn parse_vec3(s: &str) -> Result<[f32; 3], String> {
    let v = parse_list(s)?;
    match v.len() {
        1 => Ok([v[0] as f32; 3]),
        3 => Ok([v[0] as f32, v[1] as f32, v[2] as f32]),
        n => Err(format!(
            "'{}' ({n} numbers); expected 1 or 3 numbers",
            s.trim()
        )),
    }
}

/// The sRGB transfer function's inverse (encoded → linear); odd-symmetric for negatives.
pub(crate) fn srgb_to_linear(c: f32) -> f32 {
    crate::spectrum::cie::srgb_decode(c.abs()).copysign(c)
}

/// An RGB triple: "r, g, b", "r g b", one value for all three, or "#rrggbb" (sRGB-encoded,
/// returned linear).
pub(crate) fn parse_rgb(s: &str) -> Result<[f32; 3], String> {
    let t = s.trim();
    if let Some(hex) = t.strip_prefix('#') {
        if hex.len() != 6 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(format!("'{t}'; expected '#rrggbb' with six hex digits"));
        }
        let byte = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).unwrap_or(0);
        return Ok([0, 2, 4].map(|i| srgb_to_linear(byte(i) as f32 / 255.0)));
    }
    parse_vec3(t)
}

/// A spectrum literal: one constant, or "λ:value" pairs with increasing wavelengths (nm).
pub(crate) fn parse_spectrum(s: &str) -> Result<SpectrumValue, String> {
    let items = split_list(s)?;
    if items.is_empty() {
        return Err("an empty value; expected a number or 'wavelength:value' pairs".into());
    }
    if items.len() == 1 && !items[0].contains(':') {
        return Ok(SpectrumValue::Constant(parse_float(items[0])? as f32));
    }
    let mut pairs = Vec::with_capacity(items.len());
    for item in items {
        let Some((l, v)) = item.split_once(':') else {
            return Err(format!(
                "'{item}' among wavelength:value pairs; expected 'wavelength:value'"
            ));
        };
        let (l, v) = (parse_float(l)? as f32, parse_float(v)? as f32);
        if let Some(&(prev, _)) = pairs.last() {
            if l <= prev {
                return Err(format!(
                    "wavelength {l} after {prev}; expected increasing wavelengths"
                ));
            }
        }
        if l <= 0.0 {
            return Err(format!(
                "wavelength {l}; expected a positive wavelength in nm"
            ));
        }
        pairs.push((l, v));
    }
    Ok(SpectrumValue::Pairs(pairs))
}

/// A temperature in kelvin, "3000" or "3000K".
pub(crate) fn parse_temperature(s: &str) -> Result<f32, String> {
    let t = s.trim();
    let num = t
        .strip_suffix('K')
        .or_else(|| t.strip_suffix('k'))
        .unwrap_or(t);
    let k = parse_float(num)? as f32;
    if k > 0.0 && k.is_finite() {
        Ok(k)
    } else {
        Err(format!("'{t}'; expected a positive temperature in kelvin"))
    }
}

/// "major.minor.patch" (minor and patch optional).
pub(crate) fn parse_version(s: &str) -> Result<(u32, u32, u32), String> {
    let t = s.trim();
    let bad = || format!("'{t}'; expected a version such as '3.0.0'");
    let parts: Vec<&str> = t.split('.').collect();
    if parts.is_empty() || parts.len() > 3 {
        return Err(bad());
    }
    let mut v = [0u32; 3];
    for (slot, p) in v.iter_mut().zip(&parts) {
        if p.is_empty() || !p.bytes().all(|b| b.is_ascii_digit()) {
            return Err(bad());
        }
        *slot = p.parse().map_err(|_| bad())?;
    }
    Ok((v[0], v[1], v[2]))
}

/// Mitsuba 3's upgrade of 0.6 parameter names: an underscore before each capital that follows
/// a lower-case letter or digit, then everything lower case (`intIOR` → `int_ior`,
/// `sigmaT_0` → `sigma_t_0`).
pub(crate) fn to_snake_case(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 4);
    let mut prev: Option<char> = None;
    for c in s.chars() {
        if c.is_ascii_uppercase()
            && prev.is_some_and(|p| p.is_ascii_lowercase() || p.is_ascii_digit())
        {
            out.push('_');
        }
        out.push(c.to_ascii_lowercase());
        prev = Some(c);
    }
    out
}

/// Replaces `$name` and `${name}` (name = letters, digits, `_`) by their values; a `$` not
/// followed by a name is kept. An unknown name is an error naming it. Values are not
/// substituted again, so definitions cannot loop.
pub(crate) fn substitute(s: &str, params: &HashMap<String, String>) -> Result<String, String> {
    if !s.contains('$') {
        return Ok(s.to_string());
    }
    let is_name = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find('$') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let (name, tail) = if let Some(braced) = after.strip_prefix('{') {
            match braced.find('}') {
                Some(j) => (&braced[..j], &braced[j + 1..]),
                None => return Err(format!("'{s}', which has an unclosed '${{'")),
            }
        } else {
            let end = after.find(|c: char| !is_name(c)).unwrap_or(after.len());
            (&after[..end], &after[end..])
        };
        if name.is_empty() {
            out.push('$');
            rest = after;
            continue;
        }
        match params.get(name) {
            Some(v) => out.push_str(v),
            None => {
                return Err(format!(
                    "'${name}', which is not defined; expected a <default name=\"{name}\" …/> \
                     or a define -D {name}=…"
                ))
            }
        }
        rest = tail;
    }
    out.push_str(rest);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_are_strict() {
        assert_eq!(parse_float(" 1.5e2 ").unwrap(), 150.0);
        assert_eq!(parse_float("-.5").unwrap(), -0.5);
        for bad in [
            "abc",
            "1.0f",
            "1,0",
            "",
            "nan",
            "NaN",
            "inf",
            "-infinity",
            "1e999",
            "0x10",
        ] {
            assert!(parse_float(bad).is_err(), "{bad} accepted");
        }
        assert!(parse_int("3.0").is_err());
        assert_eq!(parse_int("-12").unwrap(), -12);
        assert!(parse_bool("yes").is_err());
        assert!(parse_bool("TRUE").unwrap());
    }

    #[test]
    fn lists_take_commas_and_blanks() {
        assert_eq!(parse_list("1, 2 ,3").unwrap(), vec![1.0, 2.0, 3.0]);
        assert_eq!(parse_list("1 2\n3").unwrap(), vec![1.0, 2.0, 3.0]);
        assert!(parse_list("1,,2").is_err());
        assert!(parse_list("1,2,").is_err());
        assert_eq!(parse_vec3("0.5").unwrap(), [0.5; 3]);
        assert!(parse_vec3("1 2").is_err());
    }

    #[test]
    fn colours_and_spectra() {
        let c = parse_rgb("#ff8000").unwrap();
        assert_eq!(c[0], 1.0);
        assert!((c[1] - srgb_to_linear(128.0 / 255.0)).abs() < 1e-7);
        assert!((c[1] - 0.2158605).abs() < 1e-5);
        assert_eq!(c[2], 0.0);
        assert!(parse_rgb("#ff80").is_err());
        assert!(parse_rgb("#gg0000").is_err());
        assert_eq!(parse_spectrum("0.5").unwrap(), SpectrumValue::Constant(0.5));
        assert_eq!(
            parse_spectrum("400:0.1, 500:0.2").unwrap(),
            SpectrumValue::Pairs(vec![(400.0, 0.1), (500.0, 0.2)])
        );
        assert!(parse_spectrum("500:0.1, 400:0.2").is_err());
        assert!(parse_spectrum("0.1 0.2").is_err());
        assert!(parse_spectrum("400:x").is_err());
        assert_eq!(parse_temperature("3000K").unwrap(), 3000.0);
        assert!(parse_temperature("-5").is_err());
    }

    #[test]
    fn versions_and_names() {
        assert_eq!(parse_version("0.6.0").unwrap(), (0, 6, 0));
        assert_eq!(parse_version("3").unwrap(), (3, 0, 0));
        assert!(parse_version("3.x").is_err());
        assert!(parse_version("1.2.3.4").is_err());
        for (a, b) in [
            ("intIOR", "int_ior"),
            ("extIOR", "ext_ior"),
            ("sampleCount", "sample_count"),
            ("toWorld", "to_world"),
            ("rrDepth", "rr_depth"),
            ("diffuseReflectance", "diffuse_reflectance"),
            ("alphaU", "alpha_u"),
            ("sigmaT_0", "sigma_t_0"),
            ("filename", "filename"),
        ] {
            assert_eq!(to_snake_case(a), b);
        }
    }

    #[test]
    fn substitution() {
        let p: HashMap<String, String> = [("spp", "64"), ("name", "bunny"), ("s", "X")]
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        assert_eq!(substitute("$spp", &p).unwrap(), "64");
        assert_eq!(
            substitute("meshes/$name.obj", &p).unwrap(),
            "meshes/bunny.obj"
        );
        assert_eq!(substitute("${s}pp $ 5", &p).unwrap(), "Xpp $ 5");
        let e = substitute("$nope", &p).unwrap_err();
        assert!(e.contains("'$nope'"), "{e}");
        assert!(substitute("${s", &p).is_err());
    }
}
