//! The characteristic-matrix (transfer-matrix) method for a stack of layers, exactly, in complex
//! f64, one wavelength at a time: the reference the fast path and the single-film code are tested
//! against, and the fast path's fallback for absorbing or evanescent layers.
//!
//! Model (Born & Wolf, *Principles of Optics*, §1.6.2–1.6.5; Macleod, *Thin-Film Optical
//! Filters*, ch. 2). Light arrives from a lossless medium n_inc at angle θ_inc; its tangential
//! index σ = n_inc sin θ_inc is the same in every layer. In layer j (index n_j, thickness d_j)
//! the normal wave number is q_j = n_j cos θ_j = √(n_j² − σ²) on the branch Im q ≥ 0 (decaying or
//! forward-propagating; Re q ≥ 0 when Im q = 0), and the phase thickness is δ_j = 2π d_j q_j / λ.
//! The tangential fields at the two faces of layer j are related by
//!
//! M_j = [[cos δ, −i sin δ / y], [−i y sin δ, cos δ]],
//!
//! with the tilted admittance y = q for s (fields E_t, H_t) and y = q / n² for p — the dual form,
//! relating H_t and E_t, so that at grazing incidence y → 0 instead of ∞. With
//! [B, C]ᵀ = M_1 ⋯ M_N [1, y_exit]ᵀ:
//!
//! r = (y_inc B − C)/(y_inc B + C),  T = 4 y_inc Re(y_exit) / |y_inc B + C|²,  A = 1 − R − T.
//!
//! These are the `tmm` package's conventions exactly (Byrnes 2016, arXiv:1603.02720): time
//! dependence e^{−iωt}, k ≥ 0 absorbing, r_s = (n_i cos θ_i − n_f cos θ_f)/(…+…), r_p = (n_f cos θ_i
//! − n_i cos θ_f)/(…+…) (the ratio of H amplitudes, which equals tmm's ratio of E amplitudes for
//! reflection), T_s ∝ Re(n_f cos θ_f), T_p ∝ Re(n_f cos θ_f*); the transmitted amplitude t is
//! returned as tmm's E-field ratio.
//!
//! Numerically stable form: cos δ and sin δ grow as e^{Im δ} in an evanescent or absorbing layer
//! and overflow for thick ones. Each matrix is therefore multiplied by e^{iδ} (|e^{iδ}| ≤ 1), which
//! leaves r unchanged and scales t by a factor tracked separately:
//!
//! e^{iδ} M = [[(1 + w)/2, g·(y_s/y)], [y·y_s·g, (1 + w)/2]],  w = e^{2iδ},  g = (1 − w)/(2q),
//!
//! where every entry is bounded (|w| ≤ 1). g = −i (2π d/λ) (e^z − 1)/z with z = 2iδ is evaluated
//! through expm1, so it has no 0/0 at q = 0 (a layer at its critical angle) or d = 0. A product
//! that still grows (a deep stop band of many periods) is rescaled by exact powers of two.
//! Exactly grazing incidence (cos θ_inc = 0) reflects everything: R = 1, T = 0.

use super::thinfilm::FilmRt;
use num_complex::Complex64 as C;

/// One layer at one wavelength: n² and the vacuum wave number times thickness, 2π d/λ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LayerAt {
    pub n2: C,
    pub kd: f64,
}

/// Complex reflection and transmission amplitudes (tmm's conventions, see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Amplitudes {
    pub r_s: C,
    pub r_p: C,
    pub t_s: C,
    pub t_p: C,
}

/// A 2×2 complex matrix [[a, b], [c, d]] and a power-of-two exponent: value = 2^exp · M.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scaled2 {
    pub m: [C; 4],
    pub exp: i32,
}

impl Scaled2 {
    pub const IDENTITY: Scaled2 = Scaled2 {
        m: [
            C::new(1.0, 0.0),
            C::new(0.0, 0.0),
            C::new(0.0, 0.0),
            C::new(1.0, 0.0),
        ],
        exp: 0,
    };

    /// self · o, renormalised when the entries leave [2^-400, 2^400].
    #[inline]
    pub(crate) fn mul(&self, o: &Scaled2) -> Scaled2 {
        let [a, b, c, d] = self.m;
        let [e, f, g, h] = o.m;
        let mut out = Scaled2 {
            m: [a * e + b * g, a * f + b * h, c * e + d * g, c * f + d * h],
            exp: self.exp + o.exp,
        };
        out.renormalise();
        out
    }

    #[inline]
    fn renormalise(&mut self) {
        let big = self
            .m
            .iter()
            .fold(0.0f64, |m, z| m.max(z.re.abs()).max(z.im.abs()));
        if big > 2f64.powi(400) || (big < 2f64.powi(-400) && big > 0.0) {
            let e = big.log2().round() as i32;
            let f = 2f64.powi(-e);
            for z in &mut self.m {
                *z *= f;
            }
            self.exp += e;
        }
    }
}

/// q = √(n² − σ²) on the branch Im q ≥ 0 (Re q ≥ 0 when real).
#[inline]
pub(crate) fn normal_q(n2: C, sigma2: f64) -> C {
    let q = (n2 - sigma2).sqrt();
    if q.im < 0.0 {
        -q
    } else {
        q
    }
}

/// (e^z − 1)/z, accurate for every z (1 at z = 0).
#[inline]
fn expm1_over_z(z: C) -> C {
    if z == C::new(0.0, 0.0) {
        return C::new(1.0, 0.0);
    }
    // e^{a+ib} − 1 = (e^a − 1) cos b − 2 sin²(b/2) + i e^a sin b: no cancellation near 0.
    let (sb, cb) = z.im.sin_cos();
    let h = (0.5 * z.im).sin();
    let em1 = C::new(z.re.exp_m1() * cb - 2.0 * h * h, z.re.exp() * sb);
    em1 / z
}

/// The scaled matrices e^{iδ}M of one layer for s and p, and δ itself.
#[inline]
pub(crate) fn layer_matrices(layer: LayerAt, sigma2: f64) -> (Scaled2, Scaled2, C) {
    let q = normal_q(layer.n2, sigma2);
    let q2 = layer.n2 - sigma2;
    let delta = q * layer.kd;
    let iz = C::new(-2.0 * delta.im, 2.0 * delta.re); // 2iδ
    let w = iz.exp();
    let h = (C::new(1.0, 0.0) + w) * 0.5;
    let g = C::new(0.0, -layer.kd) * expm1_over_z(iz);
    let s = Scaled2 {
        m: [h, g, q2 * g, h],
        exp: 0,
    };
    let p = Scaled2 {
        m: [h, layer.n2 * g, q2 * g / layer.n2, h],
        exp: 0,
    };
    (s, p, delta)
}

/// The stack's total scaled matrices for s and p, and the total phase Σδ.
pub(crate) struct StackMatrices {
    pub s: Scaled2,
    pub p: Scaled2,
    pub phase: C,
}

/// Multiplies the layers in the order given (the first is next to the incident medium).
pub(crate) fn product(layers: impl Iterator<Item = LayerAt>, sigma2: f64) -> StackMatrices {
    let mut out = StackMatrices {
        s: Scaled2::IDENTITY,
        p: Scaled2::IDENTITY,
        phase: C::new(0.0, 0.0),
    };
    for l in layers {
        let (s, p, d) = layer_matrices(l, sigma2);
        out.s = out.s.mul(&s);
        out.p = out.p.mul(&p);
        out.phase += d;
    }
    out
}

/// R, T and the amplitudes from the product, for incident index `n_inc` (real) at `cos_inc`
/// and exit medium `n_exit` (n² given).
pub fn finish(
    m: &StackMatrices,
    n_inc: f64,
    cos_inc: f64,
    sigma2: f64,
    n_exit: C,
) -> (FilmRt, Amplitudes) {
    let q_exit = normal_q(n_exit * n_exit, sigma2);
    // |e^{iΣδ}| and its phase, and the 2^exp scale of the product (the same for s and p
    // up to the exponents), for the transmitted amplitude.
    let prop = (C::i() * m.phase).exp();
    let one = |mm: &Scaled2, y_inc: f64, y_exit: C| {
        let [a, b, c, d] = mm.m;
        let bb = a + b * y_exit;
        let cc = c + d * y_exit;
        // Divided by max(|Re|, |Im|) of the denominator first, so that |den|² cannot underflow
        // (y_inc → 0 at grazing incidence).
        let den = bb * y_inc + cc;
        let s = 1.0 / den.re.abs().max(den.im.abs());
        let (den, num) = (den * s, (bb * y_inc - cc) * s);
        let r = num / den;
        let t = prop * (2.0 * y_inc * s) / den * 2f64.powi(-mm.exp);
        let t_pow = 4.0 * (y_inc * s) * (y_exit.re * s) / den.norm_sqr()
            * prop.norm_sqr()
            * 2f64.powi(-2 * mm.exp);
        (r, t, t_pow)
    };
    let (r_s, t_s, ts) = one(&m.s, n_inc * cos_inc, q_exit);
    let (r_p, t_h, tp) = one(&m.p, cos_inc / n_inc, q_exit / (n_exit * n_exit));
    // A NaN can only come from a degenerate 0/0 (no interface at exactly grazing incidence).
    let fin = super::simd4::unit;
    let amp = Amplitudes {
        r_s,
        r_p,
        t_s,
        // tmm's p amplitude is the ratio of E fields: H = n E for a plane wave.
        t_p: t_h * n_inc / n_exit,
    };
    (
        FilmRt {
            r_s: fin(r_s.norm_sqr()),
            r_p: fin(r_p.norm_sqr()),
            t_s: fin(ts),
            t_p: fin(tp),
        },
        amp,
    )
}

/// The whole computation for one wavelength: layers in order from the incident medium.
pub(crate) fn stack_rt(
    n_inc: f64,
    cos_inc: f64,
    layers: impl Iterator<Item = LayerAt>,
    n_exit: C,
) -> (FilmRt, Amplitudes) {
    let cos = if cos_inc.is_nan() {
        0.0
    } else {
        cos_inc.clamp(0.0, 1.0)
    };
    if cos == 0.0 {
        let minus = C::new(-1.0, 0.0);
        let zero = C::new(0.0, 0.0);
        return (
            FilmRt {
                r_s: 1.0,
                r_p: 1.0,
                t_s: 0.0,
                t_p: 0.0,
            },
            Amplitudes {
                r_s: minus,
                r_p: minus,
                t_s: zero,
                t_p: zero,
            },
        );
    }
    let sigma2 = n_inc * n_inc * (1.0 - cos * cos);
    let m = product(layers, sigma2);
    finish(&m, n_inc, cos, sigma2, n_exit)
}
