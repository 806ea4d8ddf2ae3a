//! A film stack prepared for rendering: R and T at the path's four hero wavelengths, for any angle
//! and either side, many times per shading point.
//!
//! [`StackEval::new`] (via [`FilmStack::prepare`]) evaluates every index at the four wavelengths
//! and folds the thickness scale into the phase constants 2π d s/λ once. Each
//! [`StackEval::rt`] call then costs, per distinct layer, one square root and one sin/cos pair
//! per wavelength, all four wavelengths at once in f64 lanes ([`super::simd4`]):
//!
//! - **Real path** — every layer lossless and the wave propagating in every layer (n_j² > σ²) at
//!   all four wavelengths: the characteristic matrix [[cos δ, −i sin δ/y], [−i y sin δ, cos δ]] has
//!   real diagonal and imaginary off-diagonal entries, a form closed under multiplication, so a
//!   matrix is four reals [a, b, c, d] ↦ [[a, ib], [ic, d]] and a product costs 8 multiplications.
//!   The base (dielectric, totally reflecting, or metal) enters only the final complex step.
//! - **Complex path** — any absorbing layer, or an evanescent wave in a layer (total internal
//!   reflection inside the stack): per wavelength, the scaled complex matrices of
//!   [`super::charmatrix`] (no overflow however thick the layer).
//!
//! A periodic group costs its period once: its matrix is raised to the repeat count by squaring
//! (a 10-pair Bragg mirror is two layer evaluations and five matrix products). Products that grow
//! (a deep stop band of many periods) are rescaled by powers of two, so R stays exact and T
//! underflows to 0 rather than overflowing.
//!
//! Same model, branch and conventions as [`super::filmstack`] and [`super::charmatrix`] (tested
//! against them to 1e-12). `from_inside`: light arrives from the base, which must then be
//! lossless (else its real part is used).

use super::charmatrix::{self, LayerAt, Scaled2, StackMatrices};
use super::filmstack::FilmStack;
use super::simd4::{sincos4, zip4, F4};
use super::thinfilm::FilmRt;
use num_complex::Complex64 as C;

/// Layers (or groups) held inline; larger stacks use the heap.
const INLINE: usize = 8;

/// One distinct layer at the four wavelengths.
#[derive(Clone, Copy, Debug, Default)]
struct LayerLanes {
    /// n² (real and imaginary parts).
    n2: F4,
    n2_im: F4,
    /// 1/n² where the layer is lossless.
    inv_n2: F4,
    /// 2π d·scale/λ.
    kd: F4,
}

/// A run of `len` layers from `start`, repeated `count` times.
#[derive(Clone, Copy, Debug, Default)]
struct Group {
    start: u32,
    len: u32,
    count: u32,
}

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
}

#[inline(always)]
fn splat(v: f64) -> F4 {
    [v; 4]
}

/// Structured real matrix [[a, ib], [ic, d]] (see the module doc), with a per-lane power-of-two
/// exponent: value = 2^e · M.
#[derive(Clone, Copy)]
struct RealM {
    a: F4,
    b: F4,
    c: F4,
    d: F4,
    e: F4,
}

impl RealM {
    const I: RealM = RealM {
        a: [1.0; 4],
        b: [0.0; 4],
        c: [0.0; 4],
        d: [1.0; 4],
        e: [0.0; 4],
    };

    #[inline(always)]
    fn mul(&self, o: &RealM) -> RealM {
        let mut r = RealM::I;
        for i in 0..4 {
            r.a[i] = self.a[i] * o.a[i] - self.b[i] * o.c[i];
            r.b[i] = self.a[i] * o.b[i] + self.b[i] * o.d[i];
            r.c[i] = self.c[i] * o.a[i] + self.d[i] * o.c[i];
            r.d[i] = self.d[i] * o.d[i] - self.c[i] * o.b[i];
            r.e[i] = self.e[i] + o.e[i];
        }
        r
    }

    fn pow(&self, mut n: u32) -> RealM {
        let (mut base, mut acc) = (*self, RealM::I);
        while n > 0 {
            if n & 1 == 1 {
                acc = acc.mul(&base);
                acc.renormalise();
            }
            n >>= 1;
            if n > 0 {
                base = base.mul(&base);
                base.renormalise();
            }
        }
        acc
    }

    /// Keeps the entries below 2^400 (lanes whose product grew are divided by a power of two).
    #[inline]
    fn renormalise(&mut self) {
        for i in 0..4 {
            let big = self.a[i]
                .abs()
                .max(self.b[i].abs())
                .max(self.c[i].abs())
                .max(self.d[i].abs());
            if big > 2f64.powi(400) {
                let e = big.log2().round();
                let f = 2f64.powf(-e);
                self.a[i] *= f;
                self.b[i] *= f;
                self.c[i] *= f;
                self.d[i] *= f;
                self.e[i] += e;
            }
        }
    }
}

/// √(x + iy) with y ≥ 0 on the branch Im ≥ 0, lane-wise and branch-free.
#[inline(always)]
fn csqrt_up(x: F4, y: F4) -> (F4, F4) {
    let mut u = [0.0; 4];
    let mut v = [0.0; 4];
    for i in 0..4 {
        let m = (x[i] * x[i] + y[i] * y[i]).sqrt();
        let t = (0.5 * (m + x[i].abs())).sqrt();
        let o = if t > 0.0 { y[i] / (2.0 * t) } else { 0.0 };
        (u[i], v[i]) = if x[i] >= 0.0 { (t, o) } else { (o, t) };
    }
    (u, v)
}

/// R and T from the structured product, incident admittance y0 and exit admittance u + iv.
#[inline(always)]
fn finish_real(m: &RealM, y0: F4, u: F4, v: F4) -> (F4, F4) {
    let mut r = [0.0; 4];
    let mut t = [0.0; 4];
    for i in 0..4 {
        let (b_re, b_im) = (m.a[i] - m.b[i] * v[i], m.b[i] * u[i]);
        let (c_re, c_im) = (m.d[i] * u[i], m.c[i] + m.d[i] * v[i]);
        let (nr, ni) = (y0[i] * b_re - c_re, y0[i] * b_im - c_im);
        let (dr, di) = (y0[i] * b_re + c_re, y0[i] * b_im + c_im);
        let den = dr * dr + di * di;
        r[i] = ((nr * nr + ni * ni) / den).min(1.0);
        let scale = if m.e[i] == 0.0 {
            1.0
        } else {
            2f64.powf(-2.0 * m.e[i])
        };
        t[i] = (4.0 * y0[i] * u[i] / den * scale).clamp(0.0, 1.0);
    }
    (r, t)
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
                all_lossless &= n.iter().all(|n| n.im == 0.0);
                layers.push(LayerLanes {
                    n2: n2.map(|z| z.re),
                    n2_im: n2.map(|z| z.im),
                    inv_n2: n2.map(|z| 1.0 / z.re),
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
        StackEval {
            lambda,
            layers,
            groups,
            all_lossless,
            ext: lambda.map(|w| stack.ext().at(w).re),
            base: lambda.map(|w| stack.base().at(w)),
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
    pub fn rt(&self, cos_theta: f64, from_inside: bool) -> Rt4 {
        let cos = if cos_theta.is_nan() {
            0.0
        } else {
            cos_theta.clamp(0.0, 1.0)
        };
        if cos == 0.0 {
            return Rt4 {
                r_s: splat(1.0),
                r_p: splat(1.0),
                t_s: splat(0.0),
                t_p: splat(0.0),
            };
        }
        let (n_inc, exit) = if from_inside {
            (self.base.map(|b| b.re), self.ext.map(|e| C::new(e, 0.0)))
        } else {
            (self.ext, self.base)
        };
        let sin2 = 1.0 - cos * cos;
        let sigma2 = n_inc.map(|n| n * n * sin2);
        if self.all_lossless {
            if let Some(rt) = self.rt_real(cos, n_inc, sigma2, exit, from_inside) {
                return rt;
            }
        }
        let mut out = Rt4 {
            r_s: [0.0; 4],
            r_p: [0.0; 4],
            t_s: [0.0; 4],
            t_p: [0.0; 4],
        };
        for i in 0..4 {
            let rt = self.rt_complex_lane(i, cos, n_inc[i], sigma2[i], exit[i], from_inside);
            (out.r_s[i], out.r_p[i], out.t_s[i], out.t_p[i]) = (rt.r_s, rt.r_p, rt.t_s, rt.t_p);
        }
        out
    }

    /// The groups in the order light meets them, each with its layers in that order.
    #[inline(always)]
    fn ordered(&self, k: usize, from_inside: bool) -> (Group, bool) {
        let g = self.groups.as_slice();
        (
            if from_inside {
                g[g.len() - 1 - k]
            } else {
                g[k]
            },
            from_inside,
        )
    }

    /// The real path (see the module doc); `None` if some layer does not propagate.
    #[inline(always)]
    fn rt_real(
        &self,
        cos: f64,
        n_inc: F4,
        sigma2: F4,
        exit: [C; 4],
        from_inside: bool,
    ) -> Option<Rt4> {
        let layers = self.layers.as_slice();
        let (mut ms, mut mp) = (RealM::I, RealM::I);
        for k in 0..self.groups.as_slice().len() {
            let (g, rev) = self.ordered(k, from_inside);
            let (mut ps, mut pp) = (RealM::I, RealM::I);
            for j in 0..g.len {
                let idx = if rev {
                    g.start + g.len - 1 - j
                } else {
                    g.start + j
                };
                let l = &layers[idx as usize];
                let q2 = zip4(l.n2, sigma2, |a, b| a - b);
                if !q2.iter().all(|&v| v > 0.0) {
                    return None;
                }
                let q = q2.map(f64::sqrt);
                let (sn, cs) = sincos4(zip4(l.kd, q, |k, q| k * q));
                let mut s = RealM::I;
                let mut p = RealM::I;
                for i in 0..4 {
                    let bs = -sn[i] / q[i];
                    let cq = -sn[i] * q[i];
                    s.a[i] = cs[i];
                    s.d[i] = cs[i];
                    s.b[i] = bs;
                    s.c[i] = cq;
                    p.a[i] = cs[i];
                    p.d[i] = cs[i];
                    p.b[i] = bs * l.n2[i];
                    p.c[i] = cq * l.inv_n2[i];
                }
                if j == 0 {
                    (ps, pp) = (s, p);
                } else {
                    ps = ps.mul(&s);
                    pp = pp.mul(&p);
                }
            }
            if g.count > 1 {
                ps = ps.pow(g.count);
                pp = pp.pow(g.count);
            }
            if k == 0 {
                (ms, mp) = (ps, pp);
            } else {
                ms = ms.mul(&ps);
                mp = mp.mul(&pp);
            }
            if g.count > 1 || k % 16 == 15 {
                ms.renormalise();
                mp.renormalise();
            }
        }
        // Exit medium: q = √(n² − σ²) (complex for a metal or beyond its critical angle).
        let n2e: [C; 4] = exit.map(|n| n * n);
        let (u, v) = csqrt_up(
            std::array::from_fn(|i| n2e[i].re - sigma2[i]),
            n2e.map(|z| z.im),
        );
        let ye_p: [C; 4] = std::array::from_fn(|i| C::new(u[i], v[i]) / n2e[i]);
        let y0_s = n_inc.map(|n| n * cos);
        let y0_p = n_inc.map(|n| cos / n);
        let (r_s, t_s) = finish_real(&ms, y0_s, u, v);
        let (r_p, t_p) = finish_real(&mp, y0_p, ye_p.map(|z| z.re), ye_p.map(|z| z.im));
        Some(Rt4 { r_s, r_p, t_s, t_p })
    }

    /// The complex path for lane `i`.
    fn rt_complex_lane(
        &self,
        i: usize,
        cos: f64,
        n_inc: f64,
        sigma2: f64,
        exit: C,
        from_inside: bool,
    ) -> FilmRt {
        let layers = self.layers.as_slice();
        let mut m = StackMatrices {
            s: Scaled2::IDENTITY,
            p: Scaled2::IDENTITY,
            phase: C::new(0.0, 0.0),
        };
        for k in 0..self.groups.as_slice().len() {
            let (g, rev) = self.ordered(k, from_inside);
            let (mut ps, mut pp, mut ph) = (Scaled2::IDENTITY, Scaled2::IDENTITY, C::new(0.0, 0.0));
            for j in 0..g.len {
                let idx = if rev {
                    g.start + g.len - 1 - j
                } else {
                    g.start + j
                };
                let l = &layers[idx as usize];
                let at = LayerAt {
                    n2: C::new(l.n2[i], l.n2_im[i]),
                    kd: l.kd[i],
                };
                let (s, p, d) = charmatrix::layer_matrices(at, sigma2);
                ps = ps.mul(&s);
                pp = pp.mul(&p);
                ph += d;
            }
            if g.count > 1 {
                ps = ps.pow(g.count);
                pp = pp.pow(g.count);
                ph *= g.count as f64;
            }
            m.s = m.s.mul(&ps);
            m.p = m.p.mul(&pp);
            m.phase += ph;
        }
        charmatrix::finish(&m, n_inc, cos, sigma2, exit).0
    }
}
