//! The library side of `ophis thinfilm`: a film or stack described on the command line, its
//! reflectance table as CSV, the colour of reflected daylight, and the thickness × angle colour
//! chart. Kept here (not in the binary) so that it is tested.
//!
//! Colour: the film reflects D65; XYZ = ∫ R(λ) D65(λ) (x̄, ȳ, z̄)(λ) dλ / ∫ D65 ȳ dλ over
//! 360–830 nm at 1 nm (the CIE tables' own spacing), then linear sRGB. A perfect reflector
//! (R ≡ 1) is exactly white (1, 1, 1) (see [`crate::spectrum::cie`]).
//!
//! Angles are in degrees from the normal on the side the light comes from; `from_inside` means
//! from the base (see [`FilmStack::rt`]). The chart's thickness axis is the stack's total
//! thickness, all layers scaled together (for one film: the film's thickness).

use super::filmstack::FilmStack;
use super::ior::Ior;
use super::thinfilm::FilmRt;
use crate::spectrum::cie::{d65, xyz_bar, xyz_to_linear_srgb, CIE_Y_INTEGRAL};
use std::fmt::Write;

/// s, p, reflectance and transmittance at `angle_deg` from the normal and `lambda` nm. For a
/// metal base, T is the power that enters the metal (and is absorbed there).
pub fn rt_deg(stack: &FilmStack, angle_deg: f64, lambda: f64, from_inside: bool) -> FilmRt {
    stack.rt(angle_deg.to_radians().cos().max(0.0), lambda, from_inside)
}

/// Linear sRGB of D65 reflected at `angle_deg`.
pub fn stack_rgb(stack: &FilmStack, angle_deg: f64, from_inside: bool) -> [f64; 3] {
    reflected_rgb(|l| rt_deg(stack, angle_deg, l, from_inside).r(), 1)
}

/// Colour chart: `width` total thicknesses over `[d0, d1]` (left to right; every layer scaled by
/// the same factor) × `height` angles over 0–90° (bottom to top), rows top first, each pixel
/// sampled at its centre; `step_nm` is the spectral integration step. Errors if the stack has no
/// thickness to scale.
#[allow(clippy::too_many_arguments)]
pub fn chart(
    stack: &FilmStack,
    d0: f64,
    d1: f64,
    width: usize,
    height: usize,
    step_nm: usize,
    from_inside: bool,
) -> Result<Vec<[f32; 3]>, String> {
    let total = stack.total_thickness();
    if !(total > 0.0) {
        return Err("the chart scales the stack's thicknesses, but they are all 0 nm".into());
    }
    let step = step_nm.max(1);
    let lambdas: Vec<f32> = (360..=830).step_by(step).map(|l| l as f32).collect();
    let mut out = vec![[0.0f32; 3]; width * height];
    let mut r = vec![0.0f64; lambdas.len()];
    for col in 0..width {
        let d = d0 + (d1 - d0) * (col as f64 + 0.5) / width as f64;
        let st = stack.scaled(d / total);
        // Four wavelengths at a time through the rendering evaluator (equal to the exact path
        // to 1e-12; the last group repeats its final wavelength).
        let evs: Vec<_> = lambdas
            .chunks(4)
            .map(|c| st.prepare(std::array::from_fn(|i| c[i.min(c.len() - 1)]), 1.0))
            .collect();
        for row in 0..height {
            let a = 90.0 * (height - row) as f64 - 45.0;
            let a = a / height as f64;
            let cos = a.to_radians().cos().max(0.0);
            for (k, ev) in evs.iter().enumerate() {
                let rr = ev.rt(cos, from_inside).r();
                for (i, v) in r[4 * k..].iter_mut().take(4).enumerate() {
                    *v = rr[i];
                }
            }
            let c = reflected_rgb(|l| r[(l as usize - 360) / step], step);
            out[row * width + col] = c.map(|v| v as f32);
        }
    }
    Ok(out)
}

/// Linear sRGB of D65 reflected by a surface of reflectance `r(λ)`, integrated over 360–830 nm
/// every `step_nm` nm (1 for reference values); R ≡ 1 gives (1, 1, 1).
pub fn reflected_rgb(r: impl Fn(f64) -> f64, step_nm: usize) -> [f64; 3] {
    let mut xyz = [0.0f64; 3];
    let mut l = 360usize;
    while l <= 830 {
        let lf = l as f32;
        let w = r(l as f64) * d65(lf) as f64 * step_nm as f64;
        let b = xyz_bar(lf);
        for i in 0..3 {
            xyz[i] += w * b[i] as f64;
        }
        l += step_nm.max(1);
    }
    let xyz = xyz.map(|v| (v / CIE_Y_INTEGRAL as f64) as f32);
    xyz_to_linear_srgb(xyz).map(|v| v as f64)
}

/// Parses `START:END:STEP` (inclusive of END when it falls on the grid) or a single number.
/// `what` names the argument in messages.
pub fn parse_range(what: &str, s: &str) -> Result<Vec<f64>, String> {
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{what}: '{t}' is not a finite number (in '{s}')"))
    };
    let parts: Vec<&str> = s.split(':').collect();
    match parts.as_slice() {
        [v] => Ok(vec![num(v)?]),
        [a, b, st] => {
            let (a, b, st) = (num(a)?, num(b)?, num(st)?);
            if st.is_nan() || st <= 0.0 {
                return Err(format!("{what}: the step must be positive, got {st}"));
            }
            if b < a {
                return Err(format!("{what}: the end {b} is below the start {a}"));
            }
            let n = ((b - a) / st + 1e-9).floor() as usize + 1;
            if n > 1_000_000 {
                return Err(format!("{what}: {n} values is too many"));
            }
            Ok((0..n).map(|i| a + i as f64 * st).collect())
        }
        _ => Err(format!(
            "{what}: expected START:END:STEP or a number, got '{s}'"
        )),
    }
}

/// Parses `A:B` (A < B).
pub fn parse_interval(what: &str, s: &str) -> Result<(f64, f64), String> {
    let v: Vec<&str> = s.split(':').collect();
    let num = |t: &str| t.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    match v.as_slice() {
        [a, b] => match (num(a), num(b)) {
            (Some(a), Some(b)) if a < b => Ok((a, b)),
            (Some(_), Some(_)) => Err(format!("{what}: the start must be below the end in '{s}'")),
            _ => Err(format!("{what}: '{s}' is not two finite numbers A:B")),
        },
        _ => Err(format!("{what}: expected A:B, got '{s}'")),
    }
}

/// Parses a comma-separated list of finite numbers.
pub fn parse_list(what: &str, s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("{what}: '{t}' is not a finite number (in '{s}')"))
        })
        .collect()
}

/// An index argument: anything [`Ior::parse`] reads (a number, `n+ki`, `keratin`,
/// `cauchy(A,B)`, a dielectric or metal name); `what` names the argument in the message.
pub fn parse_index(what: &str, s: &str) -> Result<Ior, String> {
    Ior::parse(s).map_err(|e| format!("{what}: {e}"))
}

/// Checks angles (0–90°) and wavelengths (positive); the errors name the argument.
pub fn check_grid(angles: &[f64], wavelengths: &[f64]) -> Result<(), String> {
    if let Some(a) = angles.iter().find(|a| !(0.0..=90.0).contains(*a)) {
        return Err(format!("--angles: {a} is outside 0–90 degrees"));
    }
    if let Some(l) = wavelengths.iter().find(|l| l.is_nan() || **l <= 0.0) {
        return Err(format!(
            "--wavelengths: {l} nm is not a positive wavelength"
        ));
    }
    Ok(())
}

/// The table `wavelength_nm,angle_deg,R_s,R_p,R,T`, angles outer, wavelengths inner.
pub fn csv(stack: &FilmStack, angles: &[f64], wavelengths: &[f64], from_inside: bool) -> String {
    let mut s = String::from("wavelength_nm,angle_deg,R_s,R_p,R,T\n");
    for &a in angles {
        for &l in wavelengths {
            let rt = rt_deg(stack, a, l, from_inside);
            let _ = writeln!(
                s,
                "{l},{a},{:.8},{:.8},{:.8},{:.8}",
                rt.r_s,
                rt.r_p,
                rt.r(),
                rt.t()
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bubble() -> FilmStack {
        FilmStack::film(Ior::Real(1.0), Ior::Real(1.56), 900.0, Ior::Real(1.0)).unwrap()
    }

    #[test]
    fn white_is_white_and_t6_colours() {
        let w = reflected_rgb(|_| 1.0, 1);
        assert!(w.iter().all(|v| (v - 1.0).abs() < 1e-3), "{w:?}");
        // research §8 T6 (CIE-integrated with the Wyman 2013 analytic CMF fit): 0° (0.120, 0.073,
        // 0.093), 60° (0.088, 0.177, 0.150). The tabulated CMFs used here differ from that fit;
        // research asks for agreement within ~0.02 between such integrations.
        for (a, want) in [(0.0, [0.120, 0.073, 0.093]), (60.0, [0.088, 0.177, 0.150])] {
            let c = stack_rgb(&bubble(), a, false);
            for i in 0..3 {
                assert!((c[i] - want[i]).abs() < 0.02, "{a}: {c:?} vs {want:?}");
            }
        }
    }

    #[test]
    fn csv_columns_and_values() {
        let t = csv(&bubble(), &[0.0, 45.0], &[510.0, 550.0], false);
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines[0], "wavelength_nm,angle_deg,R_s,R_p,R,T");
        assert_eq!(lines.len(), 5);
        let row =
            |i: usize| -> Vec<f64> { lines[i].split(',').map(|v| v.parse().unwrap()).collect() };
        let r0 = row(1);
        assert_eq!((r0[0], r0[1]), (510.0, 0.0));
        assert!((r0[4] - 0.174275).abs() < 1e-6 && (r0[4] + r0[5] - 1.0).abs() < 1e-7);
        let r = row(4);
        assert!(
            (r[2] - 0.341236).abs() < 1e-6 && (r[3] - 0.043006).abs() < 1e-6,
            "{r:?}"
        );
    }

    #[test]
    fn argument_errors_name_the_argument() {
        assert_eq!(
            parse_range("--wavelengths", "400:700:100").unwrap().len(),
            4
        );
        for bad in [
            "400:700:0",
            "400:700:-5",
            "700:400:5",
            "400:nan:5",
            "a",
            "1:2",
        ] {
            let e = parse_range("--wavelengths", bad).unwrap_err();
            assert!(e.starts_with("--wavelengths"), "{e}");
        }
        assert!(parse_interval("--thickness-range", "100:50").is_err());
        let e = parse_index("--ext-ior", "-1").unwrap_err();
        assert!(e.starts_with("--ext-ior") && e.contains("> 0"), "{e}");
        assert!(parse_index("--ext-ior", "unobtainium").is_err());
        assert_eq!(parse_index("--film-ior", "keratin"), Ok(Ior::Keratin));
        assert!(check_grid(&[95.0], &[500.0])
            .unwrap_err()
            .starts_with("--angles"));
        assert!(parse_list("--angles", "0,x").is_err());
    }

    #[test]
    fn chart_orientation_and_thickness_axis() {
        // Top row is near grazing (brighter: R grows towards 1); bottom-left is a 1 nm film at
        // 0.5°, which between equal media reflects almost nothing.
        let c = chart(&bubble(), 0.0, 200.0, 100, 90, 5, false).unwrap();
        let row_mean = |r: usize| c[r * 100..(r + 1) * 100].iter().map(|p| p[1]).sum::<f32>();
        assert!(row_mean(0) > 3.0 * row_mean(89));
        let bottom_left = c[89 * 100];
        assert!(bottom_left.iter().all(|v| *v < 1e-3), "{bottom_left:?}");
        // Column 37 of a 0–200 nm axis is a 75 nm film (centre of the pixel), row 45 is 44.5°.
        let film75 =
            FilmStack::film(Ior::Real(1.0), Ior::Real(1.56), 75.0, Ior::Real(1.0)).unwrap();
        let want = reflected_rgb(|l| rt_deg(&film75, 44.5, l, false).r(), 5);
        let got = c[45 * 100 + 37];
        for i in 0..3 {
            assert!(
                (got[i] as f64 - want[i]).abs() < 1e-6,
                "{got:?} vs {want:?}"
            );
        }
        // A stack with no thickness has no axis to scale.
        let zero = FilmStack::film(Ior::Real(1.0), Ior::Real(1.56), 0.0, Ior::Real(1.0)).unwrap();
        assert!(chart(&zero, 0.0, 100.0, 4, 4, 5, false)
            .unwrap_err()
            .contains("0 nm"));
    }
}
