//! The `aov` integrator and the `thinlens` / `orthographic` sensors, end to end: AOV values on a
//! scene whose answers are known in closed form, the image unchanged by recording AOVs, the
//! EXR channels `ophis render` writes, and the sensors' loading errors.

mod common;

use common::scene;
use ophis::film::Film;
use ophis::render::{render, NoProgress, RenderOptions};
use ophis::scene::Scene;
use std::sync::atomic::AtomicBool;

/// A diffuse sphere (radius 0.5, reflectance 0.6) seen straight down by an orthographic camera
/// 2 units above its centre, with a box filter so that pixels are pure; `integrator` is
/// spliced in.
fn sphere_scene(integrator: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    {integrator}
    <sensor type="orthographic">
        <transform name="to_world">
            <lookat origin="0, 2, 0" target="0, 0, 0" up="0, 0, 1"/>
        </transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="sphere"><float name="radius" value="0.5"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
</scene>"#
    )
}

fn film_of(s: &Scene, spp: u32) -> Film {
    let mut film = Film::new(s.width, s.height);
    let opts = RenderOptions {
        spp,
        time_limit: None,
        strategy: ophis::integrator::PathStrategy::Mis,
        engine: ophis::render::Engine::Auto,
    };
    render(s, &mut film, 0, &opts, &AtomicBool::new(false), &NoProgress);
    film
}

const AOVS: &str = r#"<integrator type="aov">
        <string name="aovs" value="dd:depth,pp:position,nn:sh_normal,ng:geo_normal,id:shape_index,a:albedo,tri:prim_index"/>
        <integrator type="path" name="img"><integer name="max_depth" value="3"/></integrator>
    </integrator>"#;

#[test]
fn aovs_match_the_geometry_of_a_sphere_seen_from_above() {
    let s = scene(&sphere_scene(AOVS));
    let film = film_of(&s, 16);
    let images = film.aov_images();
    let get = |name: &str| &images.iter().find(|(n, _)| n == name).unwrap().1;
    let (w, h) = (film.width as usize, film.height as usize);
    let mut hits = 0;
    let mut albedo = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let id = get("id.I")[i];
            // The sensor is 2 × 2 units: pixel centres at ±(k + ½)/8.
            let (px, pz) = ((x as f32 + 0.5) / 8.0 - 1.0, (y as f32 + 0.5) / 8.0 - 1.0);
            let r2 = px * px + pz * pz;
            // A pixel is 1/8 wide: those whose samples may straddle the rim are skipped.
            if r2 > 0.09 && r2 < 0.36 {
                continue;
            }
            if r2 >= 0.36 {
                assert_eq!(id, 0.0, "background at ({x}, {y})");
                assert_eq!(get("dd.T")[i], 0.0);
                continue;
            }
            hits += 1;
            assert_eq!(id, 1.0, "the sphere is shape 1");
            // Where the pixel's samples land the surface is y = √(0.25 − x² − z²): within 0.3 of
            // the axis it varies by at most ±0.05 across a pixel, so the mean of 16 uniformly
            // placed samples is within 4σ ≈ 0.03 of the centre's value.
            let y_top = (0.25 - r2).sqrt();
            let tol = 0.03;
            assert!(
                (get("pp.Y")[i] - y_top).abs() < tol,
                "({x},{y}) {}",
                get("pp.Y")[i]
            );
            // Rays start on the near plane, 0.01 below the camera.
            assert!((get("dd.T")[i] - (2.0 - 0.01 - y_top)).abs() < tol);
            let n = [get("nn.X")[i], get("nn.Y")[i], get("nn.Z")[i]];
            let g = [get("ng.X")[i], get("ng.Y")[i], get("ng.Z")[i]];
            for (a, b) in n.iter().zip(g) {
                assert!(
                    (a - b).abs() < 1e-4,
                    "analytic sphere: shading = geometric normal"
                );
            }
            assert!((n[1] - 2.0 * y_top).abs() < 2.0 * tol, "normal {n:?}");
            for c in ["a.R", "a.G", "a.B"] {
                albedo.push(get(c)[i] as f64);
            }
            assert_eq!(get("tri.I")[i], 0.0);
        }
    }
    assert_eq!(hits, 16, "the 4 × 4 pixels within 0.3 of the axis");
    // A diffuse surface's directional albedo is its reflectance: cosine sampling makes the
    // estimate exact per direction, and what noise remains is the colour conversion's from four
    // wavelengths per sample (as in the image). The mean over the pixels is 0.6 within 4σ.
    let (mean, se) = common::mean_stderr(&albedo);
    assert!((mean - 0.6).abs() < 4.0 * se + 1e-4, "albedo {mean} ± {se}");
    assert!(se < 0.01, "{se}");
}

#[test]
fn recording_aovs_leaves_the_image_bit_for_bit_unchanged() {
    let plain = scene(&sphere_scene(
        r#"<integrator type="path"><integer name="max_depth" value="3"/></integrator>"#,
    ));
    let with = scene(&sphere_scene(AOVS));
    let (a, b) = (film_of(&plain, 8), film_of(&with, 8));
    assert_eq!(a.pixels, b.pixels);
    assert!(a.aov_names.is_empty());
    assert_eq!(b.aov_names.len(), 1 + 3 + 3 + 3 + 1 + 3 + 1);
    // Without a nested integrator the image is black.
    let only = scene(&sphere_scene(
        r#"<integrator type="aov"><string name="aovs" value="dd:depth"/></integrator>"#,
    ));
    let f = film_of(&only, 2);
    assert!(f.to_linear_srgb().iter().flatten().all(|v| *v == 0.0));
    assert!(f.aov_images()[0].1.iter().any(|v| *v > 1.0));
}

#[test]
fn ophis_render_writes_mitsubas_channel_names_and_the_shape_legend() {
    let dir = std::env::temp_dir().join(format!("ophis-aov-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let xml = dir.join("s.xml");
    std::fs::write(&xml, sphere_scene(AOVS)).unwrap();
    let out = dir.join("s.exr");
    let st = std::process::Command::new(env!("CARGO_BIN_EXE_ophis"))
        .args(["render", "-q", "--spp", "2", "-o"])
        .arg(&out)
        .arg(&xml)
        .status()
        .unwrap();
    assert!(st.success());
    let mut names = ophis::image_io::read_exr_channel_names(&out).unwrap();
    names.sort();
    for want in [
        "R", "G", "B", "img.R", "img.G", "img.B", "img.A", "dd.T", "nn.X", "nn.Y", "nn.Z", "id.I",
        "a.R", "tri.I",
    ] {
        assert!(
            names.iter().any(|n| n == want),
            "{want} missing from {names:?}"
        );
    }
    let meta = ophis::image_io::read_exr_metadata(&out).unwrap();
    let get = |k: &str| meta.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
    assert_eq!(get("ophis.shapes").as_deref(), Some("1=sphere"));
    assert!(get("ophis.aovs").unwrap().contains("dd.T"));
    // The colour reads back as the image.
    let img = ophis::image_io::read_image(&out).unwrap();
    assert_eq!((img.width, img.height), (16, 16));
    // Merging it is refused by name.
    let merged = dir.join("m.exr");
    let m = std::process::Command::new(env!("CARGO_BIN_EXE_ophis"))
        .arg("merge")
        .arg(&merged)
        .arg(&out)
        .output()
        .unwrap();
    assert!(!m.status.success());
    assert!(String::from_utf8_lossy(&m.stderr).contains("carries AOV channels"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sensors_load_with_mitsubas_parameters_and_refuse_bad_ones() {
    let base = |sensor: &str| {
        format!(
            r#"<scene version="3.0.0">{sensor}
            <shape type="sphere"/><emitter type="constant"/></scene>"#
        )
    };
    let load = |sensor: &str| {
        ophis::scene::build::load_scene_str(
            &base(sensor),
            std::path::Path::new("cam.xml"),
            &Default::default(),
        )
    };
    let (s, w) = load(
        r#"<sensor type="thinlens"><float name="fov" value="30"/>
        <float name="aperture_radius" value="0.05"/><float name="focus_distance" value="3"/>
        <transform name="to_world"><lookat origin="0,0,-4" target="0,0,0" up="0,1,0"/></transform>
        </sensor>"#,
    )
    .unwrap();
    assert!(w.is_empty(), "{w:?}");
    match &s.camera {
        ophis::camera::Camera::ThinLens(c) => {
            assert_eq!((c.aperture_radius, c.focus_distance), (0.05, 3.0));
        }
        other => panic!("{other:?}"),
    }
    let (s, w) = load(r#"<sensor type="orthographic"/>"#).unwrap();
    assert!(w.is_empty(), "{w:?}");
    assert!(matches!(s.camera, ophis::camera::Camera::Orthographic(_)));
    // A pinhole reads the focus distance and ignores it, as Mitsuba's does.
    let (_, w) =
        load(r#"<sensor type="perspective"><float name="focus_distance" value="2"/></sensor>"#)
            .unwrap();
    assert!(w.is_empty(), "{w:?}");
    for (sensor, says) in [
        (r#"<sensor type="thinlens"/>"#, "needs 'aperture_radius'"),
        (
            r#"<sensor type="thinlens"><float name="aperture_radius" value="-1"/></sensor>"#,
            "'aperture_radius' of sensor 'thinlens': must be non-negative, got -1",
        ),
        (
            r#"<sensor type="thinlens"><float name="aperture_radius" value="1"/>
            <float name="focus_distance" value="0"/></sensor>"#,
            "focus_distance",
        ),
    ] {
        let e = load(sensor).unwrap_err().to_string();
        assert!(e.contains(says) && e.starts_with("cam.xml:"), "{e}");
    }
    // AOV lists are checked where they are written.
    let e = ophis::scene::build::load_scene_str(
        &sphere_scene(
            r#"<integrator type="aov"><string name="aovs" value="x:colour"/></integrator>"#,
        ),
        std::path::Path::new("aov.xml"),
        &Default::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("unknown AOV type 'colour'") && e.starts_with("aov.xml:"),
        "{e}"
    );
}

#[test]
fn a_resumed_aov_render_equals_an_uninterrupted_one_and_round_trips_its_state() {
    let s = scene(&sphere_scene(AOVS));
    let whole = film_of(&s, 6);
    // The first two passes (1 + 2 samples, a prefix of the 6-sample schedule), then continue
    // from the saved state's film.
    let part = film_of(&s, 3);
    let info = ophis::checkpoint::StateInfo {
        scene_path: "s.xml".into(),
        scene_hash: 1,
        seed: 0,
        spp: 6,
        strategy: "mis".into(),
        defines: vec![],
    };
    let bytes = {
        let mut b = Vec::new();
        info.encode(&part, &mut b).unwrap();
        b
    };
    let state =
        ophis::checkpoint::RenderState::from_bytes(&bytes, std::path::Path::new("s")).unwrap();
    assert_eq!(state.film, part);
    let mut resumed = state.film;
    let opts = RenderOptions {
        spp: 6,
        time_limit: None,
        strategy: ophis::integrator::PathStrategy::Mis,
        engine: ophis::render::Engine::Auto,
    };
    render(
        &s,
        &mut resumed,
        3,
        &opts,
        &AtomicBool::new(false),
        &NoProgress,
    );
    assert_eq!(resumed.pixels, whole.pixels);
    assert_eq!(resumed.aov, whole.aov);
}
