//! The manuals cannot drift from the loaders: every plugin file's `//!` header holds the
//! parameter table generated from its declaration, `docs/plugins.md` is the generated
//! reference, and the README's plugin list is the generated summary. Every declared value
//! parameter is read by its loader under every spelling the manual gives (no "never used"
//! warning), and misspelt plugins and parameters get suggestions.
//!
//! After changing a declaration, regenerate all three with
//! `OPHIS_WRITE_MANUALS=1 cargo test --release --test plugin_manuals`.

use ophis::plugin::{manual, registry, DefaultValue, Info, Param, Tag, Ty};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn writing() -> bool {
    std::env::var("OPHIS_WRITE_MANUALS").is_ok()
}

/// The plugin whose table a file's header holds: the one named like the file, or its only one.
fn primary_per_file() -> BTreeMap<&'static str, &'static Info> {
    let mut by_file: BTreeMap<&'static str, Vec<&'static Info>> = BTreeMap::new();
    for i in registry::all() {
        by_file.entry(i.file).or_default().push(i);
    }
    by_file
        .into_iter()
        .map(|(file, infos)| {
            let stem = Path::new(file).file_stem().unwrap().to_str().unwrap();
            let p = match infos.iter().find(|i| i.name == stem) {
                Some(i) => *i,
                None => {
                    assert_eq!(
                        infos.len(),
                        1,
                        "{file}: which plugin's table is the header's?"
                    );
                    infos[0]
                }
            };
            (file, p)
        })
        .collect()
}

/// The header with its parameter table (the `//! |` lines after `//! ## Parameters`, or the
/// `//! PARAMS` placeholder) replaced by `table`.
fn with_table(src: &str, table: &str) -> Option<String> {
    let lines: Vec<&str> = src.lines().collect();
    let head = lines
        .iter()
        .position(|l| l.trim_end() == "//! ## Parameters")?;
    let start = (head + 1..lines.len()).find(|&i| {
        let l = lines[i].trim_end();
        l.starts_with("//! |") || l == "//! PARAMS"
    })?;
    let mut end = start;
    while end < lines.len()
        && (lines[end].starts_with("//! |") || lines[end].trim_end() == "//! PARAMS")
    {
        end += 1;
    }
    let mut out: Vec<String> = lines[..start].iter().map(|s| s.to_string()).collect();
    out.extend(table.lines().map(|l| format!("//! {l}")));
    out.extend(lines[end..].iter().map(|s| s.to_string()));
    let mut s = out.join("\n");
    s.push('\n');
    Some(s)
}

#[test]
fn plugin_headers_hold_their_declared_tables() {
    let mut bad = Vec::new();
    for (file, info) in primary_per_file() {
        let path = root().join(file);
        let src = std::fs::read_to_string(&path).unwrap();
        let table = if info.params.iter().all(|g| g.is_empty()) {
            "| parameter | type | default | unit | meaning |\n|---|---|---|---|---|\n".to_string()
        } else {
            info.markdown_table()
        };
        let Some(want) = with_table(&src, &table) else {
            bad.push(format!(
                "{file}: no `//! ## Parameters` section with a table"
            ));
            continue;
        };
        if want != src {
            if writing() {
                std::fs::write(&path, &want).unwrap();
            } else {
                bad.push(format!(
                    "{file}: the header's table differs from the declaration of '{}'",
                    info.name
                ));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "{bad:#?}\n(OPHIS_WRITE_MANUALS=1 cargo test --release --test plugin_manuals rewrites them)"
    );
}

#[test]
fn docs_reference_is_generated() {
    let path = root().join("docs/plugins.md");
    let want = manual::reference_markdown();
    if writing() {
        std::fs::write(&path, &want).unwrap();
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/plugins.md is stale: regenerate it (see the module doc)"
    );
}

#[test]
fn readme_lists_every_plugin() {
    let path = root().join("README.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let (b, e) = ("<!-- plugins:begin -->\n", "<!-- plugins:end -->");
    let start = text.find(b).expect("README has a plugins:begin marker") + b.len();
    let end = text.find(e).expect("README has a plugins:end marker");
    let want = manual::summary_markdown();
    if writing() && text[start..end] != want {
        let new = format!("{}{want}{}", &text[..start], &text[end..]);
        std::fs::write(&path, new).unwrap();
        return;
    }
    assert!(
        text[start..end] == want,
        "README's plugin list is stale: regenerate it (see the module doc)"
    );
}

/// A value that passes `p`'s check, written as an XML value tag; `None` for parameters that
/// are not plain values (nested objects, transforms).
fn sample_value(p: &Param, name: &str) -> Option<String> {
    use ophis::plugin::Check;
    let num = match p.check {
        Check::Range(lo, hi) | Check::OpenClosed(lo, hi) | Check::Open(lo, hi) => {
            if lo < 0.0 && hi > 0.0 {
                0.0
            } else {
                (lo + hi) / 2.0
            }
        }
        _ => match p.default {
            DefaultValue::Float(v) => v as f64,
            DefaultValue::Int(v) => v as f64,
            _ => 1.0,
        },
    };
    Some(match p.ty {
        Ty::Float | Ty::FloatTexture => format!(r#"<float name="{name}" value="{num}"/>"#),
        Ty::Integer => format!(r#"<integer name="{name}" value="{}"/>"#, num.round() as i64),
        Ty::Boolean => format!(r#"<boolean name="{name}" value="true"/>"#),
        Ty::String => {
            let v = match (p.check, p.default) {
                (Check::OneOf(v), _) => v[0].to_string(),
                (_, DefaultValue::Str(s)) => s.to_string(),
                _ => return None,
            };
            format!(r#"<string name="{name}" value="{v}"/>"#)
        }
        Ty::Ior => format!(r#"<float name="{name}" value="1.33"/>"#),
        Ty::Spectrum(_) | Ty::SpectrumTexture(_) => {
            format!(r#"<spectrum name="{name}" value="0.5"/>"#)
        }
        _ => return None,
    })
}

/// Loads `<tag type="plugin">value</tag>` and returns the names never read.
fn unused_after_load(info: &Info, value: &str) -> Result<Vec<String>, String> {
    let tag = info.tag.as_str();
    let xml = format!(
        r#"<scene version="3.0.0"><{tag} type="{}">{value}</{tag}></scene>"#,
        info.name
    );
    let (root, _) = ophis::scene::mitsuba::load_str(&xml, Path::new("t.xml"), &[])
        .map_err(|e| e.to_string())?;
    let node = &root.children[0].node;
    let mut w = Vec::new();
    let r = match info.tag {
        Tag::Bsdf => registry::bsdf(node, &mut w).map(|_| ()),
        Tag::Texture => registry::texture(node, ophis::texture::Want::Float, &mut w)
            .or_else(|_| {
                registry::texture(
                    node,
                    ophis::texture::Want::Spectrum(ophis::plugin::SpectrumKind::Albedo),
                    &mut w,
                )
            })
            .map(|_| ()),
        // Shape index 0 stands for the shape an `area` emitter would be nested in.
        Tag::Emitter => registry::emitter(node, Some(0), &mut w).map(|_| ()),
        Tag::Shape => registry::shape(node, ophis::math::Transform::IDENTITY, &mut w).map(|_| ()),
        Tag::Sensor => registry::sensor(node, None, &mut w).map(|_| ()),
        Tag::Film => registry::film(node, &mut w).map(|_| ()),
        Tag::Rfilter => registry::rfilter(node, &mut w).map(|_| ()),
        Tag::Sampler => registry::sampler(node, &mut w).map(|_| ()),
        Tag::Integrator => registry::integrator(node, &mut w).map(|_| ()),
        _ => return Err("not checked here".into()),
    };
    r.map_err(|e| e.to_string())?;
    Ok(node.props.unqueried().into_iter().map(|(n, _)| n).collect())
}

/// Sample values of the parameters a plugin requires (so that it loads), leaving out `but`.
fn required_values(info: &Info, but: &Param) -> String {
    info.all_params()
        .filter(|p| p.default == DefaultValue::Required && *p != but)
        .filter_map(|p| sample_value(p, p.name))
        .collect()
}

#[test]
fn every_declared_parameter_is_read_under_every_spelling() {
    let mut checked = 0;
    let mut failures = Vec::new();
    let mut kinds = std::collections::BTreeSet::new();
    for info in registry::all() {
        for p in info.all_params() {
            let required = required_values(info, p);
            // Plugins that need nested objects or files are loaded by their own tests.
            if unused_after_load(info, &required).is_err() {
                continue;
            }
            for name in p.names() {
                let name = match name.strip_suffix("_i") {
                    Some(prefix) => format!("{prefix}_0"),
                    None => name.to_string(),
                };
                let Some(v) = sample_value(p, &name) else {
                    continue;
                };
                match unused_after_load(info, &format!("{required}{v}")) {
                    Ok(unused) if unused.is_empty() => {
                        checked += 1;
                        kinds.insert(info.tag.as_str());
                    }
                    Ok(unused) => {
                        failures.push(format!("{} '{name}': never read {unused:?}", info.name))
                    }
                    Err(e) if e.contains("not both") => {}
                    Err(e) => failures.push(format!("{} '{name}' = {v}: {e}", info.name)),
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
    assert!(checked > 100, "only {checked} spellings checked");
    // Every kind of plugin with value parameters is covered.
    let all = "bsdf emitter film integrator rfilter sampler sensor shape texture";
    assert_eq!(kinds.into_iter().collect::<Vec<_>>().join(" "), all);
}

#[test]
fn misspelt_plugins_are_errors_with_suggestions() {
    let cases = [
        (
            r#"<bsdf type="roughconductr"/>"#,
            "did you mean 'roughconductor'?",
        ),
        (
            r#"<bsdf type="diffuse"><texture type="chekerboard" name="reflectance"/></bsdf>"#,
            "did you mean 'checkerboard'?",
        ),
    ];
    for (body, want) in cases {
        let xml = format!(
            "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n{body}\n</shape>\n</scene>"
        );
        let e = ophis::scene::build::load_scene_str(&xml, Path::new("t.xml"), &Default::default())
            .map(|_| ())
            .expect_err("an error")
            .to_string();
        assert!(e.starts_with("t.xml:3:") && e.contains(want), "{e}");
    }
}

#[test]
fn misspelt_emitters_are_errors_and_mitsuba_ones_ophis_lacks_are_warnings() {
    let load = |body: &str| {
        let xml = format!("<scene version=\"3.0.0\">\n\n{body}\n</scene>");
        ophis::scene::build::load_scene_str(&xml, Path::new("t.xml"), &Default::default())
            .map(|(s, w)| (s.lights.len(), w))
            .map_err(|e| e.to_string())
    };
    let e = load(r#"<emitter type="sunksy"/>"#).expect_err("an error");
    assert!(
        e.starts_with("t.xml:3:") && e.contains("did you mean 'sunsky'"),
        "{e}"
    );
    let e = load(r#"<shape type="spehre"/>"#).expect_err("an error");
    assert!(
        e.starts_with("t.xml:3:") && e.contains("did you mean 'sphere'"),
        "{e}"
    );
    let (n, w) = load(r#"<emitter type="spot"/><emitter type="constant"/>"#).unwrap();
    assert_eq!(n, 1);
    assert!(
        w.iter()
            .any(|w| w.to_string().starts_with("t.xml:3:") && w.message.contains("'spot'")),
        "{w:?}"
    );
}

#[test]
fn unused_parameters_name_the_nearest_declared_ones() {
    let xml =
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n<bsdf type=\"roughconductor\">\n\
               <float name=\"alpah\" value=\"0.2\"/>\n</bsdf>\n</shape>\n</scene>";
    let (_, warnings) =
        ophis::scene::build::load_scene_str(xml, Path::new("t.xml"), &Default::default()).unwrap();
    let w: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        w.iter().any(|w| w.starts_with("t.xml:4:")
            && w.contains("'alpah'")
            && w.contains("did you mean 'alpha'")),
        "{w:#?}"
    );
}

/// A scene with `sensor` (one line) and `integrator` (one line), from line 3 on.
fn sensor_scene(sensor: &str, integrator: &str) -> String {
    format!("<scene version=\"3.0.0\">\n\n{sensor}\n{integrator}\n</scene>")
}

#[test]
fn misspelt_sensors_films_samplers_filters_and_integrators_are_errors() {
    let cases = [
        (
            r#"<sensor type="perspectiv"/>"#,
            "",
            "t.xml:3:",
            "'perspective'",
        ),
        (
            r#"<sensor type="perspective"><film type="hdrflm"/></sensor>"#,
            "",
            "t.xml:3:",
            "'hdrfilm'",
        ),
        (
            r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="gausian"/></film></sensor>"#,
            "",
            "t.xml:3:",
            "'gaussian'",
        ),
        (
            r#"<sensor type="perspective"><sampler type="indepedent"/></sensor>"#,
            "",
            "t.xml:3:",
            "'independent'",
        ),
        ("", r#"<integrator type="paht"/>"#, "t.xml:4:", "'path'"),
        (
            "",
            r#"<integrator type="aov"><string name="aovs" value="d:depth"/><integrator type="dirct"/></integrator>"#,
            "t.xml:4:",
            "'direct'",
        ),
    ];
    for (sensor, integrator, at, want) in cases {
        let xml = sensor_scene(sensor, integrator);
        let e = ophis::scene::build::load_scene_str(&xml, Path::new("t.xml"), &Default::default())
            .map(|_| ())
            .expect_err("an error")
            .to_string();
        assert!(
            e.starts_with(at) && e.contains(&format!("did you mean {want}")),
            "{e}"
        );
    }
}

#[test]
fn mitsuba_sensors_films_filters_and_integrators_ophis_lacks_load_as_the_nearest_it_has() {
    let xml = sensor_scene(
        r#"<sensor type="radiancemeter"><float name="fov" value="30"/><film type="specfilm"><integer name="width" value="20"/><rfilter type="lanczos"/></film></sensor>"#,
        r#"<integrator type="volpath"><integer name="max_depth" value="3"/></integrator>"#,
    );
    let (scene, w) =
        ophis::scene::build::load_scene_str(&xml, Path::new("t.xml"), &Default::default()).unwrap();
    // Read as `perspective`, `hdrfilm`, `gaussian` and `path`, with their parameters.
    assert!(matches!(
        scene.camera,
        ophis::camera::Camera::Perspective(_)
    ));
    assert_eq!(scene.width, 20);
    assert!(matches!(scene.filter, ophis::film::Filter::Gaussian { .. }));
    assert_eq!(scene.integrator.max_depth, Some(3));
    for (at, name, instead) in [
        ("t.xml:3:", "sensor 'radiancemeter'", "'perspective'"),
        ("t.xml:3:", "film 'specfilm'", "'hdrfilm'"),
        ("t.xml:3:", "rfilter 'lanczos'", "'gaussian'"),
        ("t.xml:4:", "integrator 'volpath'", "'path'"),
    ] {
        assert!(
            w.iter().any(|w| w.to_string().starts_with(at)
                && w.message.contains(name)
                && w.message.contains(instead)),
            "{name}: {w:#?}"
        );
    }
    // Nothing was left unread.
    assert!(
        !w.iter().any(|w| w.message.contains("never used")),
        "{w:#?}"
    );
}

#[test]
fn unused_sensor_and_integrator_parameters_name_the_nearest_declared_ones() {
    let xml = sensor_scene(
        r#"<sensor type="thinlens"><float name="aperture_radius" value="0.1"/><float name="focus_distnace" value="2"/></sensor>"#,
        r#"<integrator type="path"><integer name="max_dpeth" value="3"/></integrator>"#,
    );
    let (_, w) =
        ophis::scene::build::load_scene_str(&xml, Path::new("t.xml"), &Default::default()).unwrap();
    let w: Vec<String> = w.iter().map(|w| w.to_string()).collect();
    for (at, said) in [
        ("t.xml:3:", "did you mean 'focus_distance'"),
        ("t.xml:4:", "did you mean 'max_depth'"),
    ] {
        assert!(
            w.iter().any(|w| w.starts_with(at) && w.contains(said)),
            "{said}: {w:#?}"
        );
    }
}
