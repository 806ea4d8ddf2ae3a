//! Colour maps: an image (already in colour) stretched over a chart body with labelled axes,
//! for colour-versus-(thickness, angle) charts and heat maps, and the heat ramp they use.

use super::{
    font, resample, text_scale, tick_label, tick_step, valid_range, Figure, PlotArea, PlotError,
};
use crate::image_io::{srgb_to_linear, RgbImage};
use plotters::element::BitMapElement;
use plotters::prelude::*;

/// Draws `image` stretched over a chart body with labelled axes on a white `width` × `height`
/// figure: its columns span `x_range` left to right and its rows `y_range` from the bottom row
/// (y_range.0) to the top row (y_range.1). Invalid ranges (NaN, empty) show as (0, 1).
#[allow(clippy::too_many_arguments)]
pub fn color_map(
    image: &RgbImage,
    x_range: (f64, f64),
    y_range: (f64, f64),
    title: &str,
    x_label: &str,
    y_label: &str,
    width: u32,
    height: u32,
) -> Result<(Figure, PlotArea), PlotError> {
    let mut fig = Figure::new(width, height);
    let s = text_scale(fig.width(), fig.height());
    let xr = valid_range(x_range).unwrap_or((0.0, 1.0));
    let yr = valid_range(y_range).unwrap_or((0.0, 1.0));
    let area = {
        let root = fig.area();
        let mut chart = ChartBuilder::on(&root)
            .caption(title, font(22.0 * s))
            .margin(12.0 * s)
            .x_label_area_size(44.0 * s)
            .y_label_area_size(56.0 * s)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
        let a = PlotArea::of(chart.plotting_area(), xr, yr);
        let (w, h) = (a.width.max(0) as u32, a.height.max(0) as u32);
        let pixels = resample(image, w, h);
        if let Some(bitmap) =
            BitMapElement::with_owned_buffer((a.left as i32, a.top as i32), (w, h), pixels)
        {
            root.draw(&bitmap)?;
        }
        let (xs, ys) = (tick_step(xr.0, xr.1, 8), tick_step(yr.0, yr.1, 6));
        let (fx, fy) = (|v: &f64| tick_label(*v, xs), |v: &f64| tick_label(*v, ys));
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(8)
            .y_labels(6)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style(font(14.0 * s))
            .axis_desc_style(font(15.0 * s))
            .x_desc(x_label)
            .y_desc(y_label)
            .draw()?;
        let frame = [(xr.0, yr.0), (xr.1, yr.1)];
        chart.draw_series(std::iter::once(Rectangle::new(frame, BLACK)))?;
        root.present()?;
        a
    };
    Ok((fig, area))
}

/// A colour ramp of ophis's own for heat maps, in linear RGB: value/max in [0, 1] runs from dark
/// violet through blue, teal and green to yellow, interpolated in sRGB between five hand-picked
/// stops so that lightness rises steadily (readable in grey too). NaN, negative values and a
/// non-positive max give the darkest colour; values above max the brightest.
pub fn heat(value: f32, max: f32) -> [f32; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [0.26, 0.02, 0.33],
        [0.24, 0.30, 0.56],
        [0.15, 0.55, 0.55],
        [0.40, 0.77, 0.36],
        [0.98, 0.90, 0.16],
    ];
    let t = if max > 0.0 && value.is_finite() {
        (value / max).clamp(0.0, 1.0)
    } else if value.is_infinite() && value > 0.0 {
        1.0
    } else {
        0.0
    };
    let f = t * (STOPS.len() - 1) as f32;
    let i = (f as usize).min(STOPS.len() - 2);
    let u = f - i as f32;
    std::array::from_fn(|k| srgb_to_linear(STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * u))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_image_fills_the_chart_body_the_right_way_up() {
        // Left half red, right half blue; the bottom row green.
        let mut img = RgbImage::new(8, 4);
        for y in 0..4 {
            for x in 0..8 {
                img.data[y * 8 + x] = match (x < 4, y == 3) {
                    (_, true) => [0.0, 1.0, 0.0],
                    (true, false) => [1.0, 0.0, 0.0],
                    (false, false) => [0.0, 0.0, 1.0],
                };
            }
        }
        let (fig, a) = color_map(&img, (0.0, 800.0), (0.0, 90.0), "t", "x", "y", 600, 360).unwrap();
        let at = |x: f64, y: f64| {
            let (px, py) = a.to_pixel(x, y);
            fig.pixel(px, py).unwrap()
        };
        assert_eq!(at(200.0, 60.0), [255, 0, 0]);
        assert_eq!(at(600.0, 60.0), [0, 0, 255]);
        assert_eq!(
            at(400.0, 5.0),
            [0, 255, 0],
            "the last row is at the bottom (y_range.0)"
        );
        // Axes texts around it, white beyond the ticks.
        assert_eq!(fig.pixel(2, 359), Some([255; 3]));
        assert!(a.left > 30 && a.top > 20 && a.top + a.height < 360 - 30);
    }

    #[test]
    fn bad_ranges_and_sizes_do_not_panic() {
        let img = RgbImage::new(0, 0);
        let (f, a) = color_map(&img, (f64::NAN, 1.0), (2.0, 2.0), "", "", "", 1, 1).unwrap();
        assert_eq!((f.width(), f.height()), (1, 1));
        assert_eq!((a.x_range, a.y_range), ((0.0, 1.0), (0.0, 1.0)));
        let _ = color_map(
            &RgbImage::new(3, 3),
            (0.0, 1.0),
            (0.0, 1.0),
            "t",
            "x",
            "y",
            30,
            20,
        )
        .unwrap();
    }

    #[test]
    fn heat_ramp_rises_in_lightness() {
        assert_ne!(heat(0.0, 1.0), heat(1.0, 1.0));
        let lum = |c: [f32; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        let mut prev = -1.0;
        for i in 0..=20 {
            let l = lum(heat(i as f32, 20.0));
            assert!(l > prev, "lightness must rise monotonically");
            prev = l;
        }
        assert_eq!(heat(f32::NAN, 1.0), heat(0.0, 1.0));
        assert_eq!(heat(5.0, 0.0), heat(0.0, 1.0));
        assert_eq!(heat(7.0, 1.0), heat(1.0, 1.0));
    }
}
