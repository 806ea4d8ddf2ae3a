//! Contact sheets: a titled grid of images with row and column captions, for galleries of
//! renders. The cells are copied in as bitmaps; plotters draws the captions and the crosses of
//! missing cells.

use super::{font, resample, text_scale, text_size, Figure, PlotError};
use crate::image_io::RgbImage;
use plotters::element::BitMapElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Grey shown in place of a missing image (half the linear intensity of white).
pub const MISSING: RGBColor = RGBColor(188, 188, 188);

/// Gap between cells and around the sheet, in pixels.
const GAP: u32 = 6;

/// `text` shortened with ".." so that it is at most `max_w` pixels wide in `style`.
fn fit(text: &str, max_w: u32, style: &TextStyle) -> Result<String, PlotError> {
    if text_size(text, style)?.0 <= max_w {
        return Ok(text.to_string());
    }
    let mut s = text.to_string();
    while !s.is_empty() && text_size(&format!("{s}.."), style)?.0 > max_w {
        s.pop();
    }
    Ok(format!("{s}.."))
}

/// Draws `cells` (rows × columns; `None` draws a grey cell with a cross) each resized to
/// `cell_w` × `cell_h`, with `row_labels` on the left, `col_labels` above and `title` on top.
/// Rows may have different lengths; the sheet is as wide as the longest row, or the title.
pub fn contact_sheet(
    cells: &[Vec<Option<RgbImage>>],
    row_labels: &[String],
    col_labels: &[String],
    title: &str,
    cell_w: u32,
    cell_h: u32,
) -> Result<Figure, PlotError> {
    let (cell_w, cell_h) = (cell_w.clamp(1, 4096), cell_h.clamp(1, 4096));
    let rows = cells.len() as u32;
    let cols = cells
        .iter()
        .map(Vec::len)
        .max()
        .unwrap_or(0)
        .max(col_labels.len()) as u32;
    let s = text_scale(cell_w * 2, cell_w * 2);
    let (caption, heading) = (font(13.0 * s), font(20.0 * s));
    let th = text_size("Ag", &caption)?.1 + 2;
    let mut label_w = 0;
    for l in row_labels {
        label_w = label_w.max(text_size(l, &caption)?.0);
    }
    let grid_left = GAP + if label_w > 0 { label_w + GAP } else { 0 };
    let (title_w, title_h) = match title {
        "" => (0, 0),
        t => {
            let (w, h) = text_size(t, &heading)?;
            (w + 2 * GAP, h + 2 * GAP)
        }
    };
    let col_h = if col_labels.iter().any(|l| !l.is_empty()) {
        th + GAP
    } else {
        0
    };
    let top = GAP + title_h + col_h;
    let grid_w = grid_left + cols * (cell_w + GAP);
    let width = grid_w.max(title_w);
    // Under a title wider than the grid, the grid and its captions are centred.
    let shift = (width - grid_w) / 2;
    let left = grid_left + shift;
    let height = top + rows * (cell_h + GAP);
    let mut fig = Figure::new(width, height);
    let root = fig.area();
    let centred = |style: &TextStyle<'static>| style.pos(Pos::new(HPos::Center, VPos::Top));
    root.draw_text(title, &centred(&heading), (width as i32 / 2, GAP as i32))?;
    let cell_x = |j: u32| (left + j * (cell_w + GAP)) as i32;
    let cell_y = |i: u32| (top + i * (cell_h + GAP)) as i32;
    for (j, label) in col_labels.iter().enumerate().take(cols as usize) {
        let x = cell_x(j as u32) + cell_w as i32 / 2;
        let text = fit(label, cell_w, &caption)?;
        root.draw_text(&text, &centred(&caption), (x, (GAP + title_h) as i32))?;
    }
    let beside = caption.pos(Pos::new(HPos::Left, VPos::Center));
    let cross = RGBColor(203, 203, 203);
    for i in 0..rows {
        let y = cell_y(i);
        if let Some(label) = row_labels.get(i as usize) {
            let x = (GAP + shift) as i32;
            root.draw_text(label, &beside, (x, y + cell_h as i32 / 2))?;
        }
        for j in 0..cols {
            let x = cell_x(j);
            let (x1, y1) = (x + cell_w as i32 - 1, y + cell_h as i32 - 1);
            match cells[i as usize].get(j as usize) {
                Some(Some(img)) => {
                    let px = resample(img, cell_w, cell_h);
                    if let Some(b) = BitMapElement::with_owned_buffer((x, y), (cell_w, cell_h), px)
                    {
                        root.draw(&b)?;
                    }
                }
                _ => {
                    root.draw(&Rectangle::new([(x, y), (x1, y1)], MISSING.filled()))?;
                    root.draw(&PathElement::new(vec![(x, y), (x1, y1)], cross))?;
                    root.draw(&PathElement::new(vec![(x, y1), (x1, y)], cross))?;
                }
            }
        }
    }
    root.present()?;
    drop(root);
    Ok(fig)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solid(w: usize, h: usize, c: [f32; 3]) -> RgbImage {
        RgbImage {
            width: w,
            height: h,
            data: vec![c; w * h],
        }
    }

    #[test]
    fn sheet_has_the_expected_size_and_cells_in_place() {
        let red = [1.0, 0.0, 0.0];
        let blue = [0.0, 0.0, 1.0];
        let cells = vec![
            vec![Some(solid(10, 10, red)), None, Some(solid(3, 7, blue))],
            vec![None, Some(solid(64, 64, blue))],
        ];
        let rows = vec!["d = 100 nm".to_string(), "d = 900 nm".to_string()];
        let cols: Vec<String> = ["0°", "30°", "a very long column label indeed"]
            .map(String::from)
            .into();
        let c = contact_sheet(&cells, &rows, &cols, "gallery", 80, 60).unwrap();
        let caption = font(13.0);
        let label_w = text_size("d = 100 nm", &caption).unwrap().0;
        let th = text_size("Ag", &caption).unwrap().1 + 2;
        let title_h = text_size("gallery", &font(20.0)).unwrap().1 + 2 * GAP;
        let left = GAP + label_w + GAP;
        let top = GAP + title_h + th + GAP;
        assert_eq!(c.width(), left + 3 * (80 + GAP));
        assert_eq!(c.height(), top + 2 * (60 + GAP));
        let at = |i: u32, j: u32| {
            c.pixel((left + j * 86 + 40) as i64, (top + i * 66 + 20) as i64)
                .unwrap()
        };
        let grey = [MISSING.0, MISSING.1, MISSING.2];
        assert_eq!(at(0, 0), [255, 0, 0]);
        assert_eq!(at(0, 2), [0, 0, 255]);
        assert_eq!(at(1, 1), [0, 0, 255]);
        assert_eq!(at(0, 1), grey);
        assert_eq!(at(1, 2), grey, "short rows are padded with missing cells");
        // Captions are drawn: dark pixels left of the first column and above the first row.
        let dark = |xs: std::ops::Range<u32>, ys: std::ops::Range<u32>| {
            ys.clone().any(|y| {
                xs.clone()
                    .any(|x| c.pixel(x as i64, y as i64).is_some_and(|p| p[0] < 100))
            })
        };
        assert!(dark(0..left - GAP, top..top + 60), "row caption");
        assert!(dark(left..left + 80, top - th - GAP..top), "column caption");
        let long = fit("a very long column label indeed", 80, &caption).unwrap();
        assert!(
            long.ends_with("..") && text_size(&long, &caption).unwrap().0 <= 80,
            "{long}"
        );
    }

    #[test]
    fn the_sheet_is_as_wide_as_its_title() {
        let cells = vec![vec![Some(solid(4, 4, [0.2; 3]))]];
        let title = "A title much wider than one small cell";
        let c = contact_sheet(&cells, &[], &[], title, 24, 24).unwrap();
        assert!(c.width() >= text_size(title, &font(20.0)).unwrap().0 + 2 * GAP);
        // The one cell is centred under it.
        let mid = c.width() as i64 / 2;
        assert_eq!(
            c.pixel(mid, c.height() as i64 - GAP as i64 - 12),
            Some([124; 3])
        );
    }

    #[test]
    fn empty_sheet_does_not_panic() {
        let c = contact_sheet(&[], &[], &[], "", 10, 10).unwrap();
        assert!(c.width() >= 1 && c.height() >= 1);
        let c = contact_sheet(&[vec![None]], &[], &["x".into()], "", 0, 0).unwrap();
        assert!(c.width() >= 1 && c.height() >= 1);
    }
}
