//! Refractive indices for the film optics: a complex n + ik as a function of vacuum wavelength.
//!
//! | form | syntax ([`Ior::parse`]) | value at λ (nm) |
//! |---|---|---|
//! | real number | `1.56` | n |
//! | complex | `0.43+2.45i` | n + ik, k ≥ 0 absorbing |
//! | keratin | `keratin` | 1.532 + 5890/λ² (Leertouwer, Wilts & Stavenga 2011, Opt. Express 19:24061) |
//! | Cauchy pair | `cauchy(A,B)` | A + B/λ², B in nm² |
//! | named dielectric | `water`, `bk7`, … | Mitsuba 3's constant indices ([`crate::spectrum::ior::dielectric_ior`]) |
//! | named metal | `Au`, `Cu`, `TiO2`, … | measured n, k, piecewise linear in λ ([`crate::spectrum::ior::conductor_nk`]) |
//! | table | [`Ior::table`] | n(λ), k(λ) piecewise linear, constant beyond the ends |
//!
//! Conventions: k ≥ 0 means the wave e^{i(kz − ωt)} decays (the `tmm` package's convention,
//! Byrnes 2016, arXiv:1603.02720); gain media (k < 0) are rejected. Every index is validated when
//! it is built, so [`Ior::at`] is total: finite with n > 0 and k ≥ 0 at every λ > 0.
//!
//! Limits: a Cauchy pair needs A > 0 and B ≥ 0 (so it is positive at every wavelength); tables
//! are not extrapolated.

use crate::spectrum::ior::{conductor_nk, dielectric_ior};
use crate::spectrum::spectra::Spectrum;
use num_complex::Complex64 as C;
use std::fmt;
use std::sync::Arc;

/// Cauchy coefficients of keratin (Leertouwer, Wilts & Stavenga 2011): A, and B in nm².
pub(crate) const KERATIN_CAUCHY: (f64, f64) = (1.532, 5890.0);

/// A tabulated n(λ), k(λ) on one wavelength grid.
#[derive(Clone, Debug, PartialEq)]
pub struct NkTable {
    /// Name it was looked up by (for display), if any.
    pub name: Option<String>,
    lambda: Vec<f64>,
    n: Vec<f64>,
    k: Vec<f64>,
}

impl NkTable {
    /// Index at `l` nm: linear between samples, constant beyond the ends.
    fn at(&self, l: f64) -> C {
        let last = self.lambda.len() - 1;
        if !(l > self.lambda[0]) {
            return C::new(self.n[0], self.k[0]);
        }
        if l >= self.lambda[last] {
            return C::new(self.n[last], self.k[last]);
        }
        let i = self.lambda.partition_point(|&x| x <= l) - 1;
        let t = (l - self.lambda[i]) / (self.lambda[i + 1] - self.lambda[i]);
        C::new(
            self.n[i] + t * (self.n[i + 1] - self.n[i]),
            self.k[i] + t * (self.k[i + 1] - self.k[i]),
        )
    }
}

/// A refractive index n(λ) + i k(λ).
#[derive(Clone, Debug, PartialEq)]
pub enum Ior {
    /// The same real index at every wavelength.
    Real(f64),
    /// The same complex index n + ik at every wavelength.
    Complex(C),
    /// Keratin, 1.532 + 5890/λ².
    Keratin,
    /// A + B/λ² (B in nm²).
    Cauchy { a: f64, b: f64 },
    /// Tabulated n and k.
    Table(Arc<NkTable>),
}

fn positive(what: &str, v: f64) -> Result<f64, String> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{what} must be a finite number > 0, got {v}"))
    }
}

impl Ior {
    /// A real index; errors unless finite and > 0.
    pub fn real(n: f64) -> Result<Ior, String> {
        Ok(Ior::Real(positive("the index", n)?))
    }

    /// n + ik; errors unless n > 0 and k ≥ 0, both finite. k = 0 gives [`Ior::Real`].
    pub fn complex(n: f64, k: f64) -> Result<Ior, String> {
        let n = positive("the real part n", n)?;
        if !(k >= 0.0 && k.is_finite()) {
            return Err(format!(
                "the extinction k must be finite and ≥ 0 (k < 0 would be gain), got {k}"
            ));
        }
        Ok(if k == 0.0 {
            Ior::Real(n)
        } else {
            Ior::Complex(C::new(n, k))
        })
    }

    /// A Cauchy pair A + B/λ² (B in nm²); errors unless A > 0 and B ≥ 0.
    pub fn cauchy(a: f64, b: f64) -> Result<Ior, String> {
        let a = positive("Cauchy's A", a)?;
        if !(b >= 0.0 && b.is_finite()) {
            return Err(format!("Cauchy's B must be finite and ≥ 0 nm², got {b}"));
        }
        Ok(Ior::Cauchy { a, b })
    }

    /// A table of (λ nm, n, k): λ strictly increasing and > 0, n > 0, k ≥ 0, at least one row.
    pub fn table(name: Option<String>, rows: &[(f64, f64, f64)]) -> Result<Ior, String> {
        if rows.is_empty() {
            return Err("an n, k table needs at least one row".into());
        }
        for (i, &(l, n, k)) in rows.iter().enumerate() {
            let ok = l > 0.0 && l.is_finite() && n > 0.0 && n.is_finite() && k >= 0.0;
            let bad = !(ok && k.is_finite());
            if bad {
                return Err(format!(
                    "n, k table row {}: expected λ > 0, n > 0, k ≥ 0 (finite), got ({l}, {n}, {k})",
                    i + 1
                ));
            }
            if i > 0 && !(l > rows[i - 1].0) {
                return Err(format!(
                    "n, k table row {}: wavelengths must increase, {l} follows {}",
                    i + 1,
                    rows[i - 1].0
                ));
            }
        }
        Ok(Ior::Table(Arc::new(NkTable {
            name,
            lambda: rows.iter().map(|r| r.0).collect(),
            n: rows.iter().map(|r| r.1).collect(),
            k: rows.iter().map(|r| r.2).collect(),
        })))
    }

    /// A named index: `keratin`, a Mitsuba dielectric name (`water`, `bk7`, …) or a Mitsuba
    /// conductor name (`Au`, `Cu`, …; measured n, k). `None` if the name is unknown.
    pub fn named(name: &str) -> Option<Ior> {
        if name == "keratin" {
            return Some(Ior::Keratin);
        }
        if let Some(n) = dielectric_ior(name) {
            // The table's decimal (1.5046), not its f32 rounding (1.50460004…).
            return Some(Ior::Real(n.to_string().parse().unwrap_or(n as f64)));
        }
        let (Spectrum::PiecewiseLinear(n), Spectrum::PiecewiseLinear(k)) = conductor_nk(name)?
        else {
            return None;
        };
        if n.lambda != k.lambda {
            return None;
        }
        let rows: Vec<(f64, f64, f64)> = n
            .lambda
            .iter()
            .zip(n.values.iter().zip(&k.values))
            // The measured files have a few k = -0 or tiny negative round-offs; k ≥ 0 is physics.
            .map(|(&l, (&n, &k))| (l as f64, n as f64, (k as f64).max(0.0)))
            .collect();
        Ior::table(Some(name.to_string()), &rows).ok()
    }

    /// Parses an index written as in the table of the module doc. The error says what was
    /// expected.
    pub fn parse(s: &str) -> Result<Ior, String> {
        let t = s.trim();
        if let Some(ior) = Ior::named(t) {
            return Ok(ior);
        }
        let num = |x: &str, what: &str| {
            x.trim()
                .parse::<f64>()
                .map_err(|_| format!("{what} '{}' is not a number (in '{t}')", x.trim()))
        };
        if let Some(args) = t.strip_prefix("cauchy(").and_then(|r| r.strip_suffix(')')) {
            let Some((a, b)) = args.split_once(',') else {
                return Err(format!("expected cauchy(A,B), got '{t}'"));
            };
            return Ior::cauchy(num(a, "Cauchy's A")?, num(b, "Cauchy's B")?);
        }
        if let Some(body) = t.strip_suffix('i') {
            // The sign between n and k: the last + or − that is not an exponent's.
            let cut = body
                .char_indices()
                .filter(|&(i, c)| {
                    (c == '+' || c == '-')
                        && i > 0
                        && !matches!(body.as_bytes()[i - 1], b'e' | b'E')
                })
                .map(|(i, _)| i)
                .next_back();
            if let Some(i) = cut {
                let n = num(&body[..i], "the real part")?;
                let k = num(&body[i..], "the imaginary part")?;
                return Ior::complex(n, k);
            }
        }
        match t.parse::<f64>() {
            Ok(v) => Ior::real(v),
            Err(_) => Err(format!(
                "'{t}' is not an index: expected a number (1.56), n+ki (0.43+2.45i), keratin, \
                 cauchy(A,B), a dielectric name (water, bk7, …) or a metal name (Au, Cu, …)"
            )),
        }
    }

    /// n + ik at vacuum wavelength `lambda_nm`.
    #[inline]
    pub fn at(&self, lambda_nm: f64) -> C {
        match self {
            Ior::Real(n) => C::new(*n, 0.0),
            Ior::Complex(c) => *c,
            Ior::Keratin => {
                let (a, b) = KERATIN_CAUCHY;
                C::new(a + b / (lambda_nm * lambda_nm), 0.0)
            }
            Ior::Cauchy { a, b } => C::new(a + b / (lambda_nm * lambda_nm), 0.0),
            Ior::Table(t) => t.at(lambda_nm),
        }
    }

    /// Whether k = 0 at every wavelength (no absorption).
    pub fn is_lossless(&self) -> bool {
        match self {
            Ior::Real(_) | Ior::Keratin | Ior::Cauchy { .. } => true,
            Ior::Complex(c) => c.im == 0.0,
            Ior::Table(t) => t.k.iter().all(|&k| k == 0.0),
        }
    }
}

impl fmt::Display for Ior {
    /// The syntax [`Ior::parse`] reads back (a table without a name prints as `table(N rows)`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Ior::Real(n) => write!(f, "{n}"),
            Ior::Complex(c) => write!(f, "{}+{}i", c.re, c.im),
            Ior::Keratin => write!(f, "keratin"),
            Ior::Cauchy { a, b } => write!(f, "cauchy({a},{b})"),
            Ior::Table(t) => match &t.name {
                Some(n) => write!(f, "{n}"),
                None => write!(f, "table({} rows)", t.lambda.len()),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_form_and_reads_back_its_display() {
        assert_eq!(Ior::parse("1.56"), Ok(Ior::Real(1.56)));
        assert_eq!(
            Ior::parse(" 0.43+2.45i "),
            Ok(Ior::Complex(C::new(0.43, 2.45)))
        );
        assert_eq!(Ior::parse("1.5+0i"), Ok(Ior::Real(1.5)));
        assert_eq!(
            Ior::parse("1e0+2.5e-1i"),
            Ok(Ior::Complex(C::new(1.0, 0.25)))
        );
        assert_eq!(Ior::parse("keratin"), Ok(Ior::Keratin));
        assert_eq!(
            Ior::parse("cauchy(1.5,4200)"),
            Ok(Ior::Cauchy { a: 1.5, b: 4200.0 })
        );
        assert_eq!(Ior::parse("bk7"), Ok(Ior::Real(1.5046)));
        for s in [
            "1.56",
            "0.43+2.45i",
            "keratin",
            "cauchy(1.5,4200)",
            "Au",
            "TiO2",
        ] {
            let ior = Ior::parse(s).unwrap();
            assert_eq!(Ior::parse(&ior.to_string()), Ok(ior), "{s}");
        }
    }

    #[test]
    fn bad_indices_say_what_was_expected() {
        crate::test_util::assert_rejects(
            Ior::parse,
            &[
                ("-1.5", "> 0"),
                ("0", "> 0"),
                ("nan", "> 0"),
                ("1.5-0.1i", "gain"),
                ("abc+1i", "real part"),
                ("cauchy(1.5)", "cauchy(A,B)"),
                ("cauchy(1.5,-3)", "B"),
                ("unobtainium", "metal name"),
                ("none", "metal name"),
            ],
        );
        assert!(Ior::table(None, &[]).is_err());
        assert!(Ior::table(None, &[(500.0, 1.5, 0.0), (400.0, 1.5, 0.0)])
            .unwrap_err()
            .contains("row 2"));
        assert!(Ior::table(None, &[(500.0, 1.5, -1.0)]).is_err());
    }

    #[test]
    fn values_dispersion_and_tables() {
        // Keratin at 650 nm: 1.532 + 5890/650² = 1.545941…, the value research/thinfilm.md lists.
        let k = Ior::Keratin.at(650.0);
        assert!((k.re - (1.532 + 5890.0 / 422500.0)).abs() < 1e-15 && k.im == 0.0);
        assert!((k.re - 1.5459).abs() < 1e-4);
        assert_eq!(
            Ior::Keratin.at(500.0),
            Ior::Cauchy {
                a: 1.532,
                b: 5890.0
            }
            .at(500.0)
        );
        let t = Ior::table(None, &[(400.0, 1.0, 0.0), (600.0, 2.0, 1.0)]).unwrap();
        assert_eq!(t.at(500.0), C::new(1.5, 0.5));
        assert_eq!(t.at(300.0), C::new(1.0, 0.0));
        assert_eq!(t.at(900.0), C::new(2.0, 1.0));
        assert!(!t.is_lossless() && Ior::Keratin.is_lossless());
        // Gold from Mitsuba's measured data (see spectrum::ior's test: n 0.3504, k 2.7141 at 550).
        let au = Ior::named("Au").unwrap().at(550.0);
        assert!(
            (au.re - 0.3504).abs() < 1e-3 && (au.im - 2.7141).abs() < 1e-3,
            "{au}"
        );
        assert_eq!(Ior::named("water"), Some(Ior::Real(1.333)));
    }
}
