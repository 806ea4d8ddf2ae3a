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

use super::head_shields::{self, HEAD_CELLS};
use super::{FloatTexture, NormalSource, SpectrumTexture, Texture, Want};
use crate::math::Vec2;
use crate::plugin::{declare, Args, Check, Param, SceneError};
use std::sync::{Arc, OnceLock};

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

/// The head layout's seeds in map coordinates, computed once.
fn head_seeds() -> &'static [Vec2] {
    static SEEDS: OnceLock<Vec<Vec2>> = OnceLock::new();
    SEEDS.get_or_init(head_shields::seeds)
}

/// The parameters.
const PARAMS: &[Param] = &[
    Param::float("scale_u", 20.0)
        .check(Check::OpenClosed(0.0, 1e6))
        .unit("1/UV")
        .doc("cells per unit u"),
    Param::float("scale_v", 20.0)
        .check(Check::OpenClosed(0.0, 1e6))
        .unit("1/UV")
        .doc("rows per unit v"),
    Param::fraction("irregularity", 0.3).doc("0 = regular hexagons … 1 = Voronoi-like jitter"),
    Param::float("gap", 0.08)
        .also(&["line_width"])
        .v06("lineWidth")
        .check(Check::Range(0.0, 0.5))
        .unit("cells")
        .doc("groove width at half height"),
    Param::fraction("dome", 0.5).doc("0 = flat top … 1 = fully rounded"),
    Param::fraction("overlap", 0.3).doc("0 = symmetric … 1 = a ramp rising to the free edge"),
    Param::float("overlap_angle", 90.0)
        .unit("degrees")
        .doc("direction of the free edge in cell space (0 = +u, 90 = +v)"),
    Param::float("tilt_degrees", 0.0)
        .check(Check::Range(0.0, 45.0))
        .unit("degrees")
        .doc("largest random tilt of a scale's normal"),
    Param::int("seed", 0)
        .check(Check::Range(0.0, u32::MAX as f64))
        .doc("changes the random numbers"),
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
    let angle = a.float("overlap_angle")?.to_radians();
    Ok(Scales {
        scale_u: a.float("scale_u")?,
        scale_v: a.float("scale_v")?,
        irregularity: a.float("irregularity")?,
        gap: a.float("gap")?,
        dome: a.float("dome")?,
        overlap: a.float("overlap")?,
        overlap_dir: Vec2::new(angle.cos(), angle.sin()),
        tilt: a.float("tilt_degrees")?.to_radians(),
        seed: a.int("seed")? as u32,
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

/// Circumradius of the regular cell, the unit of the dome profile.
const CELL_RADIUS: f32 = 0.65;
/// Mean height of the relief, what it fades to at a distance (measured over regular cells with
/// the default dome; exact values matter little since only the relief's slope is seen).
const FADE_LEVEL: f32 = 0.6;

/// A 32-bit integer hash with good avalanche (xor-shift-multiply rounds).
#[inline]
fn mix(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Uniform [0, 1) from the top 24 bits.
#[inline]
fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Polynomial smooth minimum: min(a, b) with the corner rounded over a width `k`.
#[inline]
fn smooth_min(a: f32, b: f32, k: f32) -> f32 {
    let m = a.min(b);
    if k <= 0.0 || !m.is_finite() {
        return m;
    }
    let h = (k - (a - b).abs()).max(0.0) / k;
    m - 0.25 * k * h * h
}

/// The weights (∂/∂a, ∂/∂b) of [`smooth_min`]: the smaller argument counts 1 − h/2, the other
/// h/2, with h = max(k − |a − b|, 0)/k.
#[inline]
fn smooth_min_weights(a: f32, b: f32, k: f32) -> (f32, f32) {
    let h = if k > 0.0 && a.is_finite() && b.is_finite() {
        (k - (a - b).abs()).max(0.0) / k
    } else {
        0.0
    };
    if a <= b {
        (1.0 - 0.5 * h, 0.5 * h)
    } else {
        (0.5 * h, 1.0 - 0.5 * h)
    }
}

/// smoothstep and its derivative with respect to x.
#[inline]
fn smoothstep_d(e0: f32, e1: f32, x: f32) -> (f32, f32) {
    if e1 <= e0 {
        return (if x < e0 { 0.0 } else { 1.0 }, 0.0);
    }
    let t = (x - e0) / (e1 - e0);
    if !(0.0..=1.0).contains(&t) {
        return (t.clamp(0.0, 1.0), 0.0);
    }
    (t * t * (3.0 - 2.0 * t), 6.0 * t * (1.0 - t) / (e1 - e0))
}

#[inline]
fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    if e1 <= e0 {
        return if x < e0 { 0.0 } else { 1.0 };
    }
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Per-lookup constants of the lattice (see [`Scales::lattice`]).
#[derive(Clone, Copy)]
struct Lattice {
    pu: i32,
    pv: i32,
    seed: u32,
}

/// A lattice index wrapped into [0, period) (unchanged for period 0); the division is skipped
/// when it is already in range.
#[inline]
fn wrap(i: i32, period: i32) -> i32 {
    if period > 0 && !(0..period).contains(&i) {
        i.rem_euclid(period)
    } else {
        i
    }
}

/// The period of an integer cell count (wrapping of lattice indices), or 0 for none.
fn period(scale: f32) -> i32 {
    let r = scale.round();
    if (scale - r).abs() < 1e-3 && (1.0..1e6).contains(&r) {
        r as i32
    } else {
        0
    }
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
    fn cells_per_uv(&self) -> Vec2 {
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

    /// What every lookup needs once: the periods that wrap lattice indices (0 for none; the
    /// head's shields do not wrap) and the seed's hash.
    #[inline]
    fn lattice(&self) -> Lattice {
        let (pu, pv) = match self.layout {
            Layout::Head => (0, 0),
            _ => (period(self.scale_u), period(self.scale_v)),
        };
        Lattice {
            pu,
            pv,
            seed: mix(self.seed.wrapping_add(0x9e37_79b9)),
        }
    }

    /// The hash of row j, shared by the cells of the row.
    #[inline]
    fn row_hash(&self, j: i32, lat: Lattice) -> u32 {
        mix(wrap(j, lat.pv) as u32 ^ lat.seed)
    }

    /// Centre of lattice cell (i, j) in cell space (unwrapped, near the query point), its hash
    /// and its wrapped index; `row` is [`Scales::row_hash`] of j.
    #[inline]
    fn center(&self, i: i32, j: i32, row: u32, lat: Lattice) -> (Vec2, u32, (i32, i32)) {
        if self.layout == Layout::Head {
            // i indexes the seeds; unused indices lie far away and never win.
            let h = mix(i as u32 ^ row);
            let c = match head_seeds().get(i as usize) {
                Some(s) if i >= 0 => self.to_cell_space(*s),
                _ => Vec2::splat(1e6),
            };
            return (c, h, (i, 0));
        }
        let (wi, wj) = (wrap(i, lat.pu), wrap(j, lat.pv));
        let h = mix(wi as u32 ^ row);
        let mut jx = unit(mix(h ^ 0x68e3_1da4)) - 0.5;
        let jy = unit(mix(h ^ 0xb529_7a4d)) - 0.5;
        let mut shift = if j.rem_euclid(2) == 1 { 0.5 } else { 0.0 };
        if self.layout == Layout::Rows {
            // Plates stay aligned across the row (centred on half-integers, so that with
            // `scale_u` = 1 a plate spans u ∈ [0, 1]): only their length varies.
            (jx, shift) = (0.0, 0.5);
        }
        let c = Vec2::new(i as f32 + shift, j as f32) + self.irregularity * Vec2::new(jx, jy);
        (c, h, (wi, wj))
    }

    /// Calls `f` with every cell that may be nearest to lattice cell (ci, cj) or border it. The
    /// unjittered lattice's cells reach 0.71 from their centres, so with jitter of at most
    /// `irregularity`/2 per axis the nearest centre lies within 0.71 + 1.42·`irregularity`:
    /// one row and column either side while `irregularity` ≤ 0.35 (where the Voronoi
    /// neighbours are also the lattice's), two beyond that. The head's few seeds are all
    /// candidates.
    #[inline]
    fn candidates(&self, ci: i32, cj: i32, lat: Lattice, mut f: impl FnMut(i32, i32, u32)) {
        if self.layout == Layout::Head {
            let row = self.row_hash(0, lat);
            for i in 0..head_seeds().len() as i32 {
                f(i, 0, row);
            }
            return;
        }
        let reach = if self.irregularity <= 0.35 { 1 } else { 2 };
        for j in cj - reach..=cj + reach {
            let row = self.row_hash(j, lat);
            for i in ci - reach..=ci + reach {
                f(i, j, row);
            }
        }
    }

    /// The cell under a UV point and its hash (the nearest centre only: what the per-cell
    /// values and tilts need, at a fraction of [`Scales::sample`]'s cost).
    #[inline]
    pub fn nearest(&self, uv: Vec2) -> ((i32, i32), u32) {
        let p = self.to_cell_space(uv);
        let lat = self.lattice();
        let (j0, i0) = (p.y.round() as i32, p.x.floor() as i32);
        let mut best = (f32::INFINITY, 0u32, (0, 0));
        self.candidates(i0, j0, lat, |i, j, row| {
            let (c, h, cell) = self.center(i, j, row, lat);
            let d2 = (p - c).length_squared();
            if d2 < best.0 {
                best = (d2, h, cell);
            }
        });
        (best.2, best.1)
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

    /// The pattern and the gradient of its height with respect to cell space, in one pass: the
    /// relief is a product of smooth functions of the distances to the cell's centre and to
    /// its two nearest edges, each differentiated in closed form.
    fn evaluate(&self, uv: Vec2, width: f32) -> (ScaleSample, Vec2) {
        let p = self.to_cell_space(uv);
        let lat = self.lattice();
        let (j0, i0) = (p.y.round() as i32, p.x.floor() as i32);
        let mut best = (f32::INFINITY, Vec2::ZERO, 0u32, (0, 0), (0, 0));
        self.candidates(i0, j0, lat, |i, j, row| {
            let (c, h, cell) = self.center(i, j, row, lat);
            let d2 = (p - c).length_squared();
            if d2 < best.0 {
                best = (d2, c, h, cell, (i, j));
            }
        });
        let (_, c0, h0, cell, (bi, bj)) = best;
        // Distance to the cell edge: the nearest bisector with a neighbour, with the corners
        // rounded (a smooth minimum) so that the groove has no creases for the bump map to show.
        // Each bisector distance (m − p)·n is linear in p, with gradient −n.
        let round = 0.5 * self.gap;
        let (mut e1, mut e2) = (f32::INFINITY, f32::INFINITY);
        let (mut n1, mut n2) = (Vec2::ZERO, Vec2::ZERO);
        self.candidates(bi, bj, lat, |i, j, row| {
            if (i, j) == (bi, bj) {
                return;
            }
            let (c, _, _) = self.center(i, j, row, lat);
            let d = c - c0;
            let len = d.length();
            if len > 1e-6 {
                let n = d / len;
                let e = (0.5 * (c0 + c) - p).dot(n);
                if e < e1 {
                    (e2, n2) = (e1, n1);
                    (e1, n1) = (e, n);
                } else if e < e2 {
                    (e2, n2) = (e, n);
                }
            }
        });
        // Only the two nearest edges meet at a corner of the cell; taking just those keeps the
        // result independent of the order the neighbours were visited in.
        let raw = smooth_min(e1, e2, round);
        let edge = raw.max(0.0);
        let d_edge = if raw > 0.0 {
            let (w1, w2) = smooth_min_weights(e1, e2, round);
            -(n1 * w1 + n2 * w2)
        } else {
            Vec2::ZERO
        };
        let gap = self.gap.max((0.25 * width).min(0.5));
        let (shoulder, d_shoulder) = smoothstep_d(0.0, gap, edge);
        let q = (p - c0) / CELL_RADIUS;
        // x(2 − x) and r(3 − r²)/2 saturate with zero slope, so the relief stays C¹.
        let q2 = q.length_squared();
        let x = q2.min(1.0);
        let top = 1.0 - self.dome * x * (2.0 - x);
        let d_top = if q2 < 1.0 {
            q * (-self.dome * (2.0 - 2.0 * x) * 2.0 / CELL_RADIUS)
        } else {
            Vec2::ZERO
        };
        let r0 = q.dot(self.overlap_dir);
        let rc = r0.clamp(-1.0, 1.0);
        let r = 0.5 * rc * (3.0 - rc * rc);
        let tile = 1.0 - self.overlap * 0.5 * (1.0 - r);
        let d_tile = if r0.abs() < 1.0 {
            self.overlap_dir * (self.overlap * 0.75 * (1.0 - rc * rc) / CELL_RADIUS)
        } else {
            Vec2::ZERO
        };
        let relief = shoulder * top * tile;
        let d_relief = d_edge * (d_shoulder * top * tile)
            + d_top * (shoulder * tile)
            + d_tile * (shoulder * top);
        let fade = smoothstep(0.5, 2.0, width);
        let sample = ScaleSample {
            height: relief + fade * (FADE_LEVEL - relief),
            edge_distance: edge,
            id: unit(h0),
            cell,
            center: c0,
            groove: (1.0 - shoulder) * (1.0 - fade),
        };
        (sample, d_relief * (1.0 - fade))
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
