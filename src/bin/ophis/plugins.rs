//! `ophis plugins [NAME]`: the plugins ophis knows and their parameters, from the same
//! declarations the scene loader reads through.

use anyhow::{bail, Result};
use clap::Parser;
use ophis::plugin::{manual, registry};

/// Arguments of `ophis plugins`.
#[derive(Parser)]
pub struct PluginsArgs {
    /// A plugin name (or alias): print its parameters. Without one, list every plugin.
    name: Option<String>,
    /// Print Markdown: the whole reference (as in docs/plugins.md), or one plugin's manual.
    #[arg(long)]
    markdown: bool,
}

/// Runs `ophis plugins`.
pub fn run(args: PluginsArgs) -> Result<()> {
    let Some(name) = args.name else {
        if args.markdown {
            print!("{}", manual::reference_markdown());
        } else {
            for i in registry::all() {
                let aliases = if i.aliases.is_empty() {
                    String::new()
                } else {
                    format!(" (also {})", i.aliases.join(", "))
                };
                println!(
                    "{:<10} {:<24} {}{aliases}",
                    i.tag.as_str(),
                    i.name,
                    i.summary
                );
            }
        }
        return Ok(());
    };
    let found = registry::find(&name);
    if found.is_empty() {
        let names = registry::all().into_iter().map(|i| i.name);
        bail!(
            "no plugin is called '{name}'{}; `ophis plugins` lists them",
            ophis::plugin::did_you_mean(&name, names)
        );
    }
    for i in found {
        if args.markdown {
            println!("{}", manual::plugin_markdown(i));
            continue;
        }
        println!("{} '{}': {}", i.tag, i.name, i.summary);
        if !i.aliases.is_empty() {
            println!("  also loads as: {}", i.aliases.join(", "));
        }
        println!("  source: {}", i.file);
        for p in i.all_params() {
            let mut names = p.name.to_string();
            for a in p.also {
                names.push_str(&format!(" | {a}"));
            }
            if !p.v06.is_empty() {
                names.push_str(&format!(" (0.6: {})", p.v06));
            }
            let unit = if p.unit.is_empty() {
                String::new()
            } else {
                format!(" [{}]", p.unit)
            };
            let check = p
                .check
                .describe()
                .map(|c| format!("; {c}"))
                .unwrap_or_default();
            println!(
                "  {names:<28} {:<20} default {}{unit}  {}{check}",
                p.ty.describe(),
                p.default.describe().replace('`', ""),
                p.doc.replace('`', "")
            );
        }
    }
    Ok(())
}
