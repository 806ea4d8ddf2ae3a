//! Scene loading: every supported plugin, the 0.6 dialect, `-D` overrides, and errors that name
//! file:line:column instead of panicking.

use ophis::scene::build::{load_scene, load_scene_str, LoadOptions};
use ophis::scene::Scene;
use std::path::Path;

fn load(xml: &str) -> Result<Scene, String> {
    load_scene_str(xml, Path::new("test.xml"), &LoadOptions::default())
        .map(|(s, _)| s)
        .map_err(|e| e.to_string())
}

fn load_with(xml: &str, defines: &[(&str, &str)]) -> Result<Scene, String> {
    let opts = LoadOptions {
        defines: defines
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect(),
        ..Default::default()
    };
    load_scene_str(xml, Path::new("test.xml"), &opts)
        .map(|(s, _)| s)
        .map_err(|e| e.to_string())
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("ophis-scene-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

const EVERYTHING: &str = r##"<scene version="3.0.0">
    <default name="res" value="16"/>
    <integrator type="path">
        <integer name="max_depth" value="6"/><integer name="rr_depth" value="3"/>
        <boolean name="hide_emitters" value="true"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/><string name="fov_axis" value="y"/>
        <float name="near_clip" value="0.1"/><float name="far_clip" value="100"/>
        <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
        <sampler type="stratified"><integer name="sample_count" value="4"/><integer name="seed" value="3"/></sampler>
        <film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="$res"/>
            <rfilter type="tent"/></film>
    </sensor>
    <texture type="checkerboard" id="checks">
        <rgb name="color0" value="0.1, 0.2, 0.3"/><rgb name="color1" value="#ff8000"/>
    </texture>
    <bsdf type="diffuse" id="d"><ref name="reflectance" id="checks"/></bsdf>
    <bsdf type="twosided" id="ts"><bsdf type="diffuse"><srgb name="reflectance" value="0.5, 0.5, 0.2"/></bsdf></bsdf>
    <alias id="d" as="d2"/>
    <shape type="sphere"><point name="center" value="1, 0, 0"/><float name="radius" value="0.5"/>
        <bsdf type="dielectric"><float name="int_ior" value="1.33"/></bsdf></shape>
    <shape type="rectangle"><ref id="d2"/></shape>
    <shape type="cube"><transform name="to_world"><scale value="0.2"/><translate x="-1"/></transform>
        <bsdf type="thindielectric"/></shape>
    <shape type="disk"><transform name="to_world"><rotate x="1" angle="90"/><translate y="-1"/></transform>
        <bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.3"/></bsdf></shape>
    <shape type="sphere"><float name="radius" value="0.1"/><bsdf type="conductor"><string name="material" value="Ag"/></bsdf></shape>
    <shape type="sphere"><float name="radius" value="0.1"/><bsdf type="roughconductor">
        <spectrum name="eta" value="400:0.2, 700:0.3"/><spectrum name="k" value="3"/></bsdf></shape>
    <shape type="sphere"><float name="radius" value="0.1"/><bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.3,0.1,0.1"/></bsdf></shape>
    <shape type="sphere"><float name="radius" value="0.1"/><bsdf type="roughplastic"><boolean name="nonlinear" value="true"/></bsdf></shape>
    <shape type="sphere"><float name="radius" value="0.1"/><ref id="ts"/>
        <emitter type="area"><blackbody name="radiance" temperature="3000K"/></emitter></shape>
    <emitter type="point"><point name="position" value="0, 3, 0"/><rgb name="intensity" value="5"/></emitter>
    <emitter type="directional"><vector name="direction" value="0, -1, 0"/><spectrum name="irradiance" value="2"/></emitter>
    <emitter type="constant"><rgb name="radiance" value="0.1"/></emitter>
</scene>"##;

#[test]
fn every_supported_plugin_loads() {
    let s = load(EVERYTHING).expect("loads");
    assert_eq!(s.shapes.len(), 9);
    assert_eq!(s.lights.len(), 4);
    // The constant environment and the directional light are both at infinity.
    assert_eq!(s.infinite_lights.len(), 2);
    assert_eq!((s.width, s.height), (16, 16));
    assert_eq!(s.integrator.max_depth, Some(6));
    assert_eq!(s.integrator.rr_depth, 3);
    assert!(s.integrator.hide_emitters);
    assert_eq!(s.sampler.spp, 4);
    assert_eq!(s.sampler.seed, 3);
    // The rectangle's BSDF is referenced through an alias: shared with the declared one.
    assert_eq!(s.shape_light.iter().filter(|l| l.is_some()).count(), 1);
}

#[test]
fn defines_override_defaults() {
    let s = load_with(EVERYTHING, &[("res", "8")]).expect("loads");
    assert_eq!((s.width, s.height), (8, 8));
}

const V3: &str = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="5"/><integer name="rr_depth" value="2"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="35"/><string name="fov_axis" value="y"/>
        <transform name="to_world"><lookat origin="1,2,5" target="0,0,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="9"/></sampler>
        <film type="hdrfilm"><integer name="width" value="20"/><integer name="height" value="10"/></film>
    </sensor>
    <shape type="sphere"><float name="radius" value="0.5"/>
        <bsdf type="roughdielectric"><float name="int_ior" value="1.7"/><float name="ext_ior" value="1.1"/>
            <float name="alpha" value="0.2"/></bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="2"/></transform>
        <bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.2, 0.4, 0.6"/>
            <rgb name="specular_reflectance" value="0.9"/></bsdf>
        <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
</scene>"#;

const V06: &str = r#"<scene version="0.6.0">
    <integrator type="path"><integer name="maxDepth" value="5"/><integer name="rrDepth" value="2"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="35"/><string name="fovAxis" value="y"/>
        <transform name="toWorld"><lookAt origin="1,2,5" target="0,0,0" up="0,1,0"/></transform>
        <sampler type="independent"><integer name="sampleCount" value="9"/></sampler>
        <film type="hdrfilm"><integer name="width" value="20"/><integer name="height" value="10"/></film>
    </sensor>
    <shape type="sphere"><float name="radius" value="0.5"/>
        <bsdf type="roughdielectric"><float name="intIOR" value="1.7"/><float name="extIOR" value="1.1"/>
            <float name="alpha" value="0.2"/></bsdf></shape>
    <shape type="rectangle"><transform name="toWorld"><scale value="2"/></transform>
        <bsdf type="plastic"><rgb name="diffuseReflectance" value="0.2, 0.4, 0.6"/>
            <rgb name="specularReflectance" value="0.9"/></bsdf>
        <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
</scene>"#;

#[test]
fn mitsuba_06_and_3_spellings_build_the_same_scene() {
    let a = load(V3).expect("3.x loads");
    let b = load(V06).expect("0.6 loads");
    assert_eq!(format!("{:?}", a.camera), format!("{:?}", b.camera));
    assert_eq!(format!("{:?}", a.materials), format!("{:?}", b.materials));
    assert_eq!(format!("{:?}", a.lights), format!("{:?}", b.lights));
    assert_eq!(format!("{:?}", a.shapes), format!("{:?}", b.shapes));
    assert_eq!(a.integrator, b.integrator);
    assert_eq!(a.sampler, b.sampler);
    assert_eq!((a.width, a.height), (b.width, b.height));
}

/// Asserts that loading fails with a message naming `test.xml:line:` and containing `what`.
fn assert_error_at(xml: &str, line: u32, what: &str) {
    let e = load(xml)
        .err()
        .unwrap_or_else(|| panic!("expected an error for:\n{xml}"));
    assert!(
        e.contains(&format!("test.xml:{line}:")),
        "error does not name line {line}: {e}"
    );
    assert!(
        e.to_lowercase().contains(&what.to_lowercase()),
        "error does not mention '{what}': {e}"
    );
}

#[test]
fn errors_name_file_line_and_column() {
    // Malformed XML (unclosed element).
    assert_error_at(
        "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n</scene>",
        3,
        "",
    );
    // Unknown reference.
    assert_error_at("<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n  <ref id=\"nope\"/>\n</shape>\n</scene>", 3, "nope");
    // Non-numeric value.
    assert_error_at("<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n  <float name=\"radius\" value=\"big\"/>\n</shape>\n</scene>", 3, "big");
    // Negative radius.
    assert_error_at("<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n  <float name=\"radius\" value=\"-1\"/>\n</shape>\n</scene>", 3, "radius");
    // A parameter of the wrong type.
    assert_error_at(
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n  <string name=\"radius\" value=\"one\"/>\n</shape>\n</scene>",
        3,
        "radius",
    );
    // Absurd resolution.
    assert_error_at(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><film type=\"hdrfilm\">\n<integer name=\"width\" value=\"1000000\"/>\n</film></sensor>\n</scene>",
        3,
        "width",
    );
    // Unknown IOR name.
    assert_error_at(
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n<bsdf type=\"dielectric\">\n<string name=\"int_ior\" value=\"unobtainium\"/>\n</bsdf></shape>\n</scene>",
        4,
        "unobtainium",
    );
    // A 3.x scene with too few layers, counted in 0.6's camelCase (read only in 0.x scenes).
    assert_error_at(
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n<bsdf type=\"multilayered\">\n\
         <integer name=\"nbLayers\" value=\"2\"/>\n<bsdf type=\"diffuse\" name=\"surface_0\"/>\n\
         </bsdf></shape>\n</scene>",
        3,
        "'nbLayers' is Mitsuba 0.6's spelling",
    );
}

#[test]
fn missing_mesh_file_is_an_error_naming_the_file() {
    let dir = temp_dir("missing");
    let scene = dir.join("scene.xml");
    std::fs::write(&scene, "<scene version=\"3.0.0\">\n<shape type=\"obj\">\n  <string name=\"filename\" value=\"nothere.obj\"/>\n</shape>\n</scene>").unwrap();
    let e = load_scene(&scene, &LoadOptions::default())
        .expect_err("error")
        .to_string();
    assert!(
        e.contains("nothere.obj") && e.contains("scene.xml:3:"),
        "{e}"
    );
    // A directory where a file is expected.
    std::fs::create_dir_all(dir.join("adir.ply")).unwrap();
    std::fs::write(&scene, "<scene version=\"3.0.0\">\n<shape type=\"ply\">\n  <string name=\"filename\" value=\"adir.ply\"/>\n</shape>\n</scene>").unwrap();
    let e = load_scene(&scene, &LoadOptions::default())
        .expect_err("error")
        .to_string();
    assert!(e.contains("adir.ply") && e.contains("directory"), "{e}");
}

#[test]
fn meshes_load_relative_to_the_scene_file() {
    let dir = temp_dir("mesh");
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let scene = dir.join("scene.xml");
    std::fs::write(&scene, "<scene version=\"3.0.0\"><shape type=\"obj\"><string name=\"filename\" value=\"tri.obj\"/><boolean name=\"face_normals\" value=\"true\"/></shape></scene>").unwrap();
    let (s, _) = load_scene(&scene, &LoadOptions::default()).expect("loads");
    assert_eq!(s.primitive_count(), 1);
}

#[test]
fn unused_parameters_are_warnings_and_unknown_plugins_errors() {
    // A parameter nothing reads is a warning naming the nearest declared one.
    let xml = "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n  <float name=\"radiuss\" value=\"2\"/>\n</shape>\n</scene>";
    let (_, warnings) =
        load_scene_str(xml, Path::new("test.xml"), &LoadOptions::default()).expect("loads");
    let all: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        all.iter().any(|w| w.contains("radiuss")
            && w.contains("test.xml:3:")
            && w.contains("did you mean 'radius'")),
        "{all:?}"
    );
    // An unknown shape is an error at its element, as in Mitsuba.
    let xml =
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\"/>\n<shape type=\"teapot\"/>\n</scene>";
    let e = load(xml).expect_err("an unknown plugin is an error");
    assert!(e.contains("test.xml:3:") && e.contains("teapot"), "{e}");
}

#[test]
fn envmap_from_exr_loads_and_lights_the_scene() {
    use ophis::image_io::{write_exr, RgbImage};
    let dir = temp_dir("envmap");
    // A 16×8 sky: uniform radiance 0.5 (so a white furnace at albedo 1 renders 0.5 everywhere).
    let img = RgbImage {
        width: 16,
        height: 8,
        data: vec![[0.5, 0.5, 0.5]; 128],
    };
    write_exr(dir.join("sky.exr"), &img, &[]).unwrap();
    let scene = dir.join("scene.xml");
    std::fs::write(
        &scene,
        r#"<scene version="3.0.0">
        <sensor type="perspective"><float name="fov" value="20"/>
            <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
            <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
        <emitter type="envmap"><string name="filename" value="sky.exr"/></emitter>
        <shape type="sphere"><bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></shape>
        </scene>"#,
    )
    .unwrap();
    let (s, _) = load_scene(&scene, &LoadOptions::default()).expect("loads");
    assert_eq!(s.infinite_lights.len(), 1);
    let mut film = ophis::film::Film::new(s.width, s.height);
    let opts = ophis::render::RenderOptions {
        spp: 16,
        time_limit: None,
        strategy: ophis::integrator::PathStrategy::Mis,
        engine: ophis::render::Engine::Auto,
    };
    ophis::render::render(
        &s,
        &mut film,
        0,
        &opts,
        &std::sync::atomic::AtomicBool::new(false),
        &ophis::render::NoProgress,
    );
    let rgb = film.to_linear_srgb();
    // The map's texels are linear sRGB 0.5 grey, a D65 emission of luminance 0.5, and the white
    // sphere vanishes into it (furnace): every pixel estimates 0.5. Mean within 4 standard errors.
    let v: Vec<f64> = rgb.iter().map(|p| p[1] as f64).collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let se = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
    assert!((mean - 0.5).abs() <= 4.0 * se + 1e-5, "mean {mean} ± {se}");
}
