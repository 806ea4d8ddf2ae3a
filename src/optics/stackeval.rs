//! A film stack prepared for rendering: R and T at the path's four hero wavelengths, for any angle
//! and either side, many times per shading point.
//!
//! [`StackEval::new`] (via [`FilmStack::prepare`]) evaluates every index at the four wavelengths
//! and folds the thickness scale into the phase constants 2π d s/λ once. Each
//! [`StackEval::rt`] call then costs, per distinct layer, one square root and one sin/cos pair
//! per wavelength, all four wavelengths at once in f64 lanes ([`super::simd4`]; compiled for
//! AVX2 where the CPU has it, detected at run time, with bit-identical results):
//!
//! - **Real path** (`optics/realmat4.rs`) — every layer lossless and the wave propagating in every
//!   layer (n_j² > σ²) at all four wavelengths: the characteristic matrices have real diagonal
//!   and imaginary off-diagonal entries, a form closed under multiplication, so a product is four
//!   reals per wavelength. The base (dielectric, totally reflecting, or metal) enters only the
//!   final complex step.
//! - **Complex path** (`optics/cplxmat4.rs`) — any absorbing layer, or an evanescent wave in some
//!   layer (total internal reflection inside the stack): complex products, the scaled matrices
//!   e^{iδ}M of [`super::charmatrix`] for the layers that need them (no overflow however thick
//!   the layer), an exp and a sin/cos pair per such layer.
//!
//! A periodic group costs its period once: its matrix is raised to the repeat count by squaring
//! (a 10-pair Bragg mirror is two layer evaluations and a handful of matrix products). Products
//! that grow (a deep stop band of many periods) are rescaled by powers of two, so R stays exact
//! and T underflows to 0 rather than overflowing.
//!
//! Same model, branch and conventions as [`super::filmstack`] and [`super::charmatrix`] (tested
//! against them to 1e-12, and against `tmm`). `from_inside`: light arrives from the base, which
//! must then be lossless (else its real part is used). Exactly grazing incidence (cos θ = 0, or
//! NaN) gives R = 1, T = 0. Size: about 1.3 KB with up to 8 distinct layers inline (larger
//! stacks on the heap).

use super::cplxmat4::rt_complex;
use super::filmstack::FilmStack;
use super::realmat4::{rt_real, ExitLanes, Group, Incidence, LayerLanes};
use super::simd4::{zip4, F4};
use super::thinfilm::FilmRt;
use num_complex::Complex64 as C;

/// Layers (or groups) held inline; larger stacks use the heap.
const INLINE: usize = 8;

/// A small vector: inline up to [`INLINE`] items.
#[derive(Clone, Debug)]
enum Store<T: Copy + Default> {
    Inline(usize, [T; INLINE]),
    Heap(Vec<T>),
}

impl<T: Copy + Default> Store<T> {
    fn new() -> Self {
        Store::Inline(0, [T::default(); INLINE])
    }
    fn push(&mut self, v: T) {
        match self {
            Store::Inline(n, buf) if *n < INLINE => {
                buf[*n] = v;
                *n += 1;
            }
            Store::Inline(n, buf) => {
                let mut h = buf[..*n].to_vec();
                h.push(v);
                *self = Store::Heap(h);
            }
            Store::Heap(h) => h.push(v),
        }
    }
    #[inline]
    fn as_slice(&self) -> &[T] {
        match self {
            Store::Inline(n, buf) => &buf[..*n],
            Store::Heap(h) => h,
        }
    }
}

/// R and T for s and p at the four wavelengths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rt4 {
    pub r_s: F4,
    pub r_p: F4,
    pub t_s: F4,
    pub t_p: F4,
}

impl Rt4 {
    /// Unpolarised reflectance (R_s + R_p)/2.
    pub fn r(&self) -> F4 {
        zip4(self.r_s, self.r_p, |a, b| 0.5 * (a + b))
    }
    /// Unpolarised transmittance (T_s + T_p)/2.
    pub fn t(&self) -> F4 {
        zip4(self.t_s, self.t_p, |a, b| 0.5 * (a + b))
    }
    /// Lane `i` as a single-wavelength result.
    pub fn lane(&self, i: usize) -> FilmRt {
        FilmRt {
            r_s: self.r_s[i],
            r_p: self.r_p[i],
            t_s: self.t_s[i],
            t_p: self.t_p[i],
        }
    }
}

/// A stack's constants at four wavelengths (see the module doc).
#[derive(Clone, Debug)]
pub struct StackEval {
    lambda: F4,
    layers: Store<LayerLanes>,
    groups: Store<Group>,
    all_lossless: bool,
    ext: F4,
    base: [C; 4],
    /// 1/n of the incident medium: outside, and base (real part).
    inv_ext: F4,
    inv_base: F4,
    /// The exit medium for light from outside (the base) and from inside (the outside).
    exit_out: ExitLanes,
    exit_in: ExitLanes,
}

impl StackEval {
    /// See [`FilmStack::prepare`]. Wavelengths outside [1, 10⁶] nm (or NaN) are clamped to that
    /// range (NaN to 550 nm).
    pub fn new(stack: &FilmStack, lambda_nm: [f32; 4], thickness_scale: f32) -> StackEval {
        let lambda = lambda_nm.map(|l| {
            if l.is_nan() {
                550.0
            } else {
                (l as f64).clamp(1.0, 1e6)
            }
        });
        let scale = if thickness_scale >= 0.0 && thickness_scale.is_finite() {
            thickness_scale as f64
        } else {
            0.0
        };
        let mut layers = Store::new();
        let mut groups = Store::new();
        let mut start = 0u32;
        let mut all_lossless = true;
        for it in stack.items() {
            let period = it.period();
            for l in period {
                let n = lambda.map(|w| l.ior.at(w));
                let n2 = n.map(|n| n * n);
                let inv = n2.map(|z| {
                    if z.im == 0.0 {
                        C::new(1.0 / z.re, 0.0)
                    } else {
                        1.0 / z
                    }
                });
                let lossless = n.iter().all(|n| n.im == 0.0);
                all_lossless &= lossless;
                layers.push(LayerLanes {
                    n2: n2.map(|z| z.re),
                    n2_im: n2.map(|z| z.im),
                    inv_n2: inv.map(|z| z.re),
                    inv_n2_im: inv.map(|z| z.im),
                    lossless,
                    kd: lambda.map(|w| 2.0 * std::f64::consts::PI * l.thickness_nm * scale / w),
                });
            }
            groups.push(Group {
                start,
                len: period.len() as u32,
                count: it.count(),
            });
            start += period.len() as u32;
        }
        let ext = lambda.map(|w| stack.ext().at(w).re);
        let base = lambda.map(|w| stack.base().at(w));
        let exit = |n: [C; 4]| {
            let n2 = n.map(|n| n * n);
            let inv = n2.map(|z| 1.0 / z);
            ExitLanes {
                n2: n2.map(|z| z.re),
                n2_im: n2.map(|z| z.im),
                inv_n2: inv.map(|z| z.re),
                inv_n2_im: inv.map(|z| z.im),
                lossless: n.iter().all(|z| z.im == 0.0),
            }
        };
        StackEval {
            lambda,
            layers,
            groups,
            all_lossless,
            ext,
            base,
            inv_ext: ext.map(|n| 1.0 / n),
            inv_base: base.map(|n| 1.0 / n.re),
            exit_out: exit(base),
            exit_in: exit(ext.map(|e| C::new(e, 0.0))),
        }
    }

    /// The wavelengths (nm) the constants were computed for.
    pub fn lambda(&self) -> F4 {
        self.lambda
    }

    /// Unpolarised reflectance at the four wavelengths for light at `cos_theta` from the normal
    /// on the incident side (`from_inside`: from the base).
    #[inline]
    pub fn reflectance(&self, cos_theta: f32, from_inside: bool) -> [f32; 4] {
        self.rt(cos_theta as f64, from_inside).r().map(|v| v as f32)
    }

    /// R and T for s and p at the four wavelengths.
    #[inline]
    pub fn rt(&self, cos_theta: f64, from_inside: bool) -> Rt4 {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2 (checked just above), the only requirement of
            // `rt_avx2`.
            return unsafe { self.rt_avx2(cos_theta, from_inside) };
        }
        self.rt_lanes(cos_theta, from_inside)
    }

    /// [`StackEval::rt`] compiled for AVX2: the same operations, four lanes per instruction
    /// instead of two. No fused multiply-adds are formed (Rust never contracts), so the results
    /// are bit-for-bit those of the baseline build.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn rt_avx2(&self, cos_theta: f64, from_inside: bool) -> Rt4 {
        self.rt_lanes(cos_theta, from_inside)
    }

    #[inline(always)]
    fn rt_lanes(&self, cos_theta: f64, from_inside: bool) -> Rt4 {
        let cos = if cos_theta.is_nan() {
            0.0
        } else {
            cos_theta.clamp(0.0, 1.0)
        };
        if cos == 0.0 {
            return Rt4 {
                r_s: [1.0; 4],
                r_p: [1.0; 4],
                t_s: [0.0; 4],
                t_p: [0.0; 4],
            };
        }
        let (n_inc, inv_inc, exit) = if from_inside {
            (self.base.map(|b| b.re), self.inv_base, &self.exit_in)
        } else {
            (self.ext, self.inv_ext, &self.exit_out)
        };
        let sin2 = 1.0 - cos * cos;
        let inc = Incidence {
            rev: from_inside,
            sigma2: n_inc.map(|n| n * n * sin2),
            y0_s: n_inc.map(|n| n * cos),
            y0_p: inv_inc.map(|v| v * cos),
            exit,
        };
        let (l, g) = (self.layers.as_slice(), self.groups.as_slice());
        let rt = if self.all_lossless {
            rt_real(l, g, &inc)
        } else {
            None
        };
        let [r_s, r_p, t_s, t_p] = rt.unwrap_or_else(|| rt_complex(l, g, &inc));
        Rt4 { r_s, r_p, t_s, t_p }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::ior::Ior;
    use crate::optics::stackspec::parse_items;

    fn stack(spec: &str, base: Ior) -> FilmStack {
        FilmStack::new(Ior::Real(1.0), parse_items(spec).unwrap(), base).unwrap()
    }

    #[test]
    fn the_avx2_build_gives_the_baseline_bits() {
        // Real and complex paths, periodic groups, metal base, both sides.
        let cases = [
            stack("1.56:300,1.33:120,2.1:80", Ior::Real(1.5)),
            stack("(2.3:59.8,1.38:99.6)x10,2.3:59.8", Ior::Real(1.52)),
            stack(
                "keratin:100,1.7+0.03i:80,1.0:90",
                Ior::complex(0.35, 2.7).unwrap(),
            ),
            stack("(keratin:100,1.0:90)x4", Ior::Keratin),
        ];
        for st in &cases {
            let ev = st.prepare([400.0, 487.5, 590.0, 701.25], 1.1);
            for k in 0..200 {
                let cos = (k as f64 + 0.5) / 200.0;
                for inside in [false, true] {
                    assert_eq!(ev.rt(cos, inside), ev.rt_lanes(cos, inside), "{st} {cos}");
                }
            }
        }
    }

    #[test]
    fn thickness_scale_and_bad_inputs() {
        let st = stack("1.56:300,1.2:150", Ior::Real(1.5));
        let lam = [450.0, 500.0, 550.0, 600.0];
        let twice = stack("1.56:600,1.2:300", Ior::Real(1.5))
            .prepare(lam, 1.0)
            .rt(0.8, false);
        assert_eq!(st.prepare(lam, 2.0).rt(0.8, false), twice);
        // A scale that is not a finite number ≥ 0 removes the layers: the bare 1|1.5 interface.
        let bare = FilmStack::new(Ior::Real(1.0), vec![], Ior::Real(1.5)).unwrap();
        let want = bare.prepare(lam, 1.0).rt(0.8, false);
        for s in [f32::NAN, -1.0, f32::INFINITY] {
            assert_eq!(st.prepare(lam, s).rt(0.8, false), want, "{s}");
        }
        // NaN wavelengths are replaced, NaN and out-of-range cosines clamped: all finite.
        let ev = st.prepare([f32::NAN, 0.0, -5.0, 1e30], 1.0);
        for cos in [f64::NAN, -1.0, 0.0, 0.5, 7.0] {
            let rt = ev.rt(cos, true);
            assert!(
                rt.r_s
                    .iter()
                    .chain(&rt.t_p)
                    .all(|v| (0.0..=1.0).contains(v)),
                "{rt:?}"
            );
        }
        assert_eq!(ev.rt(0.0, false).r(), [1.0; 4]);
    }
}
