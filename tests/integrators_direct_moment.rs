//! Mitsuba's `direct` and `moment` integrators.
//!
//! `direct` has an exact answer in the furnace (a convex diffuse sphere of albedo ρ under a
//! uniform sky L reflects ρ·L: all of it is direct light), whatever its sample counts; and with
//! one light and one BSDF sample it is the same estimator as `path` with `max_depth` 2, so the
//! two must agree within noise on a scene with glossy surfaces and an area light. Tolerances as
//! in `render_furnace.rs` (4 standard errors of the pixel mean) and `render_strategies.rs`
//! (per-block t-tests of pixel differences, |t| ≤ 4.5).

mod common;
use common::{mean_stderr, render_rgb, scene};
use ophis::integrator::PathStrategy;
use ophis::scene::build::{load_scene_str, LoadOptions};
use ophis::scene::IntegratorKind;
use std::path::Path;

fn furnace(integrator: &str, albedo: f32) -> String {
    format!(
        r#"<scene version="3.0.0">
    {integrator}
    <sensor type="perspective"><float name="fov" value="30"/>
        <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="32"/></sampler>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/></film></sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <shape type="sphere"><bsdf type="diffuse"><rgb name="reflectance" value="{albedo}"/></bsdf></shape>
</scene>"#
    )
}

/// Pixels well inside (true) or well outside (false) the sphere's outline (fov 30°, distance 5).
fn on_sphere(x: usize, y: usize, n: usize) -> Option<bool> {
    let t = 15f32.to_radians().tan();
    let angle = |px: f32, py: f32| {
        let dx = (1.0 - 2.0 * px / n as f32) * t;
        let dy = (1.0 - 2.0 * py / n as f32) * t;
        (dx * dx + dy * dy).sqrt().atan()
    };
    let limit = 0.2f32.asin();
    let a = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
        .map(|(u, v)| angle(x as f32 + u, y as f32 + v));
    if a.iter().all(|&v| v < 0.97 * limit) {
        Some(true)
    } else if a.iter().all(|&v| v > 1.03 * limit) {
        Some(false)
    } else {
        None
    }
}

// Channels index both the pixel and nothing else; a range loop reads best here.
#[allow(clippy::needless_range_loop)]
fn check_furnace(integrator: &str, albedo: f32, strategy: PathStrategy, background: f64) {
    let sc = scene(&furnace(integrator, albedo));
    let img = render_rgb(&sc, 32, strategy);
    let n = 24;
    for (inside, want) in [(true, albedo as f64), (false, background)] {
        for c in 0..3 {
            let v: Vec<f64> = (0..n * n)
                .filter(|&i| on_sphere(i % n, i / n, n) == Some(inside))
                .map(|i| img[i][c] as f64)
                .collect();
            assert!(v.len() > 40);
            let (m, se) = mean_stderr(&v);
            assert!(
                (m - want).abs() <= 4.0 * se + 1e-5,
                "{integrator} {strategy:?}, inside={inside}, channel {c}: {m} ± {se}, expected {want}"
            );
        }
    }
}

#[test]
fn direct_is_exact_in_the_furnace_for_any_sample_counts() {
    for counts in [
        "",
        r#"<integer name="emitter_samples" value="3"/><integer name="bsdf_samples" value="0"/>"#,
        r#"<integer name="emitter_samples" value="0"/><integer name="bsdf_samples" value="2"/>"#,
        r#"<integer name="emitter_samples" value="2"/><integer name="bsdf_samples" value="5"/>"#,
        r#"<integer name="shading_samples" value="4"/>"#,
    ] {
        let integ = format!(r#"<integrator type="direct">{counts}</integrator>"#);
        check_furnace(&integ, 0.5, PathStrategy::Mis, 1.0);
    }
    let one = r#"<integrator type="direct"/>"#;
    check_furnace(one, 0.5, PathStrategy::LightOnly, 1.0);
    check_furnace(one, 0.5, PathStrategy::BsdfOnly, 1.0);
    let hidden =
        r#"<integrator type="direct"><boolean name="hide_emitters" value="true"/></integrator>"#;
    check_furnace(hidden, 0.5, PathStrategy::Mis, 0.0);
}

#[test]
fn moment_renders_its_nested_integrator_with_the_nested_parameters() {
    // The issue: the nested max_depth was lost and the image came out twice too bright.
    let integ = r#"<integrator type="moment"><integrator type="path"><integer name="max_depth" value="2"/></integrator></integrator>"#;
    let (sc, w) = load_scene_str(
        &furnace(integ, 0.5),
        Path::new("m.xml"),
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(sc.integrator.max_depth, Some(2));
    assert!(w.iter().any(|w| w.message.contains("moment")), "{w:?}");
    let direct = r#"<integrator type="moment"><integrator type="direct"><integer name="bsdf_samples" value="3"/></integrator></integrator>"#;
    let (sc, _) = load_scene_str(
        &furnace(direct, 0.5),
        Path::new("m.xml"),
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(
        sc.integrator.kind,
        IntegratorKind::Direct {
            emitter_samples: 1,
            bsdf_samples: 3
        }
    );
    check_furnace(direct, 0.5, PathStrategy::Mis, 1.0);
}

#[test]
fn bad_direct_and_moment_parameters_are_located_errors() {
    for (integ, what) in [
        (
            r#"<integrator type="direct"><integer name="shading_samples" value="2"/><integer name="bsdf_samples" value="1"/></integrator>"#,
            "shading_samples",
        ),
        (
            r#"<integrator type="direct"><integer name="shading_samples" value="0"/></integrator>"#,
            "no emitter or BSDF samples",
        ),
        (
            r#"<integrator type="direct"><integer name="emitter_samples" value="-1"/></integrator>"#,
            "emitter_samples",
        ),
        (r#"<integrator type="moment"/>"#, "nested integrator"),
    ] {
        let e = load_scene_str(
            &furnace(integ, 0.5),
            Path::new("d.xml"),
            &LoadOptions::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("d.xml:2:") && e.contains(what), "{e}");
    }
}

const GLOSSY: &str = r#"<scene version="3.0.0">
    INTEGRATOR
    <sensor type="perspective"><float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0,1.2,4" target="0,0.3,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/>
            <rfilter type="box"/></film></sensor>
    <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
    <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.45, 0.4"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="-0.6" y="0.5" z="0"/><float name="radius" value="0.5"/>
        <bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.2"/>
            <string name="distribution" value="ggx"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0.6" y="0.5" z="0"/><float name="radius" value="0.5"/>
        <bsdf type="conductor"/></shape>
    <shape type="sphere"><point name="center" x="0" y="2.2" z="-0.5"/><float name="radius" value="0.6"/>
        <emitter type="area"><rgb name="radiance" value="3"/></emitter></shape>
</scene>"#;

/// Per 8×8 block and channel, the mean pixel difference against its standard error.
fn agree(a: &[[f32; 3]], b: &[[f32; 3]], what: &str) {
    let n = 32;
    for block in 0..16 {
        let (bx, by) = (block % 4, block / 4);
        for c in 0..3 {
            let d: Vec<f64> = (0..64)
                .map(|k| {
                    let i = (by * 8 + k / 8) * n + bx * 8 + k % 8;
                    (a[i][c] - b[i][c]) as f64
                })
                .collect();
            let (m, se) = mean_stderr(&d);
            if se == 0.0 {
                assert!(m.abs() < 1e-6, "{what}: block {block} ch {c}: {m}");
                continue;
            }
            assert!(
                (m / se).abs() <= 4.5,
                "{what}: block {block} channel {c}: {m:.5} ± {se:.5}"
            );
        }
    }
}

#[test]
fn direct_matches_path_with_max_depth_two() {
    let path = scene(&GLOSSY.replace(
        "INTEGRATOR",
        r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>"#,
    ));
    let reference = render_rgb(&path, 64, PathStrategy::Mis);
    for counts in [
        "",
        r#"<integer name="emitter_samples" value="3"/><integer name="bsdf_samples" value="2"/>"#,
    ] {
        let direct = scene(&GLOSSY.replace(
            "INTEGRATOR",
            &format!(r#"<integrator type="direct">{counts}</integrator>"#),
        ));
        let img = render_rgb(&direct, 64, PathStrategy::Mis);
        agree(&img, &reference, &format!("direct {counts}"));
    }
}
