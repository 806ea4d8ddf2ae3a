//! The figures of the thesis and the CEIG 2023 paper as a gallery: which scenes, with which
//! `-D` parameters, in which grid; rendering them and composing labelled contact sheets
//! (`ophis gallery`).
//!
//! A [`Sheet`] is a grid: each row and each column may name a scene file (relative to the
//! `scenes/` folder) and `-D` values; a cell renders the row's scene (else the column's, else
//! the sheet's) with the sheet's, the column's and then the row's defines (later ones win).
//! Every cell is rendered with the same seed, so a sheet is reproducible.

use ophis::image_io::ImageError;
use ophis::scene::mitsuba::SceneError;
use ophis::tools::plot::{contact_sheet, Figure, PlotError};
use ophis::tools::preview::render_file;
use std::path::{Path, PathBuf};

/// What can go wrong while making a gallery.
#[derive(Debug, thiserror::Error)]
pub enum GalleryError {
    #[error("{0}")]
    Scene(#[from] SceneError),
    #[error("{0}")]
    Image(#[from] ImageError),
    #[error("{0}")]
    Plot(#[from] PlotError),
    #[error("{what}: {source}")]
    Io {
        what: String,
        source: std::io::Error,
    },
    #[error("no sheet is named '{0}' (see `ophis gallery --list`)")]
    UnknownSheet(String),
}

/// One row or column of a sheet: its caption, an optional scene and `-D` values.
#[derive(Clone, Debug)]
pub struct Axis {
    pub label: String,
    pub scene: Option<&'static str>,
    pub defines: Vec<(String, String)>,
}

/// A contact sheet: a titled grid of renders written to `NAME.png`.
#[derive(Clone, Debug)]
pub struct Sheet {
    /// File stem of the PNG.
    pub name: &'static str,
    pub title: &'static str,
    /// Scene used when neither the row nor the column names one.
    pub scene: Option<&'static str>,
    /// Defines applied to every cell (first, so rows and columns override them).
    pub defines: Vec<(String, String)>,
    pub rows: Vec<Axis>,
    pub cols: Vec<Axis>,
}

impl Sheet {
    /// The scene and defines of cell (`r`, `c`).
    pub fn cell(&self, r: usize, c: usize) -> (&'static str, Vec<(String, String)>) {
        let (row, col) = (&self.rows[r], &self.cols[c]);
        let scene = row
            .scene
            .or(col.scene)
            .or(self.scene)
            .expect("every gallery cell has a scene");
        let mut defs = self.defines.clone();
        defs.extend(col.defines.iter().cloned());
        defs.extend(row.defines.iter().cloned());
        (scene, defs)
    }
}

fn defs(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
    pairs
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

fn axis(label: &str, scene: Option<&'static str>, pairs: &[(&str, &str)]) -> Axis {
    Axis {
        label: label.to_string(),
        scene,
        defines: defs(pairs),
    }
}

/// One axis per value of the define `key`, captioned by `label`.
fn sweep(key: &str, values: &[&str], label: impl Fn(&str) -> String) -> Vec<Axis> {
    values
        .iter()
        .map(|v| axis(&label(v), None, &[(key, v)]))
        .collect()
}

/// One axis per shape the figure scenes offer (`-Dshape=…`).
fn shapes(names: &[&str]) -> Vec<Axis> {
    sweep("shape", names, str::to_string)
}

/// A sheet of thesis fig 4.8: the three-layer scene on a sphere and a torus, across `cols`.
fn fig_4_8(name: &'static str, title: &'static str, cols: Vec<Axis>) -> Sheet {
    Sheet {
        name,
        title,
        scene: Some("thesis/fig4-6-skin.xml"),
        defines: vec![],
        rows: shapes(&["sphere", "torus"]),
        cols,
    }
}

/// Every sheet of the gallery, in the order `ophis gallery` renders them.
pub fn sheets() -> Vec<Sheet> {
    let stages = [
        ("4.1 diffuse", "thesis/fig4-1-diffuse.xml"),
        ("4.2 bump", "thesis/fig4-2-bump.xml"),
        ("4.3 film", "thesis/fig4-3-film.xml"),
        ("4.4 film+bump", "thesis/fig4-4-film-bump.xml"),
        ("4.5 absorption", "thesis/fig4-5-absorption.xml"),
        ("4.6 3 layers", "thesis/fig4-6-skin.xml"),
        ("4.7 +bump", "thesis/fig4-7-skin-bump.xml"),
    ];
    let thickness = ["300", "500", "700", "900", "1100"];
    let iors = ["1.3", "1.45", "1.56", "1.7", "1.9"];
    let nm = |d: &str| format!("{d} nm");
    // Each of two shapes rendered spectrally and in the thesis's three-wavelength mode.
    let modes = ["sphere", "snake"].iter().flat_map(|s| {
        ["spectral", "thesis"]
            .map(|m| axis(&format!("{s} {m}"), None, &[("shape", s), ("mode", m)]))
    });
    let all_shapes = ["sphere", "torus", "snake"];
    vec![
        Sheet {
            name: "thesis-4.1-4.7",
            title: "Thesis 4.1-4.7, stage by stage",
            scene: None,
            defines: vec![],
            rows: stages.iter().map(|(l, s)| axis(l, Some(s), &[])).collect(),
            cols: shapes(&all_shapes),
        },
        fig_4_8(
            "thesis-4.8-thickness",
            "Thesis fig 4.8: film thickness (3 layers, n1 1.56)",
            sweep("thickness", &thickness, nm),
        ),
        fig_4_8(
            "thesis-4.8-ior",
            "Thesis fig 4.8: film index (3 layers, 900 nm)",
            sweep("film_ior", &iors, |n| format!("n1 {n}")),
        ),
        Sheet {
            name: "spectral-vs-thesis",
            title: "Spectral (exact) vs thesis mode (650/510/475 nm)",
            scene: None,
            defines: vec![],
            rows: vec![
                axis("4.3 film", Some("thesis/fig4-3-film.xml"), &[]),
                axis("4.4 film+bump", Some("thesis/fig4-4-film-bump.xml"), &[]),
                axis("4.6 3 layers", Some("thesis/fig4-6-skin.xml"), &[]),
            ],
            cols: modes.collect(),
        },
        Sheet {
            name: "ceig2023-fig5",
            title: "CEIG 2023 fig 5: thickness x inner index",
            scene: Some("ceig2023/fig5-range.xml"),
            defines: vec![],
            rows: sweep("int_ior", &["1.0", "2.0"], |n| format!("n2 {n}")),
            cols: sweep("thickness", &["300", "600", "1200"], nm),
        },
        Sheet {
            name: "ceig2023-fig6",
            title: "CEIG 2023 fig 6: ablation",
            scene: Some("ceig2023/fig6-ablation.xml"),
            defines: vec![],
            rows: [
                ("diffuse", "diffuse"),
                ("+bump", "bump"),
                ("film+bump", "film-bump"),
                ("multilayer", "skin-bump"),
            ]
            .iter()
            .map(|(l, s)| axis(l, None, &[("stage", s)]))
            .collect(),
            cols: shapes(&all_shapes),
        },
    ]
}

/// How big and how clean the renders are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quality {
    /// Width and height of each render (the figure scenes are square).
    pub res: u32,
    pub spp: u32,
    /// Size of each cell on the sheet (renders are resampled to it).
    pub cell: u32,
}

impl Quality {
    /// The committed gallery: a few minutes on two cores.
    pub const PREVIEW: Quality = Quality {
        res: 128,
        spp: 32,
        cell: 128,
    };
    /// CI size: seconds for the whole gallery.
    pub const QUICK: Quality = Quality {
        res: 8,
        spp: 1,
        cell: 24,
    };
}

/// The `scenes/` folder: `./scenes` when it holds the figures, else the one of the source tree
/// ophis was built from.
pub fn default_scenes_dir() -> PathBuf {
    let here = PathBuf::from("scenes");
    if here.join("thesis").is_dir() {
        return here;
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// Renders every cell of `sheet` and composes it; `log` receives one line per cell.
pub fn render_sheet(
    sheet: &Sheet,
    scenes: &Path,
    q: Quality,
    log: &mut dyn FnMut(&str),
) -> Result<Figure, GalleryError> {
    let n = sheet.rows.len() * sheet.cols.len();
    let mut cells = Vec::with_capacity(sheet.rows.len());
    for r in 0..sheet.rows.len() {
        let mut row = Vec::with_capacity(sheet.cols.len());
        for c in 0..sheet.cols.len() {
            let (scene, defines) = sheet.cell(r, c);
            let t = std::time::Instant::now();
            let (img, warnings) =
                render_file(&scenes.join(scene), &defines, (q.res, q.res), q.spp)?;
            for w in warnings {
                log(&format!("  warning: {w}"));
            }
            let shown: Vec<String> = defines.iter().map(|(k, v)| format!("{k}={v}")).collect();
            log(&format!(
                "  [{}/{n}] {scene} {} ({:.1} s)",
                r * sheet.cols.len() + c + 1,
                shown.join(" "),
                t.elapsed().as_secs_f64()
            ));
            row.push(Some(img));
        }
        cells.push(row);
    }
    let rl: Vec<String> = sheet.rows.iter().map(|a| a.label.clone()).collect();
    let cl: Vec<String> = sheet.cols.iter().map(|a| a.label.clone()).collect();
    Ok(contact_sheet(
        &cells,
        &rl,
        &cl,
        sheet.title,
        q.cell,
        q.cell,
    )?)
}

/// Renders the sheets named in `only` (all when empty) into `out/NAME.png`; returns the paths.
pub fn make_gallery(
    scenes: &Path,
    out: &Path,
    q: Quality,
    only: &[String],
    log: &mut dyn FnMut(&str),
) -> Result<Vec<PathBuf>, GalleryError> {
    let all = sheets();
    for o in only {
        if !all.iter().any(|s| s.name == o) {
            return Err(GalleryError::UnknownSheet(o.clone()));
        }
    }
    std::fs::create_dir_all(out).map_err(|source| GalleryError::Io {
        what: format!("cannot create {}", out.display()),
        source,
    })?;
    let chosen: Vec<&Sheet> = all
        .iter()
        .filter(|s| only.is_empty() || only.iter().any(|o| o == s.name))
        .collect();
    let mut written = Vec::new();
    for (i, sheet) in chosen.iter().enumerate() {
        let t = std::time::Instant::now();
        log(&format!(
            "[{}/{}] {}: {} ({} x {} renders, {}x{} px, {} spp)",
            i + 1,
            chosen.len(),
            sheet.name,
            sheet.title,
            sheet.rows.len(),
            sheet.cols.len(),
            q.res,
            q.res,
            q.spp
        ));
        let canvas = render_sheet(sheet, scenes, q, log)?;
        let path = out.join(format!("{}.png", sheet.name));
        canvas.save_png(&path)?;
        log(&format!(
            "  wrote {} in {:.1} s",
            path.display(),
            t.elapsed().as_secs_f64()
        ));
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_cell_names_an_existing_scene() {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes");
        for s in sheets() {
            for r in 0..s.rows.len() {
                for c in 0..s.cols.len() {
                    let (scene, _) = s.cell(r, c);
                    assert!(dir.join(scene).is_file(), "{}: {scene}", s.name);
                }
            }
        }
    }

    #[test]
    fn rows_override_columns_and_the_sheet() {
        let s = Sheet {
            name: "t",
            title: "t",
            scene: Some("a.xml"),
            defines: defs(&[("x", "0")]),
            rows: vec![axis("r", Some("b.xml"), &[("x", "2")])],
            cols: vec![axis("c", None, &[("x", "1"), ("y", "1")])],
        };
        let (scene, d) = s.cell(0, 0);
        assert_eq!(scene, "b.xml");
        // Later defines win when the loader applies them in order.
        assert_eq!(d.last().unwrap(), &("x".to_string(), "2".to_string()));
        assert!(d.contains(&("y".to_string(), "1".to_string())));
    }
}
