//! BSDFs `multilayered` and `absorption` (the seed's layered skin; parameter tables in
//! `bsdf/layered/mod.rs` and `bsdf/absorption.rs`).

use super::materials::{build_material, spectrum_texture};
use super::values::{checked_float, checked_int, SpectrumKind};
use crate::bsdf::layered::{DEFAULT_MAX_DEPTH, MAX_INTERFACES};
use crate::bsdf::material::LayerMedium;
use crate::bsdf::Material;
use crate::scene::mitsuba::{Node, SceneError, Tag, Warning};
use crate::spectrum::Spectrum;

/// Parameters the seed's `multilayered` takes that ophis accepts and ignores (its `pdf` is
/// ophis's own mixture; its eval is unidirectional).
const IGNORED: [&str; 8] = [
    "pdf",
    "diffuse_pdf",
    "stoch_pdf_depth",
    "pdf_repetitive",
    "bidir",
    "mis",
    "bidir_use_analog",
    "max_survival_prob",
];

/// `multilayered`: `nb_layers` surfaces `surface_i` and the media `sigma_t_i`, `albedo_i`,
/// `phase_i` between them.
pub(crate) fn multilayered(
    node: &Node,
    warnings: &mut Vec<Warning>,
) -> Result<Material, SceneError> {
    let named = (0..)
        .take_while(|i| node.child(&format!("surface_{i}")).is_some())
        .count() as i64;
    if !node.props.contains("nb_layers") && !(2..=MAX_INTERFACES as i64).contains(&named) {
        // Without 'nb_layers' the count comes from the surfaces; say so rather than "got 0".
        let hint = match node
            .props
            .iter()
            .find(|(n, _, _)| n.eq_ignore_ascii_case("nblayers"))
        {
            Some((n, v, _)) => format!(
                " ('{n}' = {} is not read: version 3 scenes spell it 'nb_layers')",
                match v {
                    crate::scene::mitsuba::Value::Integer(i) => i.to_string(),
                    other => format!("a {}", other.type_name()),
                }
            ),
            None => String::new(),
        };
        return Err(SceneError::at(
            &node.loc,
            format!(
                "{} found {named} nested bsdfs 'surface_0', 'surface_1', … and no 'nb_layers'{hint}; \
                 expected 2 to {MAX_INTERFACES} surfaces",
                node.describe()
            ),
        ));
    }
    let n = checked_int(node, "nb_layers", named, 2, MAX_INTERFACES as i64)? as usize;
    let mut surfaces = Vec::with_capacity(n);
    for i in 0..n {
        let name = format!("surface_{i}");
        let child = node
            .child(&name)
            .filter(|c| c.tag == Tag::Bsdf)
            .ok_or_else(|| {
                SceneError::at(
                    &node.loc,
                    format!(
                        "{} needs a nested bsdf named '{name}' (nb_layers = {n})",
                        node.describe()
                    ),
                )
            })?;
        surfaces.push(build_material(child, warnings)?);
    }
    let mut media = Vec::with_capacity(n - 1);
    for i in 0..n - 1 {
        let sigma_t = spectrum_texture(
            node,
            &format!("sigma_t_{i}"),
            SpectrumKind::Unbounded,
            Spectrum::Constant(0.0),
        )?;
        let albedo = spectrum_texture(
            node,
            &format!("albedo_{i}"),
            SpectrumKind::Albedo,
            Spectrum::Constant(0.0),
        )?;
        media.push(LayerMedium {
            sigma_t,
            albedo,
            g: phase_g(node, i)?,
        });
    }
    let max_depth = node.props.get_int("max_depth", -1)?;
    let max_depth = if max_depth <= 0 {
        DEFAULT_MAX_DEPTH
    } else {
        max_depth.min(1 << 20) as u32
    };
    let closed_form = node.props.get_bool("closed_form", true)?;
    for name in IGNORED {
        if node.props.contains(name) {
            node.props.mark_queried(name);
        }
    }
    Ok(Material::Multilayered {
        surfaces,
        media,
        max_depth,
        closed_form,
    })
}

/// `phase_i`: a float (HG g) or a nested `phase` (`hg` with `g`, or `isotropic`).
fn phase_g(node: &Node, i: usize) -> Result<f32, SceneError> {
    let name = format!("phase_{i}");
    let ok = |g: f32| g > -1.0 && g < 1.0;
    if let Some(ph) = node.child(&name).filter(|c| c.tag == Tag::Phase) {
        return match ph.plugin.as_str() {
            "isotropic" => Ok(0.0),
            "hg" => checked_float(ph, "g", 0.0, ok, "in (−1, 1)"),
            other => Err(SceneError::at(
                &ph.loc,
                format!(
                    "phase '{other}' is not supported in multilayered (use 'hg' or 'isotropic')"
                ),
            )),
        };
    }
    checked_float(node, &name, 0.0, ok, "a Henyey–Greenstein g in (−1, 1)")
}

/// `absorption`: Lambertian `reflectance` under a layer with `sigma_a` and `thickness`.
pub(crate) fn absorption(node: &Node) -> Result<Material, SceneError> {
    Ok(Material::Absorption {
        reflectance: spectrum_texture(
            node,
            "reflectance",
            SpectrumKind::Albedo,
            Spectrum::Constant(0.5),
        )?,
        sigma_a: spectrum_texture(
            node,
            "sigma_a",
            SpectrumKind::Unbounded,
            Spectrum::Constant(0.0),
        )?,
        thickness: checked_float(
            node,
            "thickness",
            1.0,
            |t| t >= 0.0 && t.is_finite(),
            "a non-negative number",
        )?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::layered::LayeredBxdf;
    use crate::bsdf::Bxdf;
    use crate::scene::mitsuba::load_str;
    use crate::spectrum::SampledWavelengths;
    use crate::texture::TexCoord;
    use std::path::Path;

    fn build(body: &str) -> Result<Material, SceneError> {
        let xml = format!("<scene version=\"0.6.0\">{body}</scene>");
        let (root, _) = load_str(&xml, Path::new("t.xml"), &[]).unwrap();
        let node = root.children_with_tag(Tag::Bsdf).next().unwrap();
        build_material(node, &mut Vec::new())
    }

    fn bxdf(m: &Material) -> Bxdf {
        let wl = SampledWavelengths::fixed([450.0, 500.0, 550.0, 600.0]);
        m.eval(&TexCoord::default(), &wl, true).0
    }

    const SEED_STACK: &str = r#"<bsdf type="multilayered">
        <integer name="nbLayers" value="2"/>
        <bsdf type="dielectric" name="surface_0"><float name="intIOR" value="1.5"/><float name="extIOR" value="1"/></bsdf>
        <spectrum name="sigmaT_0" value="1.4"/>
        <spectrum name="albedo_0" value="0"/>
        <float name="phase_0" value="0"/>
        <bsdf type="diffuse" name="surface_1"><spectrum name="reflectance" value="0.5"/></bsdf>
        <string name="pdf" value="bidirStochTRT"/>
        <float name="diffusePdf" value="0.1"/>
        <integer name="maxDepth" value="-1"/>
        CF
    </bsdf>"#;

    #[test]
    fn seed_syntax_loads_and_picks_the_closed_form() {
        let m = build(&SEED_STACK.replace("CF", "")).unwrap();
        let Bxdf::Layered(l) = bxdf(&m) else { panic!() };
        assert!(matches!(l.as_ref(), LayeredBxdf::Closed(_)));
        let off = r#"<boolean name="closed_form" value="false"/>"#;
        let m = build(&SEED_STACK.replace("CF", off)).unwrap();
        let Bxdf::Layered(l) = bxdf(&m) else { panic!() };
        assert!(matches!(l.as_ref(), LayeredBxdf::Walk(_)));
    }

    #[test]
    fn bad_stacks_are_located_errors() {
        let e = build(
            &SEED_STACK
                .replace("value=\"2\"", "value=\"3\"")
                .replace("CF", ""),
        );
        assert!(e.unwrap_err().to_string().contains("surface_2"));
        let e = build(
            &SEED_STACK
                .replace("value=\"2\"", "value=\"9\"")
                .replace("CF", ""),
        );
        assert!(e.unwrap_err().to_string().contains("t.xml:"));
        let e = build(
            &SEED_STACK
                .replace(
                    r#"name="phase_0" value="0""#,
                    r#"name="phase_0" value="1.5""#,
                )
                .replace("CF", ""),
        );
        assert!(e.unwrap_err().to_string().contains("phase_0"));
        let e = build(r#"<bsdf type="absorption"><float name="thickness" value="-1"/></bsdf>"#);
        assert!(e.unwrap_err().to_string().contains("thickness"));
    }

    #[test]
    fn absorption_loads_with_seed_names() {
        let m = build(r#"<bsdf type="absorption"><spectrum name="sigmaA" value="0.7"/><float name="thickness" value="2"/></bsdf>"#).unwrap();
        let Bxdf::Absorption(a) = bxdf(&m) else {
            panic!()
        };
        assert!((a.tau[0] - 1.4).abs() < 1e-6 && (a.rho[0] - 0.5).abs() < 1e-6);
    }
}
