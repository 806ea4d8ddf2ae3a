//! Light sampling, BSDF sampling and their MIS combination are three unbiased estimators of the
//! same image: renders with each must agree within noise. (MIS also leaves the smooth skies —
//! `constant` and Preetham's — to the BSDF samples of the rough conductors, the coated sphere — a thin film over a dark base in
//! closed form —, a random walk sampled from its mixture density and, beside the area light,
//! the Lambertian surfaces, which the other two do not.)
//!
//! Test: for every 8×8 block of pixels and every channel, the per-pixel differences between two
//! strategies have expectation 0; their mean is compared with its standard error (from the 64
//! differences' spread, so image structure does not inflate it). With 16 blocks × 3 channels and
//! a family-wise significance of 0.01 (Šidák), each t-test (63 degrees of freedom) uses
//! |t| ≤ 4.5, slightly above the two-sided 1e-4 quantile (≈ 4.0) to allow for the mildly heavy
//! tails of path-tracing noise.

mod common;
use common::{render_rgb, scene};
use ophis::integrator::PathStrategy;

const XML: &str = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="4"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0,1.2,4" target="0,0.3,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/>
            <rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.45, 0.4"/></bsdf>
    </shape>
    <shape type="sphere"><point name="center" x="-0.6" y="0.5" z="0"/><float name="radius" value="0.5"/>
        <bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.35"/>
            <string name="distribution" value="ggx"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0.6" y="0.5" z="0"/><float name="radius" value="0.5"/>
        <bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.2, 0.3, 0.7"/><float name="alpha" value="0.3"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0" y="0.35" z="0.9"/><float name="radius" value="0.35"/>
        <bsdf type="multilayered">
            <bsdf type="thinfilm" name="surface_0"><float name="film_thickness" value="400"/></bsdf>
            <bsdf type="diffuse" name="surface_1"><rgb name="reflectance" value="0.05"/></bsdf>
        </bsdf></shape>
    <shape type="sphere"><point name="center" x="0" y="2.2" z="-0.5"/><float name="radius" value="0.6"/>
        <emitter type="area"><rgb name="radiance" value="3"/></emitter></shape>
</scene>"#;

fn compare(a: &[[f32; 3]], b: &[[f32; 3]], what: &str) {
    let n = 32;
    for by in 0..4 {
        for bx in 0..4 {
            for c in 0..3 {
                let d: Vec<f64> = (0..64)
                    .map(|k| {
                        let (x, y) = (bx * 8 + k % 8, by * 8 + k / 8);
                        (a[y * n + x][c] - b[y * n + x][c]) as f64
                    })
                    .collect();
                let m = d.iter().sum::<f64>() / 64.0;
                let var = d.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / 63.0;
                let se = (var / 64.0).sqrt();
                if se == 0.0 {
                    assert!(
                        m.abs() < 1e-6,
                        "{what}: block ({bx},{by}) ch {c}: identical noise but mean diff {m}"
                    );
                    continue;
                }
                let t = m / se;
                assert!(t.abs() <= 4.5, "{what}: block ({bx},{by}) channel {c}: mean difference {m:.5} ± {se:.5} (t = {t:.2})");
            }
        }
    }
}

#[test]
fn mis_light_and_bsdf_sampling_agree() {
    let sc = scene(XML);
    let mis = render_rgb(&sc, 64, PathStrategy::Mis);
    let light = render_rgb(&sc, 64, PathStrategy::LightOnly);
    let bsdf = render_rgb(&sc, 256, PathStrategy::BsdfOnly);
    compare(&mis, &light, "MIS vs light sampling");
    compare(&mis, &bsdf, "MIS vs BSDF sampling");
}

/// Two glossy spheres before a Lambertian wall under a uniform sky and an area light: MIS
/// leaves the sky to the BSDF samples of all three (and chooses only the area light for
/// next-event estimation there), which must still agree with BSDF sampling alone.
const GLOSSY_UNDER_SKY: &str = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0,0,3.2" target="0,0,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/>
            <rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <shape type="sphere"><point name="center" x="-0.55" y="0" z="0"/><float name="radius" value="0.55"/>
        <bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.5"/>
            <string name="distribution" value="ggx"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0.55" y="0" z="0"/><float name="radius" value="0.55"/>
        <bsdf type="multilayered">
            <bsdf type="thinfilm" name="surface_0"><float name="film_thickness" value="400"/></bsdf>
            <bsdf type="diffuse" name="surface_1"><rgb name="reflectance" value="0.05"/></bsdf>
        </bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="3"/><translate z="-1"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0" y="1.2" z="1.5"/><float name="radius" value="0.7"/>
        <emitter type="area"><rgb name="radiance" value="3"/></emitter></shape>
</scene>"#;

#[test]
fn mis_leaving_the_sky_to_glossy_bsdfs_agrees_with_bsdf_sampling() {
    let sc = scene(GLOSSY_UNDER_SKY);
    // 2048 samples: the weight of an area light found by a BSDF sample must use the light
    // choice without the sky; with the full choice's probability instead, the bias is 5.4σ (and
    // 47σ when the sky escaping from a vertex that left it out is weighted as if it had not).
    let mis = render_rgb(&sc, 2048, PathStrategy::Mis);
    let bsdf = render_rgb(&sc, 2048, PathStrategy::BsdfOnly);
    compare(&mis, &bsdf, "MIS vs BSDF sampling under a uniform sky");
}

/// Preetham's sky is a smooth environment too: under `sunsky`, MIS leaves the sky to the BSDF
/// samples of the glossy spheres and of the Lambertian ground (which choose only the sun for
/// next-event estimation), and the random walk of the small front sphere keeps the full choice,
/// where the sky takes only its power's share; light sampling alone reaches the sky by its own
/// samples everywhere. The two must agree.
const GLOSSY_UNDER_SUNSKY: &str = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0,1.0,3.2" target="0,0.2,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/>
            <rfilter type="box"/></film>
    </sensor>
    <emitter type="sunsky">
        <vector name="sun_direction" x="0.5" y="0.7" z="0.5"/>
        <float name="sun_radius_scale" value="4"/>
        <float name="sun_scale" value="0.1"/>
    </emitter>
    <shape type="sphere"><point name="center" x="-0.55" y="0.55" z="0"/><float name="radius" value="0.55"/>
        <bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.4"/>
            <string name="distribution" value="ggx"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0.55" y="0.55" z="0"/><float name="radius" value="0.55"/>
        <bsdf type="multilayered">
            <bsdf type="thinfilm" name="surface_0"><float name="film_thickness" value="400"/></bsdf>
            <bsdf type="diffuse" name="surface_1"><rgb name="reflectance" value="0.05"/></bsdf>
        </bsdf></shape>
    <shape type="sphere"><point name="center" x="0" y="0.3" z="0.9"/><float name="radius" value="0.3"/>
        <bsdf type="multilayered">
            <bsdf type="roughthinfilm" name="surface_0"><float name="alpha" value="0.1"/>
                <float name="film_thickness" value="400"/></bsdf>
            <bsdf type="diffuse" name="surface_1"><rgb name="reflectance" value="0.4"/></bsdf>
        </bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.45, 0.4"/></bsdf></shape>
</scene>"#;

#[test]
fn mis_leaving_the_sunsky_sky_to_bsdfs_agrees_with_light_sampling() {
    let sc = scene(GLOSSY_UNDER_SUNSKY);
    // With the full choice's probability in the weight of the sky that a BSDF sample finds
    // from a vertex that left it out (instead of weight 1), block (0, 0) is 5.6σ off.
    let mis = render_rgb(&sc, 512, PathStrategy::Mis);
    let light = render_rgb(&sc, 512, PathStrategy::LightOnly);
    compare(&mis, &light, "MIS vs light sampling under a sun and sky");
}

/// The random walk sampled from its mixture density (`rough_coat` = `mixture`), under a
/// uniform sky and an area light: MIS leaves the sky to its samples (as to the closed forms')
/// and weighs the area light by the choice without the sky; light sampling alone and BSDF
/// sampling alone must agree with it. A walk with its own sampling stands beside it.
const WALK_MIXTURE_UNDER_SKY: &str = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0,0.6,3.2" target="0,0.3,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/>
            <rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="0.8"/></emitter>
    <shape type="sphere"><point name="center" x="-0.5" y="0.5" z="0"/><float name="radius" value="0.5"/>
        <bsdf type="multilayered">
            <string name="rough_coat" value="mixture"/>
            <bsdf type="roughthinfilm" name="surface_0"><float name="alpha" value="0.15"/>
                <float name="film_thickness" value="450"/></bsdf>
            <bsdf type="diffuse" name="surface_1"><rgb name="reflectance" value="0.15"/></bsdf>
        </bsdf></shape>
    <shape type="sphere"><point name="center" x="0.5" y="0.5" z="0"/><float name="radius" value="0.5"/>
        <bsdf type="multilayered">
            <bsdf type="roughthinfilm" name="surface_0"><float name="alpha" value="0.15"/>
                <float name="film_thickness" value="450"/></bsdf>
            <bsdf type="diffuse" name="surface_1"><rgb name="reflectance" value="0.15"/></bsdf>
        </bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.45, 0.4"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0" y="2.0" z="0.8"/><float name="radius" value="0.4"/>
        <emitter type="area"><rgb name="radiance" value="4"/></emitter></shape>
</scene>"#;

#[test]
fn mis_with_the_walk_sampled_from_its_mixture_agrees_with_light_and_bsdf_sampling() {
    let sc = scene(WALK_MIXTURE_UNDER_SKY);
    // Checks the integrator's side (the sky left to these samples, the light choice without
    // it); a 25 % error in the mixture samples' weights is 6σ off here, while the BSDF's own
    // tests (`src/bsdf/layered/tests_mixture.rs`) hold its density and weights much closer.
    let mis = render_rgb(&sc, 256, PathStrategy::Mis);
    let light = render_rgb(&sc, 256, PathStrategy::LightOnly);
    let bsdf = render_rgb(&sc, 512, PathStrategy::BsdfOnly);
    compare(&mis, &light, "MIS vs light sampling, walk from its mixture");
    compare(&mis, &bsdf, "MIS vs BSDF sampling, walk from its mixture");
}
