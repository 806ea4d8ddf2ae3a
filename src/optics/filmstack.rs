//! Interference stacks: N coherent layers between an outside medium and a base, exactly, per
//! wavelength, for s and p separately.
//!
//! ```text
//!   outside  n_ext (lossless)            ← light arrives here (from_inside = false)
//!   layer 1  n_1 + i k_1, d_1            ← listed first: "outside in"
//!   …        (a periodic group counts as its period written `count` times)
//!   layer N  n_N + i k_N, d_N
//!   base     n_b + i k_b (dielectric or metal)   ← or here (from_inside = true, lossless base)
//! ```
//!
//! | part | meaning | units / range |
//! |---|---|---|
//! | `ext` | outside medium, [`Ior`] | lossless (k = 0) |
//! | layers | [`Layer`]: index (any [`Ior`], absorbing allowed) and thickness | nm, finite, ≥ 0 |
//! | periodic group | [`StackItem::Periodic`]: a period of layers and a repeat count | 1 ≤ count ≤ [`MAX_REPEAT`] |
//! | `base` | the half-space under the stack, [`Ior`] | any; metal: k > 0 |
//! | total | flattened layers | 0 ≤ N ≤ [`MAX_LAYERS`] |
//!
//! Exact evaluation ([`FilmStack::rt`]): one and zero layers go through the single-film Airy code
//! ([`super::thinfilm::film_rt`]; zero layers is its d = 0 case, the bare interface), so a
//! one-layer stack is bit-for-bit the single-film result; two or more through the stable
//! characteristic-matrix product of [`super::charmatrix`] (Born & Wolf §1.6; Macleod ch. 2;
//! tmm's conventions, Byrnes 2016), which is also available at N = 1 as
//! [`FilmStack::rt_matrix`] for testing. Light from the base side meets the stack reversed (base
//! as incident medium, outside as exit medium); this needs a lossless base — from inside a metal
//! the real part of its index is used, a case no renderer asks for. T is the power that enters
//! the exit medium (for a metal base: that the metal absorbs), A = 1 − R − T what the layers
//! absorb; lossless stacks have A = 0.
//!
//! Fast evaluation at four wavelengths for rendering: [`FilmStack::prepare`] (see
//! [`super::stackeval`]).
//!
//! Known limits: every layer is coherent (no incoherent thick layers à la `tmm.inc_tmm`: a
//! 100 µm layer gives fringes finer than any wavelength sampling resolves); interfaces are flat
//! and sharp (no roughness or grading); indices are isotropic.

use super::charmatrix::{self, Amplitudes, LayerAt};
use super::ior::Ior;
use super::stackeval::StackEval;
use super::thinfilm::{film_rt, FilmRt};
use num_complex::Complex64 as C;
use std::fmt;

/// Largest number of layers once periodic groups are written out.
pub(crate) const MAX_LAYERS: usize = 4096;
/// Largest repeat count of a periodic group.
pub(crate) const MAX_REPEAT: u32 = 4096;

/// One homogeneous layer.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    pub ior: Ior,
    /// Thickness in nm (finite, ≥ 0).
    pub thickness_nm: f64,
}

impl Layer {
    pub fn new(ior: Ior, thickness_nm: f64) -> Layer {
        Layer { ior, thickness_nm }
    }
}

/// A layer, or a period of layers repeated `count` times (a Bragg mirror of 10 pairs is one item).
#[derive(Clone, Debug, PartialEq)]
pub enum StackItem {
    Layer(Layer),
    Periodic { period: Vec<Layer>, count: u32 },
}

impl StackItem {
    /// The item's layers written once (a period once, not `count` times).
    pub(crate) fn period(&self) -> &[Layer] {
        match self {
            StackItem::Layer(l) => std::slice::from_ref(l),
            StackItem::Periodic { period, .. } => period,
        }
    }

    /// How many times [`StackItem::period`] repeats.
    pub fn count(&self) -> u32 {
        match self {
            StackItem::Layer(_) => 1,
            StackItem::Periodic { count, .. } => *count,
        }
    }
}

/// A validated stack: outside medium, items listed outside in, base.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmStack {
    ext: Ior,
    items: Vec<StackItem>,
    base: Ior,
    n_layers: usize,
}

impl FilmStack {
    /// Checks and builds a stack; the error names the item (1-based) and what was expected.
    pub fn new(ext: Ior, items: Vec<StackItem>, base: Ior) -> Result<FilmStack, String> {
        if !ext.is_lossless() {
            return Err(format!(
                "the outside medium must be transparent (k = 0), got {ext}"
            ));
        }
        let mut n = 0usize;
        for (i, it) in items.iter().enumerate() {
            let (period, count) = (it.period(), it.count());
            if period.is_empty() {
                return Err(format!(
                    "item {}: a periodic group needs at least one layer",
                    i + 1
                ));
            }
            if !(1..=MAX_REPEAT).contains(&count) {
                return Err(format!(
                    "item {}: the repeat count must be 1 to {MAX_REPEAT}, got {count}",
                    i + 1
                ));
            }
            for l in period {
                let d = l.thickness_nm;
                if !(d >= 0.0 && d.is_finite()) {
                    return Err(format!(
                        "item {}: the thickness must be a finite number ≥ 0 nm, got {d}",
                        i + 1
                    ));
                }
            }
            n += period.len() * count as usize;
            if n > MAX_LAYERS {
                return Err(format!(
                    "item {}: the stack exceeds {MAX_LAYERS} layers once repeats are written out",
                    i + 1
                ));
            }
        }
        Ok(FilmStack {
            ext,
            items,
            base,
            n_layers: n,
        })
    }

    /// One film: `ext | film, d | base`, the single-film configuration.
    pub fn film(ext: Ior, film: Ior, d_nm: f64, base: Ior) -> Result<FilmStack, String> {
        FilmStack::new(ext, vec![StackItem::Layer(Layer::new(film, d_nm))], base)
    }

    pub fn ext(&self) -> &Ior {
        &self.ext
    }
    pub fn base(&self) -> &Ior {
        &self.base
    }
    pub fn items(&self) -> &[StackItem] {
        &self.items
    }
    /// Number of layers with periodic groups written out.
    pub fn n_layers(&self) -> usize {
        self.n_layers
    }

    /// Every layer, outside in, with periodic groups written out.
    pub fn layers(&self) -> impl DoubleEndedIterator<Item = &Layer> + '_ {
        self.items
            .iter()
            .flat_map(|it| std::iter::repeat_n(it.period(), it.count() as usize).flatten())
    }

    /// Sum of all layer thicknesses (nm).
    pub fn total_thickness(&self) -> f64 {
        self.layers().map(|l| l.thickness_nm).sum()
    }

    /// The same stack with every thickness multiplied by `factor` (finite, ≥ 0; otherwise 0).
    pub fn scaled(&self, factor: f64) -> FilmStack {
        let f = if factor >= 0.0 && factor.is_finite() {
            factor
        } else {
            0.0
        };
        let scale = |l: &Layer| Layer::new(l.ior.clone(), l.thickness_nm * f);
        let items = self
            .items
            .iter()
            .map(|it| match it {
                StackItem::Layer(l) => StackItem::Layer(scale(l)),
                StackItem::Periodic { period, count } => StackItem::Periodic {
                    period: period.iter().map(scale).collect(),
                    count: *count,
                },
            })
            .collect();
        FilmStack {
            items,
            ..self.clone()
        }
    }

    /// Incident and exit indices: the base is the incident medium from inside.
    fn media(&self, lambda_nm: f64, from_inside: bool) -> (f64, C) {
        let (e, b) = (self.ext.at(lambda_nm), self.base.at(lambda_nm));
        if from_inside {
            (b.re, e)
        } else {
            (e.re, b)
        }
    }

    /// Exact s and p reflectance and transmittance at `cos_theta` (∈ [0, 1], from the normal on
    /// the incident side) and vacuum wavelength `lambda_nm`; `from_inside`: light arrives from
    /// the base. Zero and one layers use the single-film Airy code, more the matrix method.
    pub fn rt(&self, cos_theta: f64, lambda_nm: f64, from_inside: bool) -> FilmRt {
        if self.n_layers >= 2 {
            return self.rt_matrix(cos_theta, lambda_nm, from_inside);
        }
        let (n_inc, n_exit) = self.media(lambda_nm, from_inside);
        let cos = if cos_theta.is_nan() {
            0.0
        } else {
            cos_theta.clamp(0.0, 1.0)
        };
        match self.layers().next() {
            Some(l) => film_rt(
                cos,
                n_inc,
                l.ior.at(lambda_nm),
                l.thickness_nm,
                n_exit,
                lambda_nm,
            ),
            None => film_rt(cos, n_inc, n_exit, 0.0, n_exit, lambda_nm),
        }
    }

    /// [`FilmStack::rt`] by the characteristic-matrix method whatever the number of layers.
    pub(crate) fn rt_matrix(&self, cos_theta: f64, lambda_nm: f64, from_inside: bool) -> FilmRt {
        self.matrix(cos_theta, lambda_nm, from_inside).0
    }

    /// Complex amplitudes r and t for s and p (tmm's conventions; see [`super::charmatrix`]).
    pub fn amplitudes(&self, cos_theta: f64, lambda_nm: f64, from_inside: bool) -> Amplitudes {
        self.matrix(cos_theta, lambda_nm, from_inside).1
    }

    fn matrix(&self, cos_theta: f64, lambda_nm: f64, from_inside: bool) -> (FilmRt, Amplitudes) {
        let (n_inc, n_exit) = self.media(lambda_nm, from_inside);
        let at = |l: &Layer| {
            let n = l.ior.at(lambda_nm);
            LayerAt {
                n2: n * n,
                kd: 2.0 * std::f64::consts::PI * l.thickness_nm / lambda_nm,
            }
        };
        if from_inside {
            charmatrix::stack_rt(n_inc, cos_theta, self.layers().rev().map(at), n_exit)
        } else {
            charmatrix::stack_rt(n_inc, cos_theta, self.layers().map(at), n_exit)
        }
    }

    /// Constants for fast evaluation at four wavelengths (nm) with every thickness multiplied by
    /// `thickness_scale` (a per-point texture; non-finite or negative values count as 0).
    pub fn prepare(&self, lambda_nm: [f32; 4], thickness_scale: f32) -> StackEval {
        StackEval::new(self, lambda_nm, thickness_scale)
    }
}

impl fmt::Display for Layer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.ior, self.thickness_nm)
    }
}

impl fmt::Display for FilmStack {
    /// The layers in the syntax of [`super::stackspec::parse_items`] (outside in; media omitted).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, it) in self.items.iter().enumerate() {
            if i > 0 {
                write!(f, ",")?;
            }
            match it {
                StackItem::Layer(l) => write!(f, "{l}")?,
                StackItem::Periodic { period, count } => {
                    write!(f, "(")?;
                    for (j, l) in period.iter().enumerate() {
                        write!(f, "{}{l}", if j > 0 { "," } else { "" })?;
                    }
                    write!(f, ")x{count}")?;
                }
            }
        }
        Ok(())
    }
}
