//! The complex kernel of the film-stack evaluator, four wavelengths at once: stacks with an
//! absorbing layer, or with an evanescent wave in some layer (total internal reflection inside
//! the stack).
//!
//! Each layer that is lossless and propagating at all four wavelengths contributes its real
//! matrix [[cos δ, −i sin δ/y], [−i y sin δ, cos δ]] ([`super::realmat4`]); every other layer its
//! scaled matrix e^{iδ}M = [[(1 + w)/2, g y_s/y], [y y_s g, (1 + w)/2]], w = e^{2iδ},
//! g = (1 − w)/(2q), as in [`super::charmatrix`] (bounded however thick or opaque the layer).
//! For |2δ| < 10⁻² the difference 1 − w would cancel, so g = −i(2πd/λ)(e^z − 1)/z with z = 2iδ
//! comes from its series to z⁶ there (truncation < 10⁻¹⁷). The scale factors' modulus,
//! e^{−2 Σ Im δ}, multiplies T only. Products are complex 2×2 matrices per lane, rescaled by
//! powers of two when they grow past 2^400.
//!
//! Same conventions and results as [`super::charmatrix`] (tested to 1e-12).

use super::realmat4::{Group, Incidence, LayerLanes};
use super::simd4::{csqrt_up, exp4, sincos4, unit, zip4, F4};

/// A complex 2×2 matrix per lane, entries k = 0..4 ↦ [[0, 1], [2, 3]], times 2^e.
#[derive(Clone, Copy)]
struct CM4 {
    re: [F4; 4],
    im: [F4; 4],
    e: F4,
}

/// (re, im) lanes.
type Z4 = (F4, F4);

#[inline(always)]
fn cmul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

impl CM4 {
    const I: CM4 = CM4 {
        re: [[1.0; 4], [0.0; 4], [0.0; 4], [1.0; 4]],
        im: [[0.0; 4]; 4],
        e: [0.0; 4],
    };

    #[inline(always)]
    fn at(&self, k: usize, i: usize) -> (f64, f64) {
        (self.re[k][i], self.im[k][i])
    }

    #[inline(always)]
    fn mul(&self, o: &CM4) -> CM4 {
        let mut r = CM4::I;
        for i in 0..4 {
            for (row, col, k) in [(0, 0, 0), (0, 1, 1), (1, 0, 2), (1, 1, 3)] {
                let x = cmul(self.at(2 * row, i), o.at(col, i));
                let y = cmul(self.at(2 * row + 1, i), o.at(2 + col, i));
                r.re[k][i] = x.0 + y.0;
                r.im[k][i] = x.1 + y.1;
            }
            r.e[i] = self.e[i] + o.e[i];
        }
        r
    }

    /// self · [[h, b], [c, h]] in place.
    #[inline(always)]
    fn mul_layer(&mut self, h: &Z4, b: &Z4, c: &Z4) {
        for i in 0..4 {
            let (hh, bb, cc) = ((h.0[i], h.1[i]), (b.0[i], b.1[i]), (c.0[i], c.1[i]));
            for row in 0..2 {
                let (p, q) = (self.at(2 * row, i), self.at(2 * row + 1, i));
                let x0 = cmul(p, hh);
                let y0 = cmul(q, cc);
                let x1 = cmul(p, bb);
                let y1 = cmul(q, hh);
                self.re[2 * row][i] = x0.0 + y0.0;
                self.im[2 * row][i] = x0.1 + y0.1;
                self.re[2 * row + 1][i] = x1.0 + y1.0;
                self.im[2 * row + 1][i] = x1.1 + y1.1;
            }
        }
    }

    super::pow_by_squaring!();

    #[inline(always)]
    fn renormalise(&mut self) {
        const BIG: f64 = 2.58e120; // ≈ 2^400
        let mut any = false;
        for k in 0..4 {
            for i in 0..4 {
                any |= self.re[k][i].abs() > BIG || self.im[k][i].abs() > BIG;
            }
        }
        if any {
            self.rescale();
        }
    }

    #[cold]
    fn rescale(&mut self) {
        for i in 0..4 {
            let big = (0..4).fold(0.0f64, |m, k| {
                m.max(self.re[k][i].abs()).max(self.im[k][i].abs())
            });
            if big > 1.0 {
                let e = big.log2().round();
                let f = 2f64.powf(-e);
                for k in 0..4 {
                    self.re[k][i] *= f;
                    self.im[k][i] *= f;
                }
                self.e[i] += e;
            }
        }
    }
}

/// 1/(k+1)! for k = 0..=6: the series of (e^z − 1)/z.
const PHI_C: [f64; 7] = [
    1.0,
    0.5,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
];

/// A layer's matrix entries for s and p: (h, b_s, c_s, b_p, c_p) and Im δ.
#[inline(always)]
fn entries(l: &LayerLanes, sigma2: &F4) -> ([Z4; 5], F4) {
    let x = zip4(l.n2, *sigma2, |a, b| a - b);
    let zero = [0.0; 4];
    if l.lossless && x.iter().all(|&v| v > 0.0) {
        let q = x.map(f64::sqrt);
        let (sn, cs) = sincos4(zip4(l.kd, q, |k, q| k * q));
        let mut e = [
            (cs, zero),
            (zero, zero),
            (zero, zero),
            (zero, zero),
            (zero, zero),
        ];
        for i in 0..4 {
            let bs = -sn[i] / q[i];
            let cq = -sn[i] * q[i];
            e[1].1[i] = bs;
            e[2].1[i] = cq;
            e[3].1[i] = bs * l.n2[i];
            e[4].1[i] = cq * l.inv_n2[i];
        }
        return (e, zero);
    }
    let (qr, qi) = csqrt_up(x, l.n2_im);
    let (dr, di) = (zip4(l.kd, qr, |k, q| k * q), zip4(l.kd, qi, |k, q| k * q));
    let mag = exp4(di.map(|v| -2.0 * v));
    let (s2, c2) = sincos4(dr.map(|v| 2.0 * v));
    let mut e = [(zero, zero); 5];
    for i in 0..4 {
        let (wr, wi) = (mag[i] * c2[i], mag[i] * s2[i]);
        e[0].0[i] = 0.5 * (1.0 + wr);
        e[0].1[i] = 0.5 * wi;
        // g = (1 − w)/(2q) directly, or −i kd (e^z − 1)/z from its series for small z = 2iδ.
        let den = 2.0 * (qr[i] * qr[i] + qi[i] * qi[i]);
        let direct = cmul((1.0 - wr, -wi), (qr[i], -qi[i]));
        let (zr, zi) = (-2.0 * di[i], 2.0 * dr[i]);
        let mut p = (PHI_C[6], 0.0);
        for &c in PHI_C[..6].iter().rev() {
            p = cmul(p, (zr, zi));
            p.0 += c;
        }
        let small = zr * zr + zi * zi < 1e-4;
        let g = if small {
            (l.kd[i] * p.1, -l.kd[i] * p.0)
        } else {
            (direct.0 / den, direct.1 / den)
        };
        let q2 = (x[i], l.n2_im[i]);
        let cs = cmul(q2, g);
        let bp = cmul((l.n2[i], l.n2_im[i]), g);
        let cp = cmul(cs, (l.inv_n2[i], l.inv_n2_im[i]));
        (e[1].0[i], e[1].1[i]) = g;
        (e[2].0[i], e[2].1[i]) = cs;
        (e[3].0[i], e[3].1[i]) = bp;
        (e[4].0[i], e[4].1[i]) = cp;
    }
    (e, di)
}

/// (R, T) from a product, incident admittance y0, exit admittance (u, v) and attenuation
/// e^{−2ΣIm δ}.
#[inline(always)]
fn finish(m: &CM4, y0: &F4, y: &Z4, atten: &F4) -> (F4, F4) {
    let mut r = [0.0; 4];
    let mut t = [0.0; 4];
    for i in 0..4 {
        let ye = (y.0[i], y.1[i]);
        let b = cmul(m.at(1, i), ye);
        let b = (m.re[0][i] + b.0, m.im[0][i] + b.1);
        let c = cmul(m.at(3, i), ye);
        let c = (m.re[2][i] + c.0, m.im[2][i] + c.1);
        let (nr, ni) = (y0[i] * b.0 - c.0, y0[i] * b.1 - c.1);
        let (dr, di) = (y0[i] * b.0 + c.0, y0[i] * b.1 + c.1);
        // As in realmat4: scaled so that |den|² cannot underflow; a NaN from 0/0 maps to a bound.
        let s = 1.0 / dr.abs().max(di.abs());
        let (nr, ni, dr, di) = (nr * s, ni * s, dr * s, di * s);
        let inv = 1.0 / (dr * dr + di * di);
        r[i] = ((nr * nr + ni * ni) * inv).min(1.0);
        let scale = if m.e[i] == 0.0 {
            1.0
        } else {
            2f64.powf(-2.0 * m.e[i])
        };
        let t_i = 4.0 * (y0[i] * s) * (y.0[i] * s) * inv * atten[i] * scale;
        t[i] = unit(t_i);
    }
    (r, t)
}

/// (R_s, R_p, T_s, T_p) of any stack (see the module doc); arguments as
/// [`super::realmat4::rt_real`].
#[inline(always)]
pub(crate) fn rt_complex(layers: &[LayerLanes], groups: &[Group], inc: &Incidence) -> [F4; 4] {
    let (rev, sigma2, exit) = (inc.rev, &inc.sigma2, inc.exit);
    let (mut ms, mut mp) = (CM4::I, CM4::I);
    let mut im_delta = [0.0; 4];
    let n = groups.len();
    for k in 0..n {
        let g = Group::nth(groups, k, rev);
        let layer = |j: u32| &layers[g.layer(j, rev)];
        if g.count == 1 {
            for j in 0..g.len {
                let (e, di) = entries(layer(j), sigma2);
                ms.mul_layer(&e[0], &e[1], &e[2]);
                mp.mul_layer(&e[0], &e[3], &e[4]);
                im_delta = zip4(im_delta, di, |a, b| a + b);
            }
        } else {
            let (mut ps, mut pp) = (CM4::I, CM4::I);
            let mut gd = [0.0; 4];
            for j in 0..g.len {
                let (e, di) = entries(layer(j), sigma2);
                ps.mul_layer(&e[0], &e[1], &e[2]);
                pp.mul_layer(&e[0], &e[3], &e[4]);
                gd = zip4(gd, di, |a, b| a + b);
            }
            ms = ms.mul(&ps.pow(g.count));
            mp = mp.mul(&pp.pow(g.count));
            im_delta = zip4(im_delta, gd, |a, b| a + b * g.count as f64);
        }
        ms.renormalise();
        mp.renormalise();
    }
    let atten = exp4(im_delta.map(|v| -2.0 * v));
    let x = zip4(exit.n2, *sigma2, |a, b| a - b);
    let (u, v) = csqrt_up(x, exit.n2_im);
    let mut yp = ([0.0; 4], [0.0; 4]);
    for i in 0..4 {
        (yp.0[i], yp.1[i]) = cmul((u[i], v[i]), (exit.inv_n2[i], exit.inv_n2_im[i]));
    }
    let (r_s, t_s) = finish(&ms, &inc.y0_s, &(u, v), &atten);
    let (r_p, t_p) = finish(&mp, &inc.y0_p, &yp, &atten);
    [r_s, r_p, t_s, t_p]
}
