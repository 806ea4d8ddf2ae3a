//! `bitmap` textures (EXR and PNG) as colours and as normal maps, through whole renders: a
//! convex diffuse sphere under a uniform sky reflects ρ·L exactly (the furnace argument of
//! `render_furnace.rs`), so a texture of constant ρ must render ρ, and a flat normal map must
//! leave it unchanged. Means within 4 standard errors (+1e-5 for f32 rounding).

mod common;
use common::{mean_stderr, render_rgb};
use ophis::image_io::{write_exr, write_png, RgbImage};
use ophis::integrator::PathStrategy;
use ophis::scene::build::{load_scene, LoadOptions};

fn sphere_pixels_mean(xml_bsdf: &str, dir: &std::path::Path) -> (f64, f64) {
    let xml = format!(
        r#"<scene version="3.0.0">
        <integrator type="path"/>
        <sensor type="perspective"><float name="fov" value="10"/>
            <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="32"/></sampler>
            <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
                <rfilter type="box"/></film></sensor>
        <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
        <shape type="sphere">{xml_bsdf}</shape>
        </scene>"#
    );
    let path = dir.join("scene.xml");
    std::fs::write(&path, xml).unwrap();
    let (scene, warnings) = load_scene(&path, &LoadOptions::default()).expect("scene loads");
    assert!(warnings.is_empty(), "{warnings:?}");
    let img = render_rgb(&scene, 32, PathStrategy::Mis);
    // fov 10° at distance 5: the unit sphere (angular radius 11.5°) fills the whole image.
    let v: Vec<f64> = img.iter().map(|p| p[1] as f64).collect();
    mean_stderr(&v)
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("ophis-bitmap-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn exr_reflectance_texture_renders_its_albedo() {
    let dir = temp_dir("exr");
    write_exr(
        dir.join("grey.exr"),
        &RgbImage {
            width: 4,
            height: 2,
            data: vec![[0.5; 3]; 8],
        },
        &[],
    )
    .unwrap();
    let bsdf = r#"<bsdf type="diffuse"><texture type="bitmap" name="reflectance">
        <string name="filename" value="grey.exr"/></texture></bsdf>"#;
    let (m, se) = sphere_pixels_mean(bsdf, &dir);
    assert!((m - 0.5).abs() <= 4.0 * se + 1e-5, "{m} ± {se}");
}

#[test]
fn flat_png_normal_map_changes_nothing_and_bad_maps_are_errors() {
    let dir = temp_dir("png");
    // (0.5, 0.5, 1) encodes the unperturbed normal; written as raw data.
    let flat = RgbImage {
        width: 2,
        height: 2,
        data: vec![[0.5, 0.5, 1.0]; 4],
    };
    // write_png sRGB-encodes linear values; store the raw code values by decoding first.
    let raw = RgbImage {
        data: flat
            .data
            .iter()
            .map(|c| c.map(ophis::spectrum::cie::srgb_decode))
            .collect(),
        ..flat
    };
    write_png(dir.join("flat.png"), &raw).unwrap();
    let bsdf = r#"<bsdf type="normalmap">
        <texture type="bitmap"><string name="filename" value="flat.png"/><boolean name="raw" value="true"/></texture>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></bsdf>"#;
    let (m, se) = sphere_pixels_mean(bsdf, &dir);
    // The stored code 128/255 decodes to 0.00392 off flat: a negligible tilt for a furnace.
    assert!((m - 0.5).abs() <= 4.0 * se + 1e-5, "{m} ± {se}");

    // A missing file and a bad wrap mode are located errors.
    std::fs::write(
        dir.join("bad.xml"),
        "<scene version=\"3.0.0\"><shape type=\"sphere\"><bsdf type=\"diffuse\">\n<texture type=\"bitmap\" name=\"reflectance\">\n<string name=\"filename\" value=\"nope.png\"/></texture></bsdf></shape></scene>",
    )
    .unwrap();
    let e = load_scene(&dir.join("bad.xml"), &LoadOptions::default())
        .expect_err("missing file")
        .to_string();
    assert!(e.contains("bad.xml:3:") && e.contains("nope.png"), "{e}");
    std::fs::write(
        dir.join("bad2.xml"),
        "<scene version=\"3.0.0\"><shape type=\"sphere\"><bsdf type=\"diffuse\">\n<texture type=\"bitmap\" name=\"reflectance\">\n<string name=\"filename\" value=\"flat.png\"/>\n<string name=\"wrap_mode\" value=\"sideways\"/></texture></bsdf></shape></scene>",
    )
    .unwrap();
    let e = load_scene(&dir.join("bad2.xml"), &LoadOptions::default())
        .expect_err("bad wrap")
        .to_string();
    assert!(e.contains("bad2.xml:4:") && e.contains("sideways"), "{e}");
}

#[test]
fn tilted_png_normal_map_is_used() {
    // Normals tilted 45°: part of each shading hemisphere lies below the sphere's surface, where
    // a one-sided diffuse sphere only sees its own black inside, so the furnace darkens; a map
    // that were ignored would render 0.5.
    let dir = temp_dir("tilt");
    let n = [0.5 + 0.5 * 0.70710677, 0.5, 0.5 + 0.5 * 0.70710677];
    let raw = RgbImage {
        width: 1,
        height: 1,
        data: vec![n.map(ophis::spectrum::cie::srgb_decode)],
    };
    write_png(dir.join("tilt.png"), &raw).unwrap();
    let bsdf = r#"<bsdf type="normalmap">
        <texture type="bitmap"><string name="filename" value="tilt.png"/><boolean name="raw" value="true"/></texture>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></bsdf>"#;
    let (m, se) = sphere_pixels_mean(bsdf, &dir);
    assert!(m < 0.5 - 4.0 * se - 0.01, "{m} ± {se}");
}
