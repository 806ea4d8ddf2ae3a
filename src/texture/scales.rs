//! `scales`: procedural reptile scales — offset rows of hexagonal cells over UV space, with a
//! groove between cells, a rounded (domed) top, a roof-tile rise towards the free edge, and a
//! random number per cell.
//!
//! Model. UV is mapped to *cell space* (x, y) = (u·`scale_u`, v·`scale_v`), where the cell
//! centres sit on the lattice (i + ½·(j mod 2), j) — rows one unit apart, every other row shifted
//! by half a cell — each moved by a random jitter of at most ½·`irregularity` per axis. The cells
//! are the Voronoi regions of those centres (Worley, "A Cellular Texture Basis Function",
//! SIGGRAPH 1996): congruent hexagons when `irregularity` = 0, Voronoi-like polygons as it grows.
//! The distance to the cell's edge is the distance to the nearest bisector between the nearest
//! centre and its neighbours, so grooves have the same width everywhere; where two edges meet,
//! a smooth minimum over a width `gap`/2 rounds the corner (at most `gap`/8 closer). Cell space has
//! one cell per unit area, so a UV area A holds A·`scale_u`·`scale_v` cells.
//!
//! Height, in [0, 1]: `shoulder(e) · top(ρ) · tile(r)` with e the distance to the edge,
//! shoulder = smoothstep(0, `gap`, e) (half height at e = gap/2, so the groove is `gap` wide at
//! half height, measured in cells); top = 1 − `dome`·x(2 − x) with x = min(ρ², 1) and ρ the
//! distance to the centre over 0.65 (≈ the hexagon's circumradius); tile = 1 − `overlap`·(1 − r)/2
//! with r = s(3 − s²)/2, s ∈ [−1, 1] the clamped position along the overlap direction, so each
//! scale rises towards its free edge (both saturate with zero slope, keeping the relief C¹). The
//! shoulder has zero slope at the edge, so height and slope are continuous across cells; only
//! `gap` = 0 leaves a step at the edges (intended: tiles laid edge to edge).
//!
//! Each cell draws, from a hash of its lattice index and `seed`, an id in [0, 1) (used by
//! `per_scale`), its jitter, and a normal tilt of at most `tilt_degrees` (used by `bumpmap`).
//! When `scale_u` (`scale_v`) is an integer the lattice indices wrap, so a closed surface with a
//! seam at u = 0 ≡ 1 shows no seam; across v the rows also alternate, so v wraps cleanly only for
//! an even integer `scale_v`.
//!
//! Layouts (`layout`): `hex`, the offset rows above (dorsal scales); `rows`, rows without the
//! half-cell shift and jittered only along v (with `scale_u` = 1 each row is one plate spanning
//! u ∈ [0, 1]: the ventral plates of the `snake` shape's belly); `head`, the head shields of
//! `head_shields.rs` — fixed Voronoi seeds on the head map, `scale_u` and `scale_v` stretching the
//! map (1 = as laid out) and `irregularity` unused.
//!
//! Filtering: there are no ray differentials yet. `sample_filtered` takes a footprint (the width
//! a pixel covers, in cells): the groove is widened to at least a quarter of it, and between a
//! footprint of ½ and 2 cells the relief fades to its mean, so scales smaller than a pixel fade
//! out instead of aliasing. The bump path estimates the footprint from the camera (see
//! `bsdf/bumpmap.rs`).
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `scale_u` | float | 20.0 | 1/UV | cells per unit u; in (0, 1000000] |
//! | `scale_v` | float | 20.0 | 1/UV | rows per unit v; in (0, 1000000] |
//! | `irregularity` | float | 0.3 | — | 0 = regular hexagons … 1 = Voronoi-like jitter; between 0 and 1 |
//! | `gap`, `line_width` (0.6: `lineWidth`) | float | 0.08 | cells | groove width at half height; between 0 and 0.5 |
//! | `dome` | float | 0.5 | — | 0 = flat top … 1 = fully rounded; between 0 and 1 |
//! | `overlap` | float | 0.3 | — | 0 = symmetric … 1 = a ramp rising to the free edge; between 0 and 1 |
//! | `overlap_angle` | float | 90.0 | degrees | direction of the free edge in cell space (0 = +u, 90 = +v) |
//! | `tilt_degrees` | float | 0.0 | degrees | largest random tilt of a scale's normal; between 0 and 45 |
//! | `seed` | integer | 0 | — | changes the random numbers; between 0 and 4294967295 |
//! | `layout` | string | `hex` | — | cell layout: `hex` (dorsal scales), `rows` (ventral plates) or `head` (head shields); one of 'hex', 'rows', 'head' |
//! | `color0` | spectrum | 0.4 | — | colour of the scales (colour lookups) |
//! | `color1` | spectrum | 0.1 | — | colour of the grooves (colour lookups) |
//!
//! Accepted names: `scales`, and the thesis's `reptileSkin` (with `color0`, `color1`,
//! `lineWidth`, which 0.6 scenes upgrade to `line_width`, read as `gap`).
//!
//! Limits: the footprint estimate ignores anisotropy beyond the larger axis; cells are defined in
//! UV space, so a parametrisation that stretches UV stretches the scales.

use super::head_shields::HEAD_CELLS;
use super::{FloatTexture, NormalSource, SpectrumTexture, Texture, Want};
use crate::math::Vec2;
use crate::plugin::{declare, Args, Check, Param, SceneError};
use std::sync::Arc;

mod lanes;
mod lattice;
mod relief;

pub(crate) use lattice::{mix, unit};
#[cfg(test)]
use relief::{CELL_RADIUS, FADE_LEVEL};

/// How cells are laid out (see the module header).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Layout {
    /// Offset rows of hexagons.
    #[default]
    Hex,
    /// Aligned rows (ventral plates).
    Rows,
    /// The head shields.
    Head,
}

impl Layout {
    /// Parses the XML name.
    pub(crate) fn from_name(s: &str) -> Option<Layout> {
        Some(match s {
            "hex" => Layout::Hex,
            "rows" => Layout::Rows,
            "head" => Layout::Head,
            _ => return None,
        })
    }
}

/// The parameters.
const PARAMS: &[Param] = &[
    Param::up_to("scale_u", 20.0, 1e6, "1/UV").doc("cells per unit u"),
    Param::up_to("scale_v", 20.0, 1e6, "1/UV").doc("rows per unit v"),
    Param::fraction("irregularity", 0.3).doc("0 = regular hexagons … 1 = Voronoi-like jitter"),
    Param::float("gap", 0.08)
        .also(&["line_width"])
        .v06("lineWidth")
        .check(Check::Range(0.0, 0.5))
        .unit("cells")
        .doc("groove width at half height"),
    Param::fraction("dome", 0.5).doc("0 = flat top … 1 = fully rounded"),
    Param::fraction("overlap", 0.3).doc("0 = symmetric … 1 = a ramp rising to the free edge"),
    Param::angle("overlap_angle", 90.0)
        .doc("direction of the free edge in cell space (0 = +u, 90 = +v)"),
    Param::angle("tilt_degrees", 0.0)
        .check(Check::Range(0.0, 45.0))
        .doc("largest random tilt of a scale's normal"),
    Param::u32("seed", 0).doc("changes the random numbers"),
    Param::string("layout", "hex")
        .check(Check::OneOf(&["hex", "rows", "head"]))
        .doc(
            "cell layout: `hex` (dorsal scales), `rows` (ventral plates) or `head` (head shields)",
        ),
    Param::colour("color0", 0.4).doc("colour of the scales (colour lookups)"),
    Param::colour("color1", 0.1).doc("colour of the grooves (colour lookups)"),
];

declare!(PLUGIN: Texture, Want = Texture "scales" ["reptileSkin", "reptile_skin"]
    "procedural reptile scales: a height, a colour, or normals"
    [PARAMS] load);

/// The pattern's parameters.
pub(crate) fn load_cells(a: &Args) -> Result<Scales, SceneError> {
    let angle = a.angle("overlap_angle")?;
    Ok(Scales {
        scale_u: a.float("scale_u")?,
        scale_v: a.float("scale_v")?,
        irregularity: a.float("irregularity")?,
        gap: a.float("gap")?,
        dome: a.float("dome")?,
        overlap: a.float("overlap")?,
        overlap_dir: Vec2::new(angle.cos(), angle.sin()),
        tilt: a.angle("tilt_degrees")?,
        seed: a.u32("seed")?,
        // The declaration's check admits only the three names.
        layout: Layout::from_name(&a.string("layout")?).unwrap_or_default(),
    })
}

fn load(a: &mut Args, want: Want) -> Result<Texture, SceneError> {
    let cells = Arc::new(load_cells(a)?);
    Ok(match want {
        Want::Spectrum(kind) => Texture::Spectrum(SpectrumTexture::Scales {
            cells,
            color0: a.spectrum_as("color0", kind)?,
            color1: a.spectrum_as("color1", kind)?,
        }),
        Want::Float | Want::Normals => {
            // Colours mean nothing to a height; mark them read so they do not warn as misspelt.
            a.ignore("color0")?;
            a.ignore("color1")?;
            if want == Want::Float {
                Texture::Float(FloatTexture::Scales(cells))
            } else {
                Texture::Normals(NormalSource::Scales(cells))
            }
        }
    })
}

/// Parameters of the scale pattern (see the module header).
#[derive(Clone, Debug, PartialEq)]
pub struct Scales {
    pub scale_u: f32,
    pub scale_v: f32,
    pub irregularity: f32,
    pub gap: f32,
    pub dome: f32,
    pub overlap: f32,
    /// Unit direction of the free edge in cell space.
    pub overlap_dir: Vec2,
    /// Largest tilt of a scale's normal, radians.
    pub tilt: f32,
    pub seed: u32,
    pub layout: Layout,
}

impl Default for Scales {
    fn default() -> Scales {
        Scales {
            scale_u: 20.0,
            scale_v: 20.0,
            irregularity: 0.3,
            gap: 0.08,
            dome: 0.5,
            overlap: 0.3,
            overlap_dir: Vec2::new(0.0, 1.0),
            tilt: 0.0,
            seed: 0,
            layout: Layout::Hex,
        }
    }
}

/// Everything the pattern knows at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScaleSample {
    /// Height in [0, 1].
    pub height: f32,
    /// Distance to the nearest cell edge, in cells.
    pub edge_distance: f32,
    /// The cell's random id in [0, 1).
    pub id: f32,
    /// The cell's lattice index (after wrapping).
    pub cell: (i32, i32),
    /// The cell's centre in cell space.
    pub center: Vec2,
    /// Groove mask: 1 in the groove, 0 on the scale.
    pub groove: f32,
}

impl Scales {
    /// How many cells a UV footprint (widths along u and v) spans, along its larger axis.
    #[inline]
    pub(crate) fn cells_across(&self, footprint: Vec2) -> f32 {
        let k = self.cells_per_uv();
        (footprint.x * k.x).max(footprint.y * k.y)
    }

    /// Cell-space units per UV unit along u and v.
    #[inline]
    pub fn cells_per_uv(&self) -> Vec2 {
        let k = Vec2::new(self.scale_u, self.scale_v);
        if self.layout == Layout::Head {
            k * HEAD_CELLS
        } else {
            k
        }
    }

    /// Cell space coordinates of a UV point.
    #[inline]
    pub(crate) fn to_cell_space(&self, uv: Vec2) -> Vec2 {
        uv * self.cells_per_uv()
    }

    /// The random id in [0, 1) of the cell under a UV point.
    #[inline]
    pub(crate) fn id_at(&self, uv: Vec2) -> f32 {
        unit(self.nearest(uv).1)
    }

    /// The pattern at a UV point, unfiltered.
    pub fn sample(&self, uv: Vec2) -> ScaleSample {
        self.sample_filtered(uv, 0.0)
    }

    /// The pattern at a UV point seen through a footprint `width` cells wide.
    pub(crate) fn sample_filtered(&self, uv: Vec2, width: f32) -> ScaleSample {
        self.evaluate(uv, width).0
    }

    /// Height at a UV point (footprint `width` in cells).
    #[inline]
    pub fn height(&self, uv: Vec2, width: f32) -> f32 {
        self.sample_filtered(uv, width).height
    }

    /// Gradient of the height with respect to (u, v), in closed form (see [`Scales::evaluate`];
    /// the tests check it against central differences).
    pub(crate) fn gradient(&self, uv: Vec2, width: f32) -> Vec2 {
        self.evaluate(uv, width).1 * self.cells_per_uv()
    }

    /// The random tilt of the scale at `uv`: (angle in radians, azimuth in radians measured in
    /// the tangent plane from dp/du). Uniform over a cone of half-angle `tilt`.
    pub(crate) fn tilt_at(&self, uv: Vec2) -> (f32, f32) {
        let (_, h) = self.nearest(uv);
        let a = self.tilt * unit(mix(h ^ 0x1b87_3593)).sqrt();
        let phi = 2.0 * std::f32::consts::PI * unit(mix(h ^ 0xcc9e_2d51));
        (a, phi)
    }
}

#[cfg(test)]
#[path = "scales_tests.rs"]
mod tests;
