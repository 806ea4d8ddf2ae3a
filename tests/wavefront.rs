//! The wavefront integrator against the scalar one: every scene of `scenes/` (each `-D` variant)
//! renders to the same pixels, bit for bit, with either engine. The wavefront integrator is
//! meant to compute exactly what the scalar loop computes, path by path, only in another order
//! (batched rays, lanes), so any difference at all is a defect.

use ophis::accel::Isa;
use ophis::film::Film;
use ophis::integrator::PathStrategy;
use ophis::render::{render, Engine, NoProgress, RenderOptions};
use ophis::scene::build::{load_scene, LoadOptions};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

mod common;
use common::scenes::{scene_files, tiny_mesh, variants};

fn render_with(scene: &ophis::scene::Scene, engine: Engine, spp: u32) -> Film {
    let mut film = Film::new(scene.width, scene.height);
    let opts = RenderOptions {
        spp,
        time_limit: None,
        strategy: PathStrategy::Mis,
        engine,
    };
    render(
        scene,
        &mut film,
        0,
        &opts,
        &AtomicBool::new(false),
        &NoProgress,
    );
    film
}

#[test]
fn every_scene_renders_identically_with_both_engines() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut checked = 0;
    let mut differ = Vec::new();
    for rel in scene_files() {
        let text = std::fs::read_to_string(root.join(&rel)).unwrap();
        if !text.contains("<sensor") && !text.contains("<include") {
            continue;
        }
        for mut defines in variants(&text) {
            if text.contains("<default name=\"mesh\"") {
                defines.push(("mesh".into(), tiny_mesh().display().to_string()));
            }
            let opts = LoadOptions {
                defines: defines.clone(),
                spp: Some(2),
                seed: Some(7),
                // Wider than a tile and taller than a pool: tiles at the edge are partial and
                // the pool refills.
                resolution: Some((40, 36)),
            };
            let (mut scene, _) =
                load_scene(&root.join(&rel), &opts).unwrap_or_else(|e| panic!("{rel}: {e}"));
            let a = render_with(&scene, Engine::Scalar, 2);
            // Every instruction-set variant of the lanes this CPU runs (eight lanes with AVX2
            // or AVX-512, one lane on the baseline).
            for isa in Isa::ALL {
                if !scene.bvh.set_isa(isa) {
                    continue;
                }
                let b = render_with(&scene, Engine::Auto, 2);
                checked += 1;
                if a.pixels != b.pixels {
                    let n = a
                        .pixels
                        .iter()
                        .zip(&b.pixels)
                        .filter(|(x, y)| x != y)
                        .count();
                    differ.push(format!("{rel} {defines:?} {isa:?}: {n} pixels differ"));
                }
            }
        }
    }
    assert!(checked > 20, "only {checked} scene variants");
    assert!(differ.is_empty(), "{differ:#?}");
}

/// A scene with every material and light kind the lanes implement, beside ones they hand to
/// the scalar code (a textured diffuse, a sphere light, a point light, an environment), so
/// that chunks mix lane and scalar paths.
const MIXED: &str = r#"<scene version="3.0.0">
    <default name="depth" value="7"/><default name="rr" value="2"/><default name="hide" value="false"/>
    <integrator type="path"><integer name="max_depth" value="$depth"/>
        <integer name="rr_depth" value="$rr"/><boolean name="hide_emitters" value="$hide"/></integrator>
    <sensor type="perspective"><float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="0, 0.3, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"/>
        <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="36"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="0.2, 0.25, 0.3"/></emitter>
    <emitter type="point"><point name="position" x="1" y="2" z="1"/><rgb name="intensity" value="3, 3, 2"/></emitter>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="1.5"/></transform>
        <emitter type="area"><rgb name="radiance" value="8, 6, 4"/></emitter>
    </shape>
    <shape type="sphere"><point name="center" x="-1.5" y="1" z="-1"/><float name="radius" value="0.2"/>
        <emitter type="area"><rgb name="radiance" value="2, 4, 8"/></emitter></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/><translate y="-1"/></transform>
        <bsdf type="diffuse"><texture name="reflectance" type="checkerboard">
            <rgb name="color0" value="0.8, 0.7, 0.6"/><rgb name="color1" value="0.2, 0.3, 0.4"/></texture></bsdf>
    </shape>
    <shape type="rectangle"><transform name="to_world"><scale value="3"/><translate z="-2"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.3, 0.6, 0.2"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="-0.9" y="-0.5" z="0"/><float name="radius" value="0.45"/>
        <bsdf type="dielectric"><float name="int_ior" value="1.5"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0" y="-0.5" z="-0.5"/><float name="radius" value="0.45"/>
        <bsdf type="conductor"><string name="material" value="Cu"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0.9" y="-0.5" z="0"/><float name="radius" value="0.45"/>
        <bsdf type="roughconductor"><string name="material" value="Au"/><string name="distribution" value="ggx"/>
            <float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.3"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="1.6" y="-0.6" z="0.3"/><float name="radius" value="0.3"/>
        <bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0.2" y="0.5" z="-1"/><float name="radius" value="0.3"/>
        <bsdf type="conductor"/></shape>
    <shape type="cube"><transform name="to_world"><scale value="0.25"/><translate x="1.3" y="0.6" z="-0.8"/></transform>
        <bsdf type="diffuse"><spectrum name="reflectance" value="400:0.2, 500:0.8, 600:0.4, 700:0.9"/></bsdf></shape>
</scene>"#;

#[test]
fn mixed_lane_and_scalar_paths_are_identical_for_every_strategy_and_setting() {
    let mut differ = Vec::new();
    for (depth, rr, hide) in [(7, 2, false), (2, 5, false), (1, 0, true), (-1, 0, false)] {
        let xml = MIXED
            .replace(
                "<default name=\"depth\" value=\"7\"/>",
                &format!("<default name=\"depth\" value=\"{depth}\"/>"),
            )
            .replace(
                "<default name=\"rr\" value=\"2\"/>",
                &format!("<default name=\"rr\" value=\"{rr}\"/>"),
            )
            .replace(
                "<default name=\"hide\" value=\"false\"/>",
                &format!("<default name=\"hide\" value=\"{hide}\"/>"),
            );
        let mut scene = common::scene(&xml);
        for strategy in [
            PathStrategy::Mis,
            PathStrategy::LightOnly,
            PathStrategy::BsdfOnly,
        ] {
            let run = |scene: &ophis::scene::Scene, engine| {
                let mut film = Film::new(scene.width, scene.height);
                let opts = RenderOptions {
                    spp: 3,
                    time_limit: None,
                    strategy,
                    engine,
                };
                render(
                    scene,
                    &mut film,
                    0,
                    &opts,
                    &AtomicBool::new(false),
                    &NoProgress,
                );
                film
            };
            let a = run(&scene, Engine::Scalar);
            for isa in Isa::ALL {
                if !scene.bvh.set_isa(isa) {
                    continue;
                }
                let b = run(&scene, Engine::Auto);
                if a.pixels != b.pixels {
                    differ.push(format!(
                        "depth {depth} rr {rr} hide {hide} {strategy:?} {isa:?}"
                    ));
                }
            }
        }
    }
    assert!(differ.is_empty(), "{differ:#?}");
}

/// An adaptive render, whose pixels take different numbers of samples (some a few, some many
/// times the mean), gives the same sums with both engines.
#[test]
fn adaptive_renders_are_identical_with_both_engines() {
    let xml = MIXED.replace(
        "<sampler type=\"independent\"/>",
        "<sampler type=\"independent\"><boolean name=\"adaptive\" value=\"true\"/></sampler>",
    );
    let mut scene = common::scene(&xml);
    let a = render_with(&scene, Engine::Scalar, 12);
    let counts: std::collections::BTreeSet<u64> = a.pixels.iter().map(|p| p[3] as u64).collect();
    assert!(counts.len() > 5, "the counts should vary: {counts:?}");
    let mut checked = 0;
    for isa in Isa::ALL {
        if !scene.bvh.set_isa(isa) {
            continue;
        }
        let b = render_with(&scene, Engine::Auto, 12);
        assert!(a.pixels == b.pixels, "{isa:?}");
        checked += 1;
    }
    assert!(checked >= 1);
}
