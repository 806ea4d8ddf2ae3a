//! The seam between scene descriptions and the renderer's models.
//!
//! A scene arrives as a tree of [`Node`]s (from the Mitsuba XML reader in
//! [`crate::scene::mitsuba`], or built from a Python dictionary). Every plugin — a BSDF, a
//! texture, a shape, an emitter — is one file beside its model, holding its manual (the `//!`
//! header), its parameter declaration ([`Param`]s in a [`Plugin`]) and its loader. The loader
//! reads the node only through [`Args`], which takes defaults, accepted spellings and checks
//! from the declaration, so the declaration is the single source of truth for what the loader
//! reads, what `ophis plugins NAME` prints, and the tables of the README and the `//!` headers
//! (a test compares them). [`registry`] is the one table from plugin names to plugins.
//!
//! Layering: models (`bsdf/`, `texture/`, `shape/`, `light/`) depend on this module and on the
//! ones below it (`math`, `spectrum`, `optics`); nothing here reads XML, plots or renders.

/// Declares a plugin constant, as one registration line per plugin:
///
/// ```ignore
/// declare!(PLUGIN: Material = Bsdf "dielectric" [] "smooth glass …"
///     [DIELECTRIC_IORS, FACTORS] load);
/// ```
///
/// — the constant (crate-visible, documented as "The `dielectric` plugin."), its type
/// (`Material`, or `Texture, Want` for a loader with a request), the element, the name, its
/// aliases, the one-line summary, the parameter groups and the loader.
macro_rules! declare {
    ($id:ident: $t:ty $(, $c:ty)? = $tag:ident $name:literal
     [$($alias:literal),*] $summary:literal [$($group:expr),* $(,)?] $load:expr) => {
        #[doc = concat!("The `", $name, "` plugin.")]
        pub(crate) const $id: $crate::plugin::Plugin<$t $(, $c)?> = $crate::plugin::Plugin::new(
            $crate::plugin::Info::new(
                $crate::plugin::Tag::$tag,
                $name,
                $summary,
                &[$($group),*],
                file!(),
            )
            .aliases(&[$($alias),*]),
            $load,
        );
    };
}
pub(crate) use declare;

mod args;
mod error;
mod files;
pub mod manual;
mod node;
mod param;
mod properties;
pub mod registry;
mod suggest;
pub mod values;

pub use args::Args;
pub use error::SceneError;
pub(crate) use files::FileResolver;
pub(crate) use node::describe;
pub use node::{Child, Location, Node, Tag, Warning};
pub use param::{Check, DefaultValue, Info, Param, Plugin, Ty};
pub use properties::{Properties, SpectrumValue, Value};
pub use suggest::{did_you_mean, nearest};
pub use values::SpectrumKind;
