//! Contact sheets: a titled grid of images with row and column labels, for galleries of renders.

use super::canvas::Canvas;
use super::chart::{text_scale, BLACK, WHITE};
use crate::image_io::RgbImage;

/// Grey shown in place of a missing image.
pub const MISSING: [f32; 3] = [0.5; 3];

/// Gap between cells and around the sheet, in pixels.
const GAP: u32 = 6;

/// `text` shortened with ".." so that it is at most `max_w` pixels wide at `scale`.
fn fit(text: &str, max_w: u32, scale: u32) -> String {
    if Canvas::text_width(text, scale) <= max_w {
        return text.to_string();
    }
    let mut s: String = text.to_string();
    while !s.is_empty() && Canvas::text_width(&format!("{s}.."), scale) > max_w {
        s.pop();
    }
    format!("{s}..")
}

/// Draws `cells` (rows × columns; `None` draws a grey cell with a cross) each resized to
/// `cell_w` × `cell_h`, with `row_labels` on the left, `col_labels` above and `title` on top.
/// Rows may have different lengths; the sheet is as wide as the longest.
pub fn contact_sheet(
    cells: &[Vec<Option<RgbImage>>],
    row_labels: &[String],
    col_labels: &[String],
    title: &str,
    cell_w: u32,
    cell_h: u32,
) -> Canvas {
    let rows = cells.len() as u32;
    let cols = cells
        .iter()
        .map(Vec::len)
        .max()
        .unwrap_or(0)
        .max(col_labels.len()) as u32;
    let s = text_scale(cell_w * 2, cell_w * 2);
    let th = Canvas::text_height(s);
    let label_w = row_labels
        .iter()
        .map(|l| Canvas::text_width(l, s))
        .max()
        .unwrap_or(0);
    let left = GAP + if label_w > 0 { label_w + GAP } else { 0 };
    let title_h = if title.is_empty() { 0 } else { 2 * th + GAP };
    let col_h = if col_labels.iter().any(|l| !l.is_empty()) {
        th + GAP
    } else {
        0
    };
    let top = GAP + title_h + col_h;
    let width = left + cols * (cell_w + GAP);
    let height = top + rows * (cell_h + GAP);
    let mut c = Canvas::new(width.max(1), height.max(1), WHITE);
    c.text_centered(width as i64 / 2, GAP as i64, title, BLACK, 2 * s);
    let cell_x = |j: u32| (left + j * (cell_w + GAP)) as i64;
    let cell_y = |i: u32| (top + i * (cell_h + GAP)) as i64;
    for (j, label) in col_labels.iter().enumerate().take(cols as usize) {
        let x = cell_x(j as u32) + cell_w as i64 / 2;
        c.text_centered(x, (GAP + title_h) as i64, &fit(label, cell_w, s), BLACK, s);
    }
    for i in 0..rows {
        let y = cell_y(i);
        if let Some(label) = row_labels.get(i as usize) {
            c.text(
                GAP as i64,
                y + (cell_h as i64 - th as i64) / 2,
                label,
                BLACK,
                s,
            );
        }
        for j in 0..cols {
            let x = cell_x(j);
            match cells[i as usize].get(j as usize) {
                Some(Some(img)) => c.blit_scaled(img, x, y, cell_w, cell_h),
                _ => {
                    c.fill_rect(x, y, cell_w as i64, cell_h as i64, MISSING);
                    let (x1, y1) = (
                        (x + cell_w as i64 - 1) as f32,
                        (y + cell_h as i64 - 1) as f32,
                    );
                    c.line(x as f32, y as f32, x1, y1, [0.6; 3], 1.0);
                    c.line(x as f32, y1, x1, y as f32, [0.6; 3], 1.0);
                }
            }
        }
    }
    c
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
        let c = contact_sheet(&cells, &rows, &cols, "gallery", 80, 60);
        let label_w = Canvas::text_width("d = 100 nm", 1);
        let th = Canvas::text_height(1);
        let left = GAP + label_w + GAP;
        let top = GAP + 2 * th + GAP + th + GAP;
        assert_eq!(c.width(), left + 3 * (80 + GAP));
        assert_eq!(c.height(), top + 2 * (60 + GAP));
        let at = |i: u32, j: u32| {
            c.get((left + j * 86 + 40) as i64, (top + i * 66 + 20) as i64)
                .unwrap()
        };
        assert_eq!(at(0, 0), red);
        assert_eq!(at(0, 2), blue);
        assert_eq!(at(1, 1), blue);
        assert_eq!(at(0, 1), MISSING);
        c.save_png(std::env::temp_dir().join("ophis_plot_sheet.png"))
            .unwrap();
        assert_eq!(
            at(1, 2),
            MISSING,
            "short rows are padded with missing cells"
        );
        assert_eq!(
            fit("a very long column label indeed", 80, 1)
                .chars()
                .count(),
            13
        );
    }

    #[test]
    fn empty_sheet_does_not_panic() {
        let c = contact_sheet(&[], &[], &[], "", 10, 10);
        assert!(c.width() >= 1 && c.height() >= 1);
    }
}
