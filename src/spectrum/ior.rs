//! Named indices of refraction: Mitsuba 3's dielectric and conductor names, and the keratin
//! dispersion used for reptile and bird integument.
//!
//! - Dielectrics ([`dielectric_ior`]): the constant indices Mitsuba 3 documents for its
//!   `int_ior` / `ext_ior` names (Mitsuba 3 reference manual, "dielectric" plugin);
//!   `tools/gen_spectral_data.py` checks this table against the `mitsuba` Python package.
//! - Conductors ([`conductor_nk`]): measured complex index n + ik for the names of Mitsuba's
//!   `conductor` plugin's `material` parameter, from the `.spd` files Mitsuba ships (luxpop.com,
//!   mostly E. D. Palik, "Handbook of Optical Constants of Solids", 1985), converted to
//!   `data/ior/<name>.csv` (λ in nm, 300–900 nm) by `tools/gen_spectral_data.py` and embedded at
//!   build time. Rows the source marks as missing (n = 0; only AlAs near 400 nm) are dropped, so
//!   there the curves interpolate across the gap where Mitsuba would use n = 0. Curves are piecewise linear in λ and constant beyond the measured range. Names
//!   are case-sensitive, as in Mitsuba (`"Au"`, `"Cu_palik"`, `"a-C"`).
//! - `"none"` is Mitsuba's perfect mirror (reflectance 1 at every angle). It has no finite n, k,
//!   so [`conductor_nk`] returns `None` for it; callers check for `"none"` before looking up a
//!   material and build a mirror themselves.
//! - Keratin ([`keratin_ior`]): n(λ) = 1.532 + 5890 nm² / λ², the Cauchy fit of Leertouwer, Wilts
//!   & Stavenga 2011, "Refractive index and dispersion of butterfly chitin and bird keratin
//!   measured by polarizing interference microscopy", Opt. Express 19(24):24061.

use super::spectra::{PiecewiseLinear, Spectrum};
use std::sync::{Arc, OnceLock};

// `CONDUCTORS: &[(&str, &str)]`, (name, CSV text) for every file in data/ior, sorted by name.
include!(concat!(env!("OUT_DIR"), "/ior_data.rs"));

/// Mitsuba 3's named dielectric indices (as `mitsuba.load_dict` resolves them).
const DIELECTRICS: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The index of a named dielectric (Mitsuba's names, e.g. `"bk7"`, `"water"`), `None` if unknown.
pub fn dielectric_ior(name: &str) -> Option<f32> {
    DIELECTRICS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|&(_, v)| v)
}

/// Names accepted by [`dielectric_ior`].
pub fn dielectric_names() -> impl Iterator<Item = &'static str> {
    DIELECTRICS.iter().map(|(n, _)| *n)
}

type Nk = (Arc<PiecewiseLinear>, Arc<PiecewiseLinear>);

/// Parses one `λ,n,k` CSV; `None` if it is malformed (the build would still succeed, so a bad
/// file makes its name unknown rather than panicking at run time).
fn parse(text: &str) -> Option<Nk> {
    let (mut l, mut n, mut k) = (Vec::new(), Vec::new(), Vec::new());
    for line in text.lines() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut f = line.split(',').map(|x| x.trim().parse::<f32>());
        match (f.next(), f.next(), f.next(), f.next()) {
            (Some(Ok(a)), Some(Ok(b)), Some(Ok(c)), None) => {
                l.push(a);
                n.push(b);
                k.push(c);
            }
            _ => return None,
        }
    }
    let eta = PiecewiseLinear::new(l.clone(), n)?;
    let k = PiecewiseLinear::new(l, k)?;
    Some((Arc::new(eta), Arc::new(k)))
}

fn conductors() -> &'static [Option<Nk>] {
    static TABLE: OnceLock<Vec<Option<Nk>>> = OnceLock::new();
    TABLE.get_or_init(|| CONDUCTORS.iter().map(|(_, text)| parse(text)).collect())
}

/// Measured (n, k) of a named conductor (Mitsuba's names, e.g. `"Au"`, `"Cu"`, `"Al"`) as curves
/// over λ in nm. `None` for unknown names and for `"none"` (the perfect mirror, which the caller
/// handles itself).
pub fn conductor_nk(name: &str) -> Option<(Spectrum, Spectrum)> {
    let i = CONDUCTOR_NAMES.binary_search(&name).ok()?;
    let (eta, k) = conductors()[i].clone()?;
    Some((Spectrum::PiecewiseLinear(eta), Spectrum::PiecewiseLinear(k)))
}

/// Names accepted by [`conductor_nk`], sorted (`"none"` is not among them).
pub fn conductor_names() -> &'static [&'static str] {
    CONDUCTOR_NAMES
}

/// Refractive index of keratin at `lambda_nm`: 1.532 + 5890 / λ² (Leertouwer et al. 2011).
pub fn keratin_ior(lambda_nm: f32) -> f32 {
    1.532 + 5890.0 / (lambda_nm * lambda_nm)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gold_at_550nm_matches_palik() {
        let (n, k) = conductor_nk("Au").unwrap();
        // Mitsuba's Au.eta.spd / Au.k.spd (luxpop): (539.06 nm, n 0.402, k 2.54) and
        // (551.04 nm, n 0.3455, k 2.7306); linear interpolation at 550 nm gives n 0.3504,
        // k 2.7141. (Johnson & Christy 1972 give n ≈ 0.43, k ≈ 2.45 there; the datasets differ.)
        // The tolerance is f32 rounding of the interpolation.
        let (n, k) = (n.eval(550.0), k.eval(550.0));
        assert!((n - 0.3504).abs() < 1e-3, "n {n}");
        assert!((k - 2.7141).abs() < 1e-3, "k {k}");
    }

    #[test]
    fn every_conductor_parses_and_is_physical() {
        assert!(conductor_names().len() >= 60);
        for &name in conductor_names() {
            let (n, k) = conductor_nk(name).unwrap_or_else(|| panic!("{name} did not parse"));
            for l in (360..=830).step_by(10) {
                let (n, k) = (n.eval(l as f32), k.eval(l as f32));
                assert!(
                    n > 0.0 && n < 10.0 && (0.0..20.0).contains(&k),
                    "{name} at {l}: {n} {k}"
                );
            }
        }
        // Copper: red, because k rises (and n falls) past ~570 nm.
        let (n, _) = conductor_nk("Cu").unwrap();
        assert!(n.eval(450.0) > 1.0 && n.eval(700.0) < 0.3);
    }

    #[test]
    fn names_and_unknowns() {
        assert_eq!(dielectric_ior("bk7"), Some(1.5046));
        assert_eq!(dielectric_ior("water"), Some(1.333));
        assert_eq!(dielectric_ior("diamond"), Some(2.419));
        assert_eq!(dielectric_ior("BK7 "), None);
        assert_eq!(dielectric_ior("unobtainium"), None);
        assert_eq!(dielectric_names().count(), 23);
        assert!(conductor_nk("unobtainium").is_none());
        assert!(conductor_nk("none").is_none());
        assert!(conductor_nk("").is_none());
        assert!(conductor_names().windows(2).all(|w| w[0] < w[1]));
        for m in [
            "Ag", "Al", "Au", "Cr", "Cu", "W", "a-C", "Cu_palik", "Ni_palik",
        ] {
            assert!(conductor_nk(m).is_some(), "{m}");
        }
    }

    #[test]
    fn keratin_dispersion() {
        // 1.532 + 5890 / 650² = 1.54594.
        assert!((keratin_ior(650.0) - 1.5459).abs() < 1e-4);
        assert!(keratin_ior(400.0) > keratin_ior(700.0));
    }
}
