//! Small raster plotting for PNG figures, with no external crates: a [`Canvas`] with lines, text
//! and images, a built-in bitmap font, and charts (line, polar lobe, colour map, contact sheet).

pub mod canvas;
pub mod font;

pub use canvas::Canvas;
pub mod chart;
pub mod polar;
pub mod sheet;
pub mod ticks;

pub use chart::{color_map, heat, nice_ticks, LineChart, PlotArea, Series, PALETTE};
pub use polar::PolarChart;
pub use sheet::contact_sheet;
