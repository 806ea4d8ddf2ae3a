//! `moment`: Mitsuba 3's integrator that renders its nested integrators and adds the second
//! moment of each as extra channels (to estimate a render's variance). ophis renders the
//! first nested integrator, so that scenes written for it load and give their image.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `(nested)` | integrator | required | — | the integrator whose image is rendered (the first, if several) |
//!
//! Known limits: the second-moment channels are not written, and nested integrators after the
//! first are ignored (a warning says both); ophis estimates noise by comparing independent
//! renders instead (`ophis merge`).

use crate::plugin::{declare, registry, Args, DefaultValue, Param, SceneError, Tag, Ty};
use crate::scene::IntegratorSettings;

declare!(PLUGIN: IntegratorSettings = Integrator "moment" []
    "renders its (first) nested integrator; the second-moment channels are not written"
    [&[Param::new("(nested)", Ty::Object(Tag::Integrator), DefaultValue::Required)
        .doc("the integrator whose image is rendered (the first, if several)")]] load);

fn load(a: &mut Args, _: ()) -> Result<IntegratorSettings, SceneError> {
    let nested = a.children(Tag::Integrator);
    let Some(first) = nested.first() else {
        return Err(SceneError::at(
            &a.node().loc,
            "integrator 'moment' needs a nested integrator, e.g. <integrator type=\"path\"/>",
        ));
    };
    let extra = if nested.len() > 1 {
        format!(
            " (the first of its {}; the others are ignored)",
            nested.len()
        )
    } else {
        String::new()
    };
    a.warn(format!(
        "integrator 'moment': rendering its nested integrator{extra}; the second-moment AOVs \
         are not written"
    ));
    registry::integrator(first, a.warnings())
}
