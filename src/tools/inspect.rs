//! Looking inside one BSDF of a scene (the logic of `ophis bsdf`): find a `<bsdf>` by id, build
//! its material, and estimate its directional albedo or f·cos for a direction pair, per
//! wavelength or as a linear-sRGB colour (reflectance under D65), with standard errors.
//!
//! Directions follow [`super::testing::direction`]: the incident direction is at polar angle
//! θi in the plane φ = 0, the outgoing one at (θo, φo); θ < 0 means below the surface.

use super::plot::{color_map, heat, Figure, Plot, PlotError, PolarChart};
use crate::bsdf::testing::{direction, Estimate};
use crate::bsdf::{Material, TransportMode};
use crate::math::Pcg32;
use crate::scene::mitsuba::{Node, Tag};
use crate::spectrum::{cie, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN, N};
use crate::texture::TexCoord;
use std::sync::Arc;

/// The `<bsdf>` node with this id anywhere in the tree (depth first).
pub fn find_bsdf<'a>(root: &'a Node, id: &str) -> Option<&'a Arc<Node>> {
    for c in &root.children {
        if c.node.tag == Tag::Bsdf && c.node.id.as_deref() == Some(id) {
            return Some(&c.node);
        }
        if let Some(n) = find_bsdf(&c.node, id) {
            return Some(n);
        }
    }
    None
}

/// Ids of every `<bsdf>` in the tree, for error messages.
pub fn bsdf_ids(root: &Node) -> Vec<String> {
    let mut out = Vec::new();
    fn visit(n: &Node, out: &mut Vec<String>) {
        for c in &n.children {
            if c.node.tag == Tag::Bsdf {
                if let Some(id) = &c.node.id {
                    if !out.contains(id) {
                        out.push(id.clone());
                    }
                }
            }
            visit(&c.node, out);
        }
    }
    visit(root, &mut out);
    out
}

/// What to estimate for one sample of the BSDF at given wavelengths.
#[derive(Clone, Copy, Debug)]
pub enum Quantity {
    /// Directional albedo for incidence at θi (degrees): mean of f·|cos|/pdf under sampling.
    Albedo { theta_i: f32 },
    /// f(wo, wi)·|cos θo| at the given angles (degrees).
    Eval {
        theta_i: f32,
        theta_o: f32,
        phi_o: f32,
    },
}

fn one_sample(m: &Material, q: Quantity, wl: &SampledWavelengths, rng: &mut Pcg32) -> [f32; N] {
    // A fresh seed per sample: a stochastic BSDF's value is a deterministic function of its
    // seed and the directions, so repeated pairs need new seeds to average.
    let seed = (rng.next_u32() as u64) << 32 | rng.next_u32() as u64;
    let (bxdf, two_sided) = m.eval(&TexCoord::default(), wl, true, seed);
    let flip = |mut w: crate::math::Vec3| {
        if two_sided && w.z < 0.0 {
            w.z = -w.z;
        }
        w
    };
    let mode = TransportMode::Radiance;
    match q {
        Quantity::Albedo { theta_i } => {
            let wo = flip(direction(theta_i, 0.0));
            let (uc, u) = (rng.next_f32(), rng.next_vec2());
            match bxdf.sample_f(wo, uc, u, mode) {
                Some(bs) if bs.pdf > 0.0 => (bs.f * (bs.wi.z.abs() / bs.pdf)).0,
                _ => [0.0; N],
            }
        }
        Quantity::Eval {
            theta_i,
            theta_o,
            phi_o,
        } => {
            let wo = direction(theta_i, 0.0);
            let wi = direction(theta_o, phi_o.to_radians());
            let s = if two_sided && wo.z < 0.0 { -1.0 } else { 1.0 };
            let (wo, wi) = (
                crate::math::Vec3::new(wo.x, wo.y, wo.z * s),
                crate::math::Vec3::new(wi.x, wi.y, wi.z * s),
            );
            (bxdf.f(wo, wi, mode) * wi.z.abs()).0
        }
    }
}

fn estimate(s: f64, s2: f64, n: usize) -> Estimate {
    let nf = n as f64;
    let mean = s / nf;
    Estimate {
        mean,
        std_err: ((s2 / nf - mean * mean).max(0.0) / (nf - 1.0).max(1.0)).sqrt(),
    }
}

/// The quantity at one wavelength (nm), from `n` samples.
pub fn at_wavelength(m: &Material, q: Quantity, lambda: f32, n: usize, seed: u64) -> Estimate {
    let wl = SampledWavelengths::fixed([lambda; N]);
    let mut rng = Pcg32::new(seed, 0xb5df);
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let v = one_sample(m, q, &wl, &mut rng)[0] as f64;
        s += v;
        s2 += v * v;
    }
    estimate(s, s2, n)
}

/// The quantity as a linear-sRGB reflectance colour: ∫ value(λ) D65(λ) x̄ȳz̄(λ) dλ over
/// ∫ D65 ȳ, by Monte Carlo over hero wavelengths drawn uniformly; `n` samples.
pub fn linear_srgb(m: &Material, q: Quantity, n: usize, seed: u64) -> [Estimate; 3] {
    let mut rng = Pcg32::new(seed, 0x5e6b);
    let range = LAMBDA_MAX - LAMBDA_MIN;
    // Normalisation: ∫ D65 ȳ dλ (1 nm midpoint rule).
    let norm: f64 = (0..range as usize)
        .map(|i| {
            let l = LAMBDA_MIN + i as f32 + 0.5;
            (cie::d65(l) * cie::xyz_bar(l)[1]) as f64
        })
        .sum();
    let (mut s, mut s2) = ([0.0f64; 3], [0.0f64; 3]);
    for _ in 0..n {
        let wl = SampledWavelengths::sample_uniform(rng.next_f32());
        let v = one_sample(m, q, &wl, &mut rng);
        let mut xyz = [0.0f32; 3];
        for (j, &l) in wl.lambda.iter().enumerate() {
            let b = cie::xyz_bar(l);
            let w = v[j] * cie::d65(l) * range / N as f32;
            for c in 0..3 {
                xyz[c] += w * b[c];
            }
        }
        let rgb = cie::xyz_to_linear_srgb(xyz.map(|x| x / norm as f32));
        for c in 0..3 {
            s[c] += rgb[c] as f64;
            s2[c] += (rgb[c] as f64).powi(2);
        }
    }
    std::array::from_fn(|c| estimate(s[c], s2[c], n))
}

/// Figures of the BSDF at wavelength `lambda`: a polar plot of f·cos θo in the plane of
/// incidence for θi = 0°, 30°, 60°, 75° (angles > 0 on the mirror side), and an image of f·cos θo
/// over the hemisphere (disc of sin θo, seen from above) for incidence at `theta_i`.
/// `samples` is spent over all points; returns the (polar, hemisphere) figures.
pub fn plots(
    m: &Material,
    lambda: f32,
    theta_i: f32,
    samples: usize,
    seed: u64,
) -> Result<(Figure, Figure), PlotError> {
    let per_point = (samples / 360).max(8);
    let mut chart = PolarChart::new(
        &format!("BSDF lobes in the plane of incidence, {lambda} nm"),
        "f·cos θo",
    );
    for (k, ti) in [0.0f32, 30.0, 60.0, 75.0].into_iter().enumerate() {
        let pts = (-44..=44)
            .map(|j| {
                let a = 2.0 * j as f32;
                let q = Quantity::Eval {
                    theta_i: ti,
                    theta_o: a.abs(),
                    phi_o: if a >= 0.0 { 180.0 } else { 0.0 },
                };
                let e = at_wavelength(
                    m,
                    q,
                    lambda,
                    per_point,
                    seed.wrapping_add(k as u64 * 1000 + (j + 44) as u64),
                );
                (a as f64, e.mean)
            })
            .collect();
        chart.add(&format!("θi = {ti}°"), pts);
    }
    let polar = chart.render(720, 460)?;
    let res = 64usize;
    let mut img = crate::image_io::RgbImage::new(res, res);
    let mut vals = vec![f32::NAN; res * res];
    let per_pixel = (samples / (res * res)).max(4);
    for y in 0..res {
        for x in 0..res {
            let (u, v) = (
                (x as f32 + 0.5) / res as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / res as f32 * 2.0,
            );
            let r2 = u * u + v * v;
            if r2 >= 1.0 {
                continue;
            }
            let q = Quantity::Eval {
                theta_i,
                theta_o: r2.sqrt().asin().to_degrees(),
                phi_o: v.atan2(u).to_degrees(),
            };
            vals[y * res + x] = at_wavelength(
                m,
                q,
                lambda,
                per_pixel,
                seed.wrapping_add(5000 + (y * res + x) as u64),
            )
            .mean as f32;
        }
    }
    let max = vals
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f32::max);
    for (p, v) in img.data.iter_mut().zip(&vals) {
        *p = if v.is_finite() {
            heat(*v, max)
        } else {
            [1.0; 3]
        };
    }
    let (hemi, _) = color_map(
        &img,
        (-1.0, 1.0),
        (-1.0, 1.0),
        &format!("f·cos θo, θi = {theta_i}°, max {max:.3}"),
        "sin θo cos φo",
        "sin θo sin φo",
        520,
        520,
    )?;
    Ok((polar, hemi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::Spectrum;
    use crate::texture::SpectrumTexture;

    #[test]
    fn white_lambertian_is_white_with_unit_albedo() {
        let m = Material::diffuse(SpectrumTexture::Constant(Spectrum::Constant(1.0)));
        let q = Quantity::Albedo { theta_i: 30.0 };
        let e = at_wavelength(&m, q, 550.0, 1000, 1);
        assert!((e.mean - 1.0).abs() < 1e-5);
        for c in linear_srgb(&m, q, 20_000, 2) {
            assert!((c.mean - 1.0).abs() <= 4.0 * c.std_err + 0.01, "{c:?}");
        }
        let f = at_wavelength(
            &m,
            Quantity::Eval {
                theta_i: 0.0,
                theta_o: 60.0,
                phi_o: 0.0,
            },
            500.0,
            10,
            3,
        );
        assert!((f.mean - 0.5 / std::f64::consts::PI).abs() < 1e-6);
    }

    #[test]
    fn plots_draw_the_lobes_and_the_hemisphere() {
        let m = Material::diffuse(SpectrumTexture::Constant(Spectrum::Constant(1.0)));
        let (polar, hemi) = plots(&m, 550.0, 30.0, 2000, 1).unwrap();
        assert_eq!((polar.width(), polar.height()), (720, 460));
        assert_eq!((hemi.width(), hemi.height()), (520, 520));
        let count = |f: &Figure, c: [u8; 3]| {
            (0..f.height() as i64)
                .flat_map(|y| (0..f.width() as i64).map(move |x| (x, y)))
                .filter(|&(x, y)| f.pixel(x, y) == Some(c))
                .count()
        };
        // A Lambertian lobe does not depend on θi: the four coincide and the last one drawn
        // covers the others, which show in the legend.
        let palette = &super::super::plot::PALETTE;
        for (k, c) in palette[..4].iter().enumerate() {
            let n = count(&polar, [c.0, c.1, c.2]);
            assert!(n >= 40 && (k < 3 || n > 400), "lobe {k}: {n} pixels");
        }
        // A Lambertian f·cos θo peaks at the normal: the centre of the disc has the ramp's top
        // colour, and the corners outside the disc stay white.
        let top =
            heat(1.0, 1.0).map(|v| (crate::image_io::linear_to_srgb(v) * 255.0).round() as u8);
        assert!(count(&hemi, top) > 20);
        assert!(count(&hemi, [255; 3]) > 520 * 520 / 10);
    }
}
