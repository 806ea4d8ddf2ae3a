//! Thin films end to end: the plugins and the seed's aliases load (0.6 and 3 spellings), bad
//! parameters are errors naming file:line, and a small render shows the difference between the
//! exact spectral film and the thesis's three point samples in the direction the physics
//! predicts.

mod common;
use common::{mean_stderr, render_rgb, scene};
use ophis::bsdf::filmfresnel::{thesis_reflectance, THESIS_LAMBDA};
use ophis::integrator::PathStrategy;
use ophis::optics::filmtool::reflected_rgb;
use ophis::optics::thinfilm::film_reflectance;
use ophis::scene::build::{load_scene_str, LoadOptions};
use ophis::spectrum::rgb2spec::rgb_to_sigmoid;
use std::path::Path;

fn load(xml: &str) -> Result<usize, String> {
    load_scene_str(xml, Path::new("test.xml"), &LoadOptions::default())
        .map(|(s, _)| s.materials.len())
        .map_err(|e| e.to_string())
}

fn with_bsdf(version: &str, bsdf: &str) -> String {
    format!(
        r#"<scene version="{version}">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
    <shape type="sphere">
{bsdf}
    </shape>
</scene>"#
    )
}

#[test]
fn film_plugins_and_seed_aliases_load() {
    let v3 = [
        r#"<bsdf type="thinfilm"><float name="int_ior" value="1.33"/><string name="film_ior" value="keratin"/>
            <float name="film_thickness" value="900"/><string name="mode" value="thesis"/></bsdf>"#,
        r#"<bsdf type="roughthinfilm"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/>
            <float name="film_ior" value="1.56"/><texture type="checkerboard" name="film_thickness">
            <float name="color0" value="300"/><float name="color1" value="900"/></texture></bsdf>"#,
        r#"<bsdf type="thinfilmconductor"><string name="material" value="Au"/><string name="film_ior" value="water"/></bsdf>"#,
        r#"<bsdf type="roughthinfilmconductor"><spectrum name="eta" value="0.43"/><spectrum name="k" value="2.45"/>
            <float name="alpha" value="0.3"/></bsdf>"#,
    ];
    for b in v3 {
        assert_eq!(load(&with_bsdf("3.0.0", b)), Ok(1), "{b}");
    }
    // The seed's plugins in the 0.6 dialect (camelCase names, upgraded on load).
    let v06 = [
        r#"<bsdf type="dielectricThinFilm"><float name="intIOR" value="1.0"/><float name="extIOR" value="1.0"/>
            <float name="mediumIOR" value="1.56"/><float name="thickness" value="900"/></bsdf>"#,
        r#"<bsdf type="roughdielectricThinFilm"><float name="alpha" value="0.1"/><string name="distribution" value="beckmann"/>
            <float name="mediumIOR" value="1.56"/><float name="thickness" value="600"/></bsdf>"#,
        r#"<bsdf type="conductorThinFilm"><string name="material" value="Cu"/><float name="thickness" value="300"/>
            <float name="mediumIOR" value="1.4"/></bsdf>"#,
    ];
    for b in v06 {
        assert_eq!(load(&with_bsdf("0.6.0", b)), Ok(1), "{b}");
    }
}

fn assert_error_at(bsdf: &str, what: &str) {
    // The <bsdf> starts on line 4 of `with_bsdf`; its parameters are on that line too.
    let e = load(&with_bsdf("3.0.0", bsdf)).expect_err(bsdf);
    assert!(e.contains("test.xml:4:"), "no file:line in: {e}");
    assert!(e.to_lowercase().contains(what), "'{what}' not in: {e}");
}

#[test]
fn bad_film_parameters_are_errors_naming_the_line() {
    assert_error_at(
        r#"<bsdf type="thinfilm"><float name="film_thickness" value="-5"/></bsdf>"#,
        "film_thickness",
    );
    assert_error_at(
        r#"<bsdf type="thinfilm"><float name="thickness" value="nan"/></bsdf>"#,
        "thickness",
    );
    assert_error_at(
        r#"<bsdf type="thinfilm"><float name="film_ior" value="-1.5"/></bsdf>"#,
        "film_ior",
    );
    assert_error_at(
        r#"<bsdf type="thinfilm"><string name="film_ior" value="unobtainium"/></bsdf>"#,
        "unobtainium",
    );
    assert_error_at(
        r#"<bsdf type="thinfilm"><float name="int_ior" value="0"/></bsdf>"#,
        "int_ior",
    );
    assert_error_at(
        r#"<bsdf type="thinfilm"><string name="mode" value="rgb"/></bsdf>"#,
        "mode",
    );
    assert_error_at(
        r#"<bsdf type="thinfilmconductor"><string name="material" value="none"/></bsdf>"#,
        "none",
    );
    assert_error_at(
        r#"<bsdf type="thinfilm"><float name="film_ior" value="1.5"/><float name="medium_ior" value="1.4"/></bsdf>"#,
        "not both",
    );
}

/// The bubble sphere (1.0 | 1.56, 900 nm | 1.0), reflection only (transmittance 0), under a
/// white constant environment, seen from distance 5 with an 8° field of view: the image holds
/// only the sphere's central cap, incidence angles 0–17°, where the fringes alias most in RGB
/// (averaged over a whole sphere the two modes differ by less than 0.01).
fn bubble_xml(mode: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="4"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="{FOV}"/>
        <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="48"/></sampler>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <shape type="sphere"><float name="radius" value="1"/>
        <bsdf type="thinfilm"><float name="int_ior" value="1.0"/><float name="ext_ior" value="1.0"/>
            <float name="film_ior" value="1.56"/><float name="film_thickness" value="900"/>
            <string name="mode" value="{mode}"/><float name="specular_transmittance" value="0"/></bsdf>
    </shape>
</scene>"#
    )
}

const N: usize = 24;
const FOV: f64 = 8.0;

/// Cosine of incidence at the sphere for the ray through the pixel's centre, if it hits well
/// inside the silhouette (the whole pixel on the sphere).
fn pixel_cos(x: usize, y: usize) -> Option<f64> {
    let t = (FOV / 2.0).to_radians().tan();
    let dir = |px: f64, py: f64| {
        let v = [
            (2.0 * px / N as f64 - 1.0) * t,
            (1.0 - 2.0 * py / N as f64) * t,
            -1.0,
        ];
        let l = (v[0] * v[0] + v[1] * v[1] + 1.0).sqrt();
        v.map(|c| c / l)
    };
    let limit = (1.0f64 / 5.0).asin();
    let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
        .map(|(a, b)| (-dir(x as f64 + a, y as f64 + b)[2]).acos());
    if !corners.iter().all(|&a| a < limit * 0.97) {
        return None;
    }
    // Ray o = (0,0,5), unit d: nearest root of |o + s d|² = 1; cos θ = −d·n.
    let d = dir(x as f64 + 0.5, y as f64 + 0.5);
    let b = 5.0 * d[2];
    let s = -b - (b * b - 24.0).sqrt();
    let p = [s * d[0], s * d[1], 5.0 + s * d[2]];
    Some(-(d[0] * p[0] + d[1] * p[1] + d[2] * p[2]))
}

#[test]
fn spectral_and_thesis_bubbles_differ_as_predicted() {
    // The check: for each pixel wholly on the sphere, predict its colour as D65 reflected by
    // (a) the exact film R(λ, θ) (spectral mode) and (b) the thesis's point samples at
    // 650/510/475 nm uplifted to a smooth spectrum (thesis mode), both integrated against the
    // CIE curves; average over the pixels. At 900 nm the fringes are narrower than a channel,
    // so near normal incidence (a) is a dull purple-grey, about (0.12, 0.07, 0.09), while (b)
    // is the green-yellow of (0.13, 0.17, 0.02) (research §8 T6); the rendered means must differ
    // with the same sign in every channel where the predicted difference exceeds 0.01, by more
    // than 4 standard errors, and by about the predicted amount.
    let mut pred = [[0.0f64; 3]; 2];
    let mut count = 0.0;
    for y in 0..N {
        for x in 0..N {
            let Some(c) = pixel_cos(x, y) else { continue };
            count += 1.0;
            let exact = reflected_rgb(|l| film_reflectance(c, 1.0, 1.56, 900.0, 1.0, l), 2);
            let rgb = THESIS_LAMBDA
                .map(|l| thesis_reflectance(c, 1.0, 1.56, 900.0, 1.0, l as f64) as f32);
            let poly = rgb_to_sigmoid(rgb);
            let thesis = reflected_rgb(|l| poly.eval(l as f32) as f64, 2);
            for i in 0..3 {
                pred[0][i] += exact[i];
                pred[1][i] += thesis[i];
            }
        }
    }
    let pred = pred.map(|p| p.map(|v| v / count));
    let mut got = [[(0.0, 0.0); 3]; 2];
    for (k, mode) in ["spectral", "thesis"].into_iter().enumerate() {
        let img = render_rgb(&scene(&bubble_xml(mode)), 48, PathStrategy::Mis);
        for (i, g) in got[k].iter_mut().enumerate() {
            let vals: Vec<f64> = (0..N * N)
                .filter(|&p| pixel_cos(p % N, p / N).is_some())
                .map(|p| img[p][i] as f64)
                .collect();
            *g = mean_stderr(&vals);
        }
    }
    let mut strong = 0;
    for i in 0..3 {
        let want = pred[0][i] - pred[1][i];
        let diff = got[0][i].0 - got[1][i].0;
        let sigma = (got[0][i].1.powi(2) + got[1][i].1.powi(2)).sqrt();
        eprintln!(
            "channel {i}: predicted spectral {:.4} thesis {:.4} (Δ {want:+.4}); rendered {:.4} ± {:.4}, {:.4} ± {:.4} (Δ {diff:+.4})",
            pred[0][i], pred[1][i], got[0][i].0, got[0][i].1, got[1][i].0, got[1][i].1
        );
        if want.abs() > 0.01 {
            strong += 1;
            assert!(
                diff.signum() == want.signum() && diff.abs() > 4.0 * sigma,
                "channel {i}"
            );
            assert!(
                (diff - want).abs() < 4.0 * sigma + 0.25 * want.abs(),
                "channel {i}"
            );
        }
    }
    assert!(strong >= 2, "the two modes should differ clearly: {pred:?}");
}

#[test]
fn thinfilm_command_prints_the_table_and_rejects_bad_arguments() {
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_ophis"))
            .arg("thinfilm")
            .args(args)
            .output()
            .expect("runs")
    };
    let out = run(&["--angles", "0,45", "--wavelengths", "510:550:40"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "wavelength_nm,angle_deg,R_s,R_p,R,T");
    assert_eq!(lines.len(), 5);
    // Normal incidence, 510 nm: the fringe peak R = 0.174275 (research §8 T2), T = 1 − R.
    let v: Vec<f64> = lines[1].split(',').map(|x| x.parse().unwrap()).collect();
    assert!((v[4] - 0.174275).abs() < 1e-6 && (v[4] + v[5] - 1.0).abs() < 1e-7);
    // 45°, 550 nm: R_s = 0.341236, R_p = 0.043006 (T3).
    let v: Vec<f64> = lines[4].split(',').map(|x| x.parse().unwrap()).collect();
    assert!((v[2] - 0.341236).abs() < 1e-6 && (v[3] - 0.043006).abs() < 1e-6);
    for (args, what) in [
        (&["--wavelengths", "400:700:0"][..], "--wavelengths"),
        (&["--thickness", "-3"][..], "--thickness"),
        (&["--thickness", "nan"][..], "--thickness"),
        (&["--angles", "0,120"][..], "--angles"),
        (&["--film-ior", "-1.2"][..], "--film-ior"),
        (
            &["--chart", "x.png", "--thickness-range", "900:100"][..],
            "--thickness-range",
        ),
    ] {
        let out = run(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(what),
            "{args:?}: {err}"
        );
    }
}
