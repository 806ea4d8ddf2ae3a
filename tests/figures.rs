//! Checks on the thesis figures' physics, rendered tiny:
//!
//! - the film-thickness sweep (figure 4.8 on the film of figure 4.3) moves the hue as theory
//!   predicts: the mean colour of the film-only sphere near normal incidence matches
//!   `ophis thinfilm --rgb`'s prediction (`FilmStack::reflected_rgb`) averaged over the same
//!   angles, within 4 standard errors plus a stated quadrature allowance;
//! - the absorption figure (4.5) darkens monotonically with the layer's thickness, each step
//!   resolved by more than 4 standard errors.

use ophis::image_io::RgbImage;
use ophis::optics::filmstack::FilmStack;
use ophis::optics::filmtool::{reflected_rgb, rt_deg};
use ophis::optics::ior::Ior;
use ophis::tools::preview::render_file;
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// Per-channel mean and standard error of the mean over the pixels in `[x0, x1) × [y0, y1)`.
/// Pixels are independent estimates; their spread also holds the image's real variation, so
/// the error is an overestimate (a conservative tolerance).
fn mean_se(img: &RgbImage, x0: usize, x1: usize, y0: usize, y1: usize) -> ([f64; 3], [f64; 3]) {
    let mut s = [0.0f64; 3];
    let mut s2 = [0.0f64; 3];
    let mut n = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            let p = img.data[y * img.width + x];
            for c in 0..3 {
                s[c] += p[c] as f64;
                s2[c] += (p[c] as f64).powi(2);
            }
            n += 1.0;
        }
    }
    let mean = s.map(|v| v / n);
    let se = std::array::from_fn(|c| ((s2[c] / n - mean[c].powi(2)).max(0.0) / (n - 1.0)).sqrt());
    (mean, se)
}

/// Half-width of the patch of the unit sphere the film test looks at (as a fraction of the
/// radius): the view spans |x|, |y| ≤ H, so angles of incidence stay below asin(H·√2) ≈ 8°.
const H: f64 = 0.1;
const CAM_DIST: f64 = 100.0;

/// The thesis's figure 4.3 material (scenes/parts/mat-film.xml, included by path) on a unit
/// sphere around a black core, under a uniform white sky (linear sRGB 1 = normalised D65, the
/// illuminant `reflected_rgb` assumes), seen almost orthographically: each pixel shows R(θ)
/// of the film at one angle θ, nothing behind it (light through the film dies in the core).
fn film_scene(dir: &Path) -> PathBuf {
    let mat = scenes_dir().join("parts").join("mat-film.xml");
    let fov = 2.0 * (H / (CAM_DIST - 1.0)).atan().to_degrees();
    let xml = format!(
        r#"<scene version="3.0.0">
    <default name="mode" value="spectral"/>
    <default name="int_ior" value="1.0"/>
    <default name="film_ior" value="1.56"/>
    <integrator type="path"><integer name="max_depth" value="8"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="{fov}"/>
        <transform name="to_world"><lookat origin="0, 0, {CAM_DIST}" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <include filename="{}"/>
    <shape type="sphere"><float name="radius" value="1"/><ref id="skin"/></shape>
    <shape type="sphere"><float name="radius" value="0.5"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
    </shape>
</scene>"#,
        mat.display()
    );
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join("film-sphere.xml");
    std::fs::write(&path, xml).unwrap();
    path
}

/// The colour `ophis thinfilm --rgb` predicts, averaged over the patch: a point (x, y) of the
/// view hits the sphere at angle of incidence asin(√(x² + y²)) (orthographic to 1 part in
/// 10⁴ at distance 100). Midpoint rule on a 24 × 24 grid, spectral step 2 nm.
fn predicted(d_nm: f64) -> [f64; 3] {
    let stack = FilmStack::film(Ior::Real(1.0), Ior::Real(1.56), d_nm, Ior::Real(1.0)).unwrap();
    let n = 24;
    let mut acc = [0.0; 3];
    for i in 0..n {
        for j in 0..n {
            let x = H * (2.0 * (i as f64 + 0.5) / n as f64 - 1.0);
            let y = H * (2.0 * (j as f64 + 0.5) / n as f64 - 1.0);
            let theta = (x * x + y * y).sqrt().asin().to_degrees();
            let c = reflected_rgb(|l| rt_deg(&stack, theta, l, false).r(), 2);
            for k in 0..3 {
                acc[k] += c[k] / (n * n) as f64;
            }
        }
    }
    acc
}

#[test]
fn film_thickness_sweep_matches_thin_film_theory() {
    let dir = std::env::temp_dir().join(format!("ophis-figures-{}", std::process::id()));
    let scene = film_scene(&dir);
    // Allowance for the prediction's quadrature (24² angles, 2 nm steps) and the pixel filter
    // blurring the patch edge: R changes by < 0.01 over the patch, so its mean by far less.
    const QUAD: f64 = 0.004;
    let mut preds = Vec::new();
    for d in [300.0, 600.0, 900.0] {
        let defines = vec![("thickness".to_string(), format!("{d}"))];
        let (img, warnings) = render_file(&scene, &defines, (16, 16), 64).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        let (mean, se) = mean_se(&img, 0, 16, 0, 16);
        let p = predicted(d);
        for c in 0..3 {
            let tol = 4.0 * se[c] + QUAD;
            assert!(
                (mean[c] - p[c]).abs() <= tol,
                "{d} nm, channel {c}: rendered {mean:?} ± {se:?}, theory {p:?} (tolerance {tol})"
            );
        }
        eprintln!("{d} nm: rendered {mean:.4?} ± {se:.4?}, theory {p:.4?}");
        preds.push((d, p, mean, se));
    }
    // The sweep must show a change the test can see: every pair of thicknesses differs in
    // colour by more than the tolerance (otherwise a renderer ignoring thickness would pass).
    for a in 0..preds.len() {
        for b in a + 1..preds.len() {
            let (pa, pb) = (preds[a].1, preds[b].1);
            let (sa, sb) = (preds[a].3, preds[b].3);
            let resolved =
                (0..3).any(|c| (pa[c] - pb[c]).abs() > 4.0 * (sa[c] + sb[c]) + 2.0 * QUAD);
            assert!(
                resolved,
                "{} vs {} nm: {pa:?} vs {pb:?}",
                preds[a].0, preds[b].0
            );
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn absorption_darkens_monotonically_with_thickness() {
    let scene = scenes_dir().join("thesis").join("fig4-5-absorption.xml");
    let mut prev: Option<(f64, f64, f64)> = None;
    for depth in [0.0, 0.5, 1.0, 2.0, 4.0] {
        let defines = vec![
            ("shape".to_string(), "sphere".to_string()),
            ("depth".to_string(), format!("{depth}")),
        ];
        let (img, warnings) = render_file(&scene, &defines, (16, 16), 16).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        // The central 6 × 6 pixels lie on the sphere (it fills the middle of the frame).
        let (m, se) = mean_se(&img, 5, 11, 5, 11);
        let lum = 0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2];
        let lum_se = 0.2126 * se[0] + 0.7152 * se[1] + 0.0722 * se[2]; // upper bound
        if let Some((d0, l0, s0)) = prev {
            assert!(
                l0 - lum > 4.0 * (s0 * s0 + lum_se * lum_se).sqrt(),
                "depth {d0} → {depth}: luminance {l0} ± {s0} → {lum} ± {lum_se} is not darker"
            );
        }
        eprintln!("depth {depth}: luminance {lum:.4} ± {lum_se:.4}");
        prev = Some((depth, lum, lum_se));
    }
}
