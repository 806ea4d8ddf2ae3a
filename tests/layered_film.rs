//! The layered BSDF with a thin-film top: the random walk through a `thinfilm` interface against
//! the closed form with the film's exact Airy reflectance (research/layered.md §3.2 lists the
//! albedo values used here: film n = 1.8, 300 nm, on an n = 1.5 coat over a base of albedo 0.5),
//! and the white furnace with a film top. Statistical checks at 4 standard errors.

use ophis::bsdf::layered::LayeredModel;
use ophis::bsdf::{Bxdf, Material};
use ophis::scene::build::build_material;
use ophis::scene::mitsuba::load_str;
use ophis::tools::inspect::{at_wavelength, Quantity};
use std::path::Path;

fn material(id: &str, tau: f32, rho: f32, closed_form: bool) -> Material {
    let xml = format!(
        r#"<scene version="0.6.0">
        <bsdf type="multilayered" id="{id}">
            <integer name="nbLayers" value="2"/>
            <boolean name="closed_form" value="{closed_form}"/>
            <bsdf type="thinfilm" name="surface_0">
                <float name="int_ior" value="1.5"/><float name="ext_ior" value="1.0"/>
                <float name="film_ior" value="1.8"/><float name="film_thickness" value="300"/>
            </bsdf>
            <spectrum name="sigmaT_0" value="{tau}"/>
            <spectrum name="albedo_0" value="0"/>
            <bsdf type="diffuse" name="surface_1"><spectrum name="reflectance" value="{rho}"/></bsdf>
        </bsdf></scene>"#
    );
    let (root, _) = load_str(&xml, Path::new("film.xml"), &[]).expect("scene parses");
    let node = root
        .children
        .iter()
        .find(|c| c.node.id.as_deref() == Some(id))
        .expect("bsdf")
        .node
        .clone();
    build_material(&node, &mut Vec::new()).expect("material builds")
}

#[test]
fn walk_through_a_film_top_matches_the_research_albedo() {
    // τ = 1.4, normal incidence: research/layered.md §3.2 gives R = 0.135037 (450 nm),
    // 0.050829 (550 nm), 0.122312 (650 nm).
    for (lambda, want) in [(450.0, 0.135037), (550.0, 0.050829), (650.0, 0.122312)] {
        for closed in [true, false] {
            let m = material("skin", 1.4, 0.5, closed);
            // The smooth film coat takes the closed form unless it is switched off.
            let wl = ophis::spectrum::SampledWavelengths::fixed([lambda; 4]);
            let (bxdf, _) = m.eval(&Default::default(), &wl, true, 0);
            let is_closed =
                matches!(bxdf, Bxdf::Layered(ref l) if matches!(l.model, LayeredModel::Closed(_)));
            assert_eq!(is_closed, closed);
            let e = at_wavelength(&m, Quantity::Albedo { theta_i: 0.0 }, lambda, 100_000, 7);
            let tol = 4.0 * e.std_err + 1e-4;
            assert!(
                (e.mean - want).abs() <= tol,
                "closed_form={closed} λ={lambda}: {} ± {} vs {want}",
                e.mean,
                e.std_err
            );
        }
    }
}

#[test]
fn white_furnace_with_a_film_top_through_the_walk() {
    let m = material("white", 0.0, 1.0, false);
    for theta in [0.0, 60.0, 85.0] {
        let e = at_wavelength(&m, Quantity::Albedo { theta_i: theta }, 530.0, 50_000, 3);
        assert!(
            (e.mean - 1.0).abs() <= 4.0 * e.std_err + 1e-4,
            "θ={theta}: {} ± {}",
            e.mean,
            e.std_err
        );
    }
}
