//! A raster canvas for figures: rectangles, anti-aliased lines and circles, bitmap text (horizontal
//! and rotated), and image blits. Pixel (i, j) is centred on the point (i, j); colours are linear
//! RGB like `RgbImage`. Everything clips at the borders: any coordinates, however large, negative or
//! NaN, are safe to draw with.

use super::font::{glyph, ADVANCE, GLYPH_H, GLYPH_W};
use crate::image_io::{write_png, ImageError, RgbImage};
use std::path::Path;

/// An image being drawn on.
#[derive(Clone, Debug)]
pub struct Canvas {
    pub image: RgbImage,
}

/// Clips the segment (x0, y0)–(x1, y1) to the rectangle [xmin, xmax] × [ymin, ymax]
/// (Liang–Barsky); `None` when nothing of it lies inside or a coordinate is not finite.
pub fn clip_segment(
    (x0, y0): (f64, f64),
    (x1, y1): (f64, f64),
    (xmin, ymin, xmax, ymax): (f64, f64, f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    if ![x0, y0, x1, y1].iter().all(|v| v.is_finite()) {
        return None;
    }
    let (dx, dy) = (x1 - x0, y1 - y0);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, x0 - xmin),
        (dx, xmax - x0),
        (-dy, y0 - ymin),
        (dy, ymax - y0),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some(((x0 + t0 * dx, y0 + t0 * dy), (x0 + t1 * dx, y0 + t1 * dy)))
}

impl Canvas {
    /// A `width` × `height` canvas filled with `background`.
    pub fn new(width: u32, height: u32, background: [f32; 3]) -> Canvas {
        let mut image = RgbImage::new(width as usize, height as usize);
        image.data.fill(background);
        Canvas { image }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.image.width as u32
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.image.height as u32
    }

    /// The colour at (x, y), or `None` outside the canvas.
    pub fn get(&self, x: i64, y: i64) -> Option<[f32; 3]> {
        self.index(x, y).map(|i| self.image.data[i])
    }

    fn index(&self, x: i64, y: i64) -> Option<usize> {
        let (w, h) = (self.image.width as i64, self.image.height as i64);
        (x >= 0 && y >= 0 && x < w && y < h).then(|| (y * w + x) as usize)
    }

    /// Sets one pixel; outside the canvas it does nothing.
    pub fn set(&mut self, x: i64, y: i64, c: [f32; 3]) {
        if let Some(i) = self.index(x, y) {
            self.image.data[i] = c;
        }
    }

    /// Mixes `c` into one pixel with coverage `a` in [0, 1].
    fn blend(&mut self, x: i64, y: i64, c: [f32; 3], a: f32) {
        if let Some(i) = self.index(x, y) {
            let p = &mut self.image.data[i];
            for k in 0..3 {
                p[k] += (c[k] - p[k]) * a;
            }
        }
    }

    /// Fills the `w` × `h` rectangle whose top-left pixel is (x, y).
    pub fn fill_rect(&mut self, x: i64, y: i64, w: i64, h: i64, c: [f32; 3]) {
        let x0 = x.clamp(0, self.image.width as i64);
        let y0 = y.clamp(0, self.image.height as i64);
        let x1 = x.saturating_add(w.max(0)).clamp(0, self.image.width as i64);
        let y1 = y
            .saturating_add(h.max(0))
            .clamp(0, self.image.height as i64);
        for yy in y0..y1 {
            let row = yy as usize * self.image.width;
            self.image.data[row + x0 as usize..row + x1 as usize].fill(c);
        }
    }

    /// Outlines the `w` × `h` rectangle whose top-left pixel is (x, y), one pixel thick.
    pub fn rect(&mut self, x: i64, y: i64, w: i64, h: i64, c: [f32; 3]) {
        if w <= 0 || h <= 0 {
            return;
        }
        self.fill_rect(x, y, w, 1, c);
        self.fill_rect(x, y.saturating_add(h - 1), w, 1, c);
        self.fill_rect(x, y, 1, h, c);
        self.fill_rect(x.saturating_add(w - 1), y, 1, h, c);
    }

    /// An anti-aliased line of the given width (in pixels) with round ends.
    pub fn line(&mut self, x0: f32, y0: f32, x1: f32, y1: f32, c: [f32; 3], width: f32) {
        let r = (width.max(0.0) * 0.5) as f64;
        // Clip first, so that far-away endpoints cost nothing and keep f32 precision.
        let pad = r + 2.0;
        let bounds = (
            -pad,
            -pad,
            self.image.width as f64 + pad,
            self.image.height as f64 + pad,
        );
        let Some(((ax, ay), (bx, by))) =
            clip_segment((x0 as f64, y0 as f64), (x1 as f64, y1 as f64), bounds)
        else {
            return;
        };
        let xmin = (ax.min(bx) - r - 1.0).floor() as i64;
        let xmax = (ax.max(bx) + r + 1.0).ceil() as i64;
        let ymin = (ay.min(by) - r - 1.0).floor() as i64;
        let ymax = (ay.max(by) + r + 1.0).ceil() as i64;
        let (dx, dy) = (bx - ax, by - ay);
        let len2 = dx * dx + dy * dy;
        for y in ymin.max(0)..=ymax.min(self.image.height as i64 - 1) {
            for x in xmin.max(0)..=xmax.min(self.image.width as i64 - 1) {
                let (px, py) = (x as f64 - ax, y as f64 - ay);
                let t = if len2 > 0.0 {
                    ((px * dx + py * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = ((px - t * dx).powi(2) + (py - t * dy).powi(2)).sqrt();
                // Coverage of a unit pixel by a band of half-width r, approximated by a linear ramp.
                let a = (r + 0.5 - d).clamp(0.0, 1.0) as f32;
                if a > 0.0 {
                    self.blend(x, y, c, a);
                }
            }
        }
    }

    /// Connected line segments through `points`.
    pub fn polyline(&mut self, points: &[(f32, f32)], c: [f32; 3], width: f32) {
        for w in points.windows(2) {
            self.line(w[0].0, w[0].1, w[1].0, w[1].1, c, width);
        }
        if points.len() == 1 {
            self.line(points[0].0, points[0].1, points[0].0, points[0].1, c, width);
        }
    }

    /// An anti-aliased circle outline of radius `r`, one pixel thick.
    pub fn circle(&mut self, cx: f32, cy: f32, r: f32, c: [f32; 3]) {
        self.ring(cx, cy, r, c, 1.0, false);
    }

    /// An anti-aliased filled disc of radius `r`.
    pub fn disc(&mut self, cx: f32, cy: f32, r: f32, c: [f32; 3]) {
        self.ring(cx, cy, r, c, 1.0, true);
    }

    fn ring(&mut self, cx: f32, cy: f32, r: f32, c: [f32; 3], width: f32, filled: bool) {
        let (cx, cy, r) = (cx as f64, cy as f64, r.max(0.0) as f64);
        let (w, h) = (self.image.width as f64, self.image.height as f64);
        if !(cx.is_finite() && cy.is_finite() && r.is_finite()) {
            return;
        }
        let ext = r + width as f64 + 1.0;
        let x0 = (cx - ext).floor().max(0.0);
        let x1 = (cx + ext).ceil().min(w - 1.0);
        let y0 = (cy - ext).floor().max(0.0);
        let y1 = (cy + ext).ceil().min(h - 1.0);
        if x0 > x1 || y0 > y1 {
            return;
        }
        let half = width as f64 * 0.5;
        for y in y0 as i64..=y1 as i64 {
            for x in x0 as i64..=x1 as i64 {
                let d = ((x as f64 - cx).powi(2) + (y as f64 - cy).powi(2)).sqrt();
                let dist = if filled {
                    (d - r).max(0.0)
                } else {
                    (d - r).abs()
                };
                let reach = if filled { 0.5 } else { half + 0.5 };
                let a = (reach - dist).clamp(0.0, 1.0) as f32;
                if a > 0.0 {
                    self.blend(x, y, c, a);
                }
            }
        }
    }

    /// Width in pixels of `s` drawn at `scale` (no trailing spacing).
    pub fn text_width(s: &str, scale: u32) -> u32 {
        let n = s.chars().count() as u32;
        if n == 0 {
            0
        } else {
            (n * ADVANCE - 1) * scale
        }
    }

    /// Height in pixels of a line of text at `scale`, descenders included.
    pub fn text_height(scale: u32) -> u32 {
        GLYPH_H * scale
    }

    /// Draws `s` with its top-left corner at (x, y); returns the width drawn.
    pub fn text(&mut self, x: i64, y: i64, s: &str, c: [f32; 3], scale: u32) -> u32 {
        let sc = scale as i64;
        for (i, ch) in s.chars().enumerate() {
            let gx = x.saturating_add(i as i64 * ADVANCE as i64 * sc);
            if gx >= self.image.width as i64 {
                break;
            }
            for (row, bits) in glyph(ch).iter().enumerate() {
                for col in 0..GLYPH_W {
                    if bits & (1 << (GLYPH_W - 1 - col)) != 0 {
                        let px = gx.saturating_add(col as i64 * sc);
                        let py = y.saturating_add(row as i64 * sc);
                        self.fill_rect(px, py, sc, sc, c);
                    }
                }
            }
        }
        Canvas::text_width(s, scale)
    }

    /// Draws `s` horizontally centred on `cx`, top at `y`; returns the width drawn.
    pub fn text_centered(&mut self, cx: i64, y: i64, s: &str, c: [f32; 3], scale: u32) -> u32 {
        let w = Canvas::text_width(s, scale) as i64;
        self.text(cx.saturating_sub(w / 2), y, s, c, scale)
    }

    /// Draws `s` right-aligned so that it ends at `right`, top at `y`.
    pub fn text_right(&mut self, right: i64, y: i64, s: &str, c: [f32; 3], scale: u32) -> u32 {
        let w = Canvas::text_width(s, scale) as i64;
        self.text(right.saturating_sub(w), y, s, c, scale)
    }

    /// Draws `s` rotated 90° anticlockwise (reading upwards, as a y-axis label), in the box whose
    /// top-left corner is (x, y): the box is `text_height` wide and `text_width` tall.
    pub fn text_vertical(&mut self, x: i64, y: i64, s: &str, c: [f32; 3], scale: u32) -> u32 {
        let sc = scale as i64;
        let total = Canvas::text_width(s, scale) as i64;
        for (i, ch) in s.chars().enumerate() {
            let u0 = i as i64 * ADVANCE as i64 * sc;
            for (row, bits) in glyph(ch).iter().enumerate() {
                for col in 0..GLYPH_W as i64 {
                    if bits & (1 << (GLYPH_W as i64 - 1 - col)) != 0 {
                        // Along the text (u) runs upwards, down the glyph (v) runs right.
                        let u = u0 + col * sc;
                        let px = x.saturating_add(row as i64 * sc);
                        let py = y.saturating_add(total - u - sc);
                        self.fill_rect(px, py, sc, sc, c);
                    }
                }
            }
        }
        total as u32
    }

    /// Draws `s` rotated as in `text_vertical`, centred vertically on `cy`, left edge at `x`.
    pub fn text_vertical_centered(&mut self, x: i64, cy: i64, s: &str, c: [f32; 3], scale: u32) {
        let h = Canvas::text_width(s, scale) as i64;
        self.text_vertical(x, cy.saturating_sub(h / 2), s, c, scale);
    }

    /// Copies `src` with its top-left pixel at (x, y).
    pub fn blit(&mut self, src: &RgbImage, x: i64, y: i64) {
        for sy in 0..src.height {
            for sx in 0..src.width {
                let (dx, dy) = (x.saturating_add(sx as i64), y.saturating_add(sy as i64));
                self.set(dx, dy, src.data[sy * src.width + sx]);
            }
        }
    }

    /// Draws `src` resized to `w` × `h` at (x, y): each target pixel averages the source pixels
    /// under it (a box filter), which is nearest-neighbour when enlarging.
    pub fn blit_scaled(&mut self, src: &RgbImage, x: i64, y: i64, w: u32, h: u32) {
        if src.width == 0 || src.height == 0 || w == 0 || h == 0 {
            return;
        }
        let (sw, sh) = (src.width as u64, src.height as u64);
        let ty0 = y.max(0) - y;
        let ty1 = (h as i64).min(self.image.height as i64 - y);
        let tx0 = x.max(0) - x;
        let tx1 = (w as i64).min(self.image.width as i64 - x);
        for ty in ty0..ty1 {
            let sy0 = ty as u64 * sh / h as u64;
            let sy1 = ((ty as u64 + 1) * sh).div_ceil(h as u64).max(sy0 + 1);
            for tx in tx0..tx1 {
                let sx0 = tx as u64 * sw / w as u64;
                let sx1 = ((tx as u64 + 1) * sw).div_ceil(w as u64).max(sx0 + 1);
                let mut acc = [0.0f32; 3];
                for sy in sy0..sy1 {
                    for sx in sx0..sx1 {
                        let p = src.data[(sy * sw + sx) as usize];
                        for k in 0..3 {
                            acc[k] += p[k];
                        }
                    }
                }
                let n = ((sy1 - sy0) * (sx1 - sx0)) as f32;
                self.set(x + tx, y + ty, acc.map(|v| v / n));
            }
        }
    }

    /// Writes the canvas as an 8-bit sRGB PNG.
    pub fn save_png(&self, path: impl AsRef<Path>) -> Result<(), ImageError> {
        write_png(path, &self.image)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WHITE: [f32; 3] = [1.0; 3];
    const BLACK: [f32; 3] = [0.0; 3];

    fn ink(c: &Canvas) -> Vec<(i64, i64)> {
        let mut v = Vec::new();
        for y in 0..c.height() as i64 {
            for x in 0..c.width() as i64 {
                if c.get(x, y) != Some(WHITE) {
                    v.push((x, y));
                }
            }
        }
        v
    }

    #[test]
    fn text_sets_pixels_within_its_reported_width() {
        let mut c = Canvas::new(200, 40, WHITE);
        let w = c.text(10, 5, "Hi λ=5", BLACK, 2);
        assert_eq!(w, Canvas::text_width("Hi λ=5", 2));
        assert_eq!(w, (6 * 6 - 1) * 2);
        let pts = ink(&c);
        assert!(pts.len() > 50);
        let maxx = pts.iter().map(|p| p.0).max().unwrap();
        let minx = pts.iter().map(|p| p.0).min().unwrap();
        assert_eq!(minx, 10, "H starts at the left edge of its cell");
        assert!(maxx < 10 + w as i64 && maxx > 10 + w as i64 - 12);
        // 'H' at scale 2: the top-left 2×2 block is ink, the gap between its legs is not.
        assert_eq!(c.get(10, 5), Some(BLACK));
        assert_eq!(c.get(11, 6), Some(BLACK));
        assert_eq!(c.get(14, 5), Some(WHITE));
        assert_eq!(Canvas::text_width("", 3), 0);
    }

    #[test]
    fn vertical_text_is_the_horizontal_text_rotated() {
        let s = "Ab°";
        let (tw, th) = (
            Canvas::text_width(s, 1) as i64,
            Canvas::text_height(1) as i64,
        );
        let mut h = Canvas::new(tw as u32, th as u32, WHITE);
        h.text(0, 0, s, BLACK, 1);
        let mut v = Canvas::new(th as u32, tw as u32, WHITE);
        v.text_vertical(0, 0, s, BLACK, 1);
        for y in 0..th {
            for x in 0..tw {
                assert_eq!(h.get(x, y), v.get(y, tw - 1 - x), "at {x},{y}");
            }
        }
    }

    #[test]
    fn drawing_far_outside_never_panics() {
        let mut c = Canvas::new(50, 30, WHITE);
        let far = [-1e6f32, -1.0, 0.0, 49.0, 50.0, 1e6, f32::NAN, f32::INFINITY];
        for &a in &far {
            for &b in &far {
                c.line(a, b, -a, 15.0, BLACK, 3.0);
                c.circle(a, b, 1e6, BLACK);
                c.disc(a, b, 5.0, BLACK);
                c.text(a as i64, b as i64, "far away", BLACK, 3);
                c.text_vertical(a as i64, b as i64, "far", BLACK, 2);
                c.text_centered(i64::MAX, i64::MIN, "x", BLACK, 1);
                c.fill_rect(a as i64, b as i64, i64::MAX, i64::MAX, BLACK);
                c.rect(i64::MIN, i64::MIN, i64::MAX, 5, BLACK);
                let img = RgbImage::new(4, 4);
                c.blit(&img, a as i64, b as i64);
                c.blit_scaled(&img, a as i64, b as i64, 100, 7);
            }
        }
        c.polyline(&[(-1e6, -1e6), (1e6, 1e6), (f32::NAN, 0.0)], BLACK, 1.0);
    }

    #[test]
    fn line_hits_its_pixels_and_spares_others() {
        let mut c = Canvas::new(40, 40, WHITE);
        c.line(5.0, 20.0, 35.0, 20.0, BLACK, 1.0);
        assert_eq!(c.get(20, 20), Some(BLACK));
        assert_eq!(c.get(20, 22), Some(WHITE));
        assert_eq!(c.get(38, 20), Some(WHITE));
        // A diagonal crossing the whole canvas from far away still passes through the middle.
        let mut d = Canvas::new(40, 40, WHITE);
        d.line(-1e6, -1e6, 1e6, 1e6, BLACK, 2.0);
        assert_eq!(d.get(17, 17), Some(BLACK));
        assert_eq!(d.get(30, 10), Some(WHITE));
    }

    #[test]
    fn circle_outline_leaves_the_centre_empty() {
        let mut c = Canvas::new(40, 40, WHITE);
        c.circle(20.0, 20.0, 10.0, BLACK);
        assert_eq!(c.get(30, 20), Some(BLACK));
        assert_eq!(c.get(20, 10), Some(BLACK));
        assert_eq!(c.get(20, 20), Some(WHITE));
    }

    #[test]
    fn blit_scaled_averages_when_shrinking() {
        let mut src = RgbImage::new(4, 2);
        for (i, p) in src.data.iter_mut().enumerate() {
            *p = if i % 2 == 0 { [1.0; 3] } else { [0.0; 3] };
        }
        let mut c = Canvas::new(4, 4, [0.5, 0.0, 0.0]);
        c.blit_scaled(&src, 1, 1, 2, 1);
        assert_eq!(c.get(1, 1), Some([0.5; 3]));
        assert_eq!(c.get(0, 1), Some([0.5, 0.0, 0.0]));
        c.blit_scaled(&src, 0, 0, 8, 4); // enlarged: nearest
        assert_eq!(c.get(0, 0), Some([1.0; 3]));
        assert_eq!(c.get(2, 0), Some([0.0; 3]));
    }
}

#[cfg(test)]
mod sample {
    use super::*;

    /// Writes the whole font to a PNG in the temporary directory, for a person to look at.
    #[test]
    fn font_sample_png() {
        let mut c = Canvas::new(620, 150, [1.0; 3]);
        let ascii: String = (32u8..=126).map(|b| b as char).collect();
        for (i, chunk) in ascii.as_bytes().chunks(48).enumerate() {
            c.text(
                4,
                4 + i as i64 * 24,
                std::str::from_utf8(chunk).unwrap(),
                [0.0; 3],
                2,
            );
        }
        c.text(4, 52, "°λθφσαμ µηΔ×±·²−– €", [0.0; 3], 2);
        c.text(
            4,
            80,
            "Reflectance at 45°, λ = 550 nm (d = 300 nm)",
            [0.1, 0.2, 0.6],
            1,
        );
        c.text_vertical(600, 4, "vertical θ (°)", [0.0; 3], 1);
        c.line(4.0, 100.0, 300.0, 140.0, [0.8, 0.1, 0.1], 2.0);
        c.circle(400.0, 115.0, 25.0, [0.1, 0.5, 0.1]);
        let path = std::env::temp_dir().join("ophis_plot_font.png");
        c.save_png(&path).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 100);
    }
}
