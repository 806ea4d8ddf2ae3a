//! Whole-render furnace tests: a diffuse sphere inside a uniform `constant` environment.
//!
//! A convex diffuse object of albedo ρ under uniform radiance L sees only the environment, so
//! its outgoing radiance is exactly ρ·L everywhere; with ρ = 1 it disappears into the background
//! (the white furnace). A white `rgb` emitter is D65 normalised to unit luminance, so L renders
//! as linear sRGB (1, 1, 1).
//!
//! Tolerances: each pixel is an independent estimate; the test compares the mean over the
//! sphere's pixels with the expected value within 4 standard errors estimated from the pixels'
//! spread, plus 1e-5 for float32 rounding in the film.

mod common;
use common::{mean_stderr, render_rgb, scene};
use ophis::integrator::PathStrategy;

fn furnace_xml(albedo: f32, max_depth: i32) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="{max_depth}"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/>
            <rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <shape type="sphere"><float name="radius" value="1"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="{albedo}"/></bsdf></shape>
</scene>"#
    )
}

/// Pixels whose whole footprint lies on the sphere (true) or clearly off it (false); others None.
fn classify(x: usize, y: usize, n: usize) -> Option<bool> {
    let t = (15f32.to_radians()).tan();
    let to_dir = |px: f32, py: f32| {
        let dx = (1.0 - 2.0 * px / n as f32) * t;
        let dy = (1.0 - 2.0 * py / n as f32) * t;
        (dx * dx + dy * dy).sqrt().atan()
    };
    let limit = (1.0f32 / 5.0).asin();
    let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
        .map(|(a, b)| to_dir(x as f32 + a, y as f32 + b));
    if corners.iter().all(|&a| a < limit * 0.97) {
        Some(true)
    } else if corners.iter().all(|&a| a > limit * 1.03) {
        Some(false)
    } else {
        None
    }
}

// Channels index both the pixel and the expected value; a range loop reads best here.
#[allow(clippy::needless_range_loop)]
fn check(albedo: f32, max_depth: i32, strategy: PathStrategy) {
    let sc = scene(&furnace_xml(albedo, max_depth));
    let img = render_rgb(&sc, 64, strategy);
    let n = 32;
    for (on_sphere, expected) in [(true, albedo as f64), (false, 1.0)] {
        for c in 0..3 {
            let vals: Vec<f64> = (0..n * n)
                .filter(|&i| classify(i % n, i / n, n) == Some(on_sphere))
                .map(|i| img[i][c] as f64)
                .collect();
            assert!(vals.len() > 50, "too few pixels classified");
            let (m, se) = mean_stderr(&vals);
            assert!(
                (m - expected).abs() <= 4.0 * se + 1e-5,
                "albedo {albedo}, {strategy:?}, sphere={on_sphere}, channel {c}: mean {m} ± {se}, expected {expected}"
            );
        }
    }
}

#[test]
fn white_furnace_sphere_vanishes() {
    check(1.0, -1, PathStrategy::Mis);
}

#[test]
fn half_albedo_sphere_is_half_as_bright() {
    check(0.5, -1, PathStrategy::Mis);
}

#[test]
fn furnace_holds_for_each_strategy() {
    check(0.5, -1, PathStrategy::LightOnly);
    check(0.5, -1, PathStrategy::BsdfOnly);
}

/// A diffuse plane under a uniform sky reflects ρ·L everywhere, however large it is. A
/// kilometre-wide ground rectangle (two triangles with coordinates ~1000) catches rays that leave
/// it at grazing angles and wrongly re-hit it at tiny distances if the triangle test ignores its
/// own rounding error: the ground then darkens, unevenly across the two triangles.
#[test]
fn kilometre_ground_plane_reflects_rho_times_sky() {
    let xml = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="2"/></integrator>
    <sensor type="perspective"><float name="fov" value="60"/>
        <transform name="to_world"><lookat origin="0,40,60" target="0,0,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="32"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/>
            <rfilter type="box"/></film></sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <shape type="rectangle"><transform name="to_world"><scale value="1000"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
</scene>"#;
    let sc = scene(xml);
    let img = render_rgb(&sc, 32, PathStrategy::Mis);
    // Every pixel sees the ground (the horizon is above the image's top edge).
    for half in [0..img.len() / 2, img.len() / 2..img.len()] {
        let vals: Vec<f64> = img[half].iter().map(|p| p[1] as f64).collect();
        let (m, se) = mean_stderr(&vals);
        assert!(
            (m - 0.5).abs() <= 4.0 * se + 1e-5,
            "mean {m} ± {se}, expected 0.5"
        );
    }
}
