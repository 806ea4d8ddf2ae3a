//! The real-arithmetic kernel of the film-stack evaluator: characteristic matrices of lossless,
//! propagating layers at four wavelengths at once.
//!
//! For a lossless layer in which the wave propagates (n² > σ², σ = n_inc sin θ_inc), the phase
//! thickness δ and the admittance y are real, so M = [[cos δ, −i sin δ/y], [−i y sin δ, cos δ]]
//! has real diagonal and imaginary off-diagonal entries. Such matrices [[a, ib], [ic, d]] are
//! closed under multiplication,
//!
//! [[a, ib], [ic, d]]·[[a', ib'], [ic', d']] = [[aa' − bc', i(ab' + bd')], [i(ca' + dc'), dd' − cb']],
//!
//! so a product is kept as four reals per wavelength. With y = q = √(n² − σ²) for s and q/n² for
//! p (the dual form of [`super::charmatrix`]), b = −sin δ/q (times n² for p) and c = −q sin δ
//! (divided by n² for p). The exit medium (a dielectric, one beyond its critical angle, or a metal)
//! has a complex admittance u + iv and enters only at the end:
//!
//! B = (a − bv) + i bu,  C = du + i(c + dv),  r = (y₀B − C)/(y₀B + C),  T = 4y₀u/|y₀B + C|².
//!
//! For a lossless exit medium R + T = 1 to rounding, since det M = ad + bc = 1. Entries are kept
//! below 2^400 by exact power-of-two rescaling (a periodic group deep in its stop band grows as
//! e^{Nκ}); the exponent scales T only.
//!
//! Everything here is `#[inline(always)]` and branch-free inside the lane loops, so that the
//! caller's target features (SSE2, or AVX2 where detected) decide the vector width.

use super::simd4::{csqrt_up, sincos4, unit, zip4, F4};

/// One distinct layer at the four wavelengths.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LayerLanes {
    /// n² (real and imaginary parts).
    pub n2: F4,
    pub n2_im: F4,
    /// 1/n² (real and imaginary parts).
    pub inv_n2: F4,
    pub inv_n2_im: F4,
    /// 2π d·scale/λ.
    pub kd: F4,
    /// k = 0 at all four wavelengths.
    pub lossless: bool,
}

/// A run of `len` layers from `start`, repeated `count` times.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Group {
    pub start: u32,
    pub len: u32,
    pub count: u32,
}

impl Group {
    /// The `k`-th of `groups` in the order light meets them (`rev`: light from the base).
    #[inline(always)]
    pub(crate) fn nth(groups: &[Group], k: usize, rev: bool) -> Group {
        groups[if rev { groups.len() - 1 - k } else { k }]
    }

    /// Index of the group's `j`-th layer in the order light meets them.
    #[inline(always)]
    pub(crate) fn layer(&self, j: u32, rev: bool) -> usize {
        (if rev {
            self.start + self.len - 1 - j
        } else {
            self.start + j
        }) as usize
    }
}

/// The light meeting a stack at four wavelengths: from which side (`rev`: from the base, so
/// meeting the groups in reverse order), its tangential index squared σ², its incident
/// admittances for s and p, and the medium it leaves by.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Incidence<'a> {
    pub rev: bool,
    pub sigma2: F4,
    pub y0_s: F4,
    pub y0_p: F4,
    pub exit: &'a ExitLanes,
}

/// The exit medium at the four wavelengths: n² and 1/n².
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ExitLanes {
    pub n2: F4,
    pub n2_im: F4,
    pub inv_n2: F4,
    pub inv_n2_im: F4,
    pub lossless: bool,
}

/// [[a, ib], [ic, d]] · 2^e per lane.
#[derive(Clone, Copy)]
pub(crate) struct RealM {
    pub a: F4,
    pub b: F4,
    pub c: F4,
    pub d: F4,
    pub e: F4,
}

impl RealM {
    pub const I: RealM = RealM {
        a: [1.0; 4],
        b: [0.0; 4],
        c: [0.0; 4],
        d: [1.0; 4],
        e: [0.0; 4],
    };

    /// self · o.
    #[inline(always)]
    pub(crate) fn mul(&self, o: &RealM) -> RealM {
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

    /// self · [[cs, i·b], [i·c, cs]] (a layer's matrix), in place.
    #[inline(always)]
    fn mul_layer(&mut self, cs: &F4, b: &F4, c: &F4) {
        for i in 0..4 {
            let (a0, b0, c0, d0) = (self.a[i], self.b[i], self.c[i], self.d[i]);
            self.a[i] = a0 * cs[i] - b0 * c[i];
            self.b[i] = a0 * b[i] + b0 * cs[i];
            self.c[i] = c0 * cs[i] + d0 * c[i];
            self.d[i] = d0 * cs[i] - c0 * b[i];
        }
    }

    super::pow_by_squaring!(pub(crate));

    /// Keeps the entries below 2^400 (lanes whose product grew are divided by a power of two).
    #[inline(always)]
    pub(crate) fn renormalise(&mut self) {
        const BIG: f64 = 2.58e120; // ≈ 2^400
        let mut any = false;
        for i in 0..4 {
            any |= self.a[i].abs() > BIG
                || self.b[i].abs() > BIG
                || self.c[i].abs() > BIG
                || self.d[i].abs() > BIG;
        }
        if any {
            self.rescale();
        }
    }

    #[cold]
    fn rescale(&mut self) {
        for i in 0..4 {
            let big = [self.a[i], self.b[i], self.c[i], self.d[i]]
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            if big > 1.0 {
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

/// (R, T) from the product, incident admittance y0 and exit admittance u + iv.
#[inline(always)]
fn finish(m: &RealM, y0: &F4, u: &F4, v: &F4) -> (F4, F4) {
    let mut r = [0.0; 4];
    let mut t = [0.0; 4];
    for i in 0..4 {
        let (b_re, b_im) = (m.a[i] - m.b[i] * v[i], m.b[i] * u[i]);
        let (c_re, c_im) = (m.d[i] * u[i], m.c[i] + m.d[i] * v[i]);
        let (nr, ni) = (y0[i] * b_re - c_re, y0[i] * b_im - c_im);
        let (dr, di) = (y0[i] * b_re + c_re, y0[i] * b_im + c_im);
        // Divided by max(|dr|, |di|) first, so that |den|² cannot underflow (y0 → 0 at grazing
        // incidence, entries rescaled by 2^-e).
        let s = 1.0 / dr.abs().max(di.abs());
        let (nr, ni, dr, di) = (nr * s, ni * s, dr * s, di * s);
        let inv = 1.0 / (dr * dr + di * di);
        // min and `unit` (not clamp) also map a NaN from a degenerate 0/0 to a bound.
        r[i] = ((nr * nr + ni * ni) * inv).min(1.0);
        t[i] = unit(4.0 * (y0[i] * s) * (u[i] * s) * inv);
    }
    if m.e.iter().any(|&e| e != 0.0) {
        for (t, e) in t.iter_mut().zip(m.e) {
            *t *= 2f64.powf(-2.0 * e);
        }
    }
    (r, t)
}

/// A layer's matrix entries [cos δ, b_s, c_s, b_p, c_p] (see the module doc); `None` if the wave
/// does not propagate in it at some wavelength.
#[inline(always)]
fn entries(l: &LayerLanes, sigma2: &F4) -> Option<[F4; 5]> {
    let q2 = zip4(l.n2, *sigma2, |a, b| a - b);
    if !q2.iter().all(|&v| v > 0.0) {
        return None;
    }
    let q = q2.map(f64::sqrt);
    let (sn, cs) = sincos4(zip4(l.kd, q, |k, q| k * q));
    let mut e = [cs, [0.0; 4], [0.0; 4], [0.0; 4], [0.0; 4]];
    for i in 0..4 {
        let bs = -sn[i] / q[i];
        let cq = -sn[i] * q[i];
        e[1][i] = bs;
        e[2][i] = cq;
        e[3][i] = bs * l.n2[i];
        e[4][i] = cq * l.inv_n2[i];
    }
    Some(e)
}

/// (R_s, R_p, T_s, T_p) of the stack for the light `inc`. `None` if the wave does not
/// propagate in some layer (use the complex path).
#[inline(always)]
pub(crate) fn rt_real(layers: &[LayerLanes], groups: &[Group], inc: &Incidence) -> Option<[F4; 4]> {
    let (rev, sigma2, exit) = (inc.rev, &inc.sigma2, inc.exit);
    let (mut ms, mut mp) = (RealM::I, RealM::I);
    let n = groups.len();
    let mut since_check = 0;
    for k in 0..n {
        let g = Group::nth(groups, k, rev);
        let layer = |j: u32| &layers[g.layer(j, rev)];
        // Separate loops (rather than one loop writing through a reference chosen per group) keep
        // the lanes in vector registers.
        if g.count == 1 {
            for j in 0..g.len {
                let e = entries(layer(j), sigma2)?;
                ms.mul_layer(&e[0], &e[1], &e[2]);
                mp.mul_layer(&e[0], &e[3], &e[4]);
            }
            since_check += g.len;
        } else {
            let (mut ps, mut pp) = (RealM::I, RealM::I);
            for j in 0..g.len {
                let e = entries(layer(j), sigma2)?;
                ps.mul_layer(&e[0], &e[1], &e[2]);
                pp.mul_layer(&e[0], &e[3], &e[4]);
            }
            ms = ms.mul(&ps.pow(g.count));
            mp = mp.mul(&pp.pow(g.count));
            since_check = 16;
        }
        if since_check >= 16 {
            ms.renormalise();
            mp.renormalise();
            since_check = 0;
        }
    }
    let x = zip4(exit.n2, *sigma2, |a, b| a - b);
    let (r_s, t_s, r_p, t_p);
    if exit.lossless && x.iter().all(|&v| v > 0.0) {
        // A transparent exit medium below its critical angle: real admittances.
        let u = x.map(f64::sqrt);
        let up = zip4(u, exit.inv_n2, |a, b| a * b);
        (r_s, t_s) = finish(&ms, &inc.y0_s, &u, &[0.0; 4]);
        (r_p, t_p) = finish(&mp, &inc.y0_p, &up, &[0.0; 4]);
    } else {
        let (u, v) = csqrt_up(x, exit.n2_im);
        let mut up = [0.0; 4];
        let mut vp = [0.0; 4];
        for i in 0..4 {
            up[i] = u[i] * exit.inv_n2[i] - v[i] * exit.inv_n2_im[i];
            vp[i] = u[i] * exit.inv_n2_im[i] + v[i] * exit.inv_n2[i];
        }
        (r_s, t_s) = finish(&ms, &inc.y0_s, &u, &v);
        (r_p, t_p) = finish(&mp, &inc.y0_p, &up, &vp);
    }
    Some([r_s, r_p, t_s, t_p])
}
