//! The plugin reference, generated from the declarations: what `ophis plugins` prints, the
//! tables in each plugin file's `//!` header, `docs/plugins.md` and the README's list (tests
//! compare all of them with this output, so none can drift from the loaders).

use super::registry;
use super::{Info, Tag};
use std::fmt::Write as _;

/// The elements plugins appear as, in the order the reference lists them.
const TAGS: [Tag; 9] = [
    Tag::Bsdf,
    Tag::Texture,
    Tag::Shape,
    Tag::Emitter,
    Tag::Sensor,
    Tag::Film,
    Tag::Rfilter,
    Tag::Sampler,
    Tag::Integrator,
];

fn names(i: &Info) -> String {
    let mut s = format!("`{}`", i.name);
    for a in i.aliases {
        write!(s, ", `{a}`").unwrap();
    }
    s
}

/// One table per element of every plugin: names, aliases and summary.
pub fn summary_markdown() -> String {
    let all = registry::all();
    let mut s = String::new();
    for tag in TAGS {
        let of: Vec<&Info> = all.iter().copied().filter(|i| i.tag == tag).collect();
        if of.is_empty() {
            continue;
        }
        writeln!(s, "| {tag} | what |\n|---|---|").unwrap();
        for i in of {
            writeln!(s, "| {} | {} |", names(i), i.summary).unwrap();
        }
        s.push('\n');
    }
    s
}

/// The manual of one plugin: its names, summary and parameter table.
pub fn plugin_markdown(i: &Info) -> String {
    let mut s = format!("### {} `{}`\n\n{}", i.tag, i.name, capitalise(i.summary));
    if !i.aliases.is_empty() {
        let a: Vec<String> = i.aliases.iter().map(|a| format!("`{a}`")).collect();
        write!(s, " Also loads as {}.", a.join(", ")).unwrap();
    }
    write!(s, " Source and model: `{}`.\n\n", i.file).unwrap();
    if i.params.iter().all(|g| g.is_empty()) {
        s.push_str("No parameters.\n");
    } else {
        s.push_str(&i.markdown_table());
    }
    s
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect::<String>() + ".",
        None => String::new(),
    }
}

/// The whole reference (`docs/plugins.md`).
pub fn reference_markdown() -> String {
    let mut s = String::from(
        "# ophis plugin reference\n\nGenerated from the plugins' declarations by \
         `ophis plugins --markdown`; a test keeps this file equal to its output.\n\n",
    );
    for tag in TAGS {
        for i in registry::all().into_iter().filter(|i| i.tag == tag) {
            s.push_str(&plugin_markdown(i));
            s.push('\n');
        }
    }
    s
}
