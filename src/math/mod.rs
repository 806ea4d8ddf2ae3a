//! Geometry and sampling primitives: vectors (glam), frames, rays, bounds, transforms, warps, RNG.

pub mod bounds;
pub mod frame;
pub mod ray;
pub mod rng;
pub mod transform;
pub mod warp;

pub(crate) use bounds::Bounds3;
pub use frame::Frame;
pub use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
pub use ray::{offset_ray_origin, Ray};
pub use rng::Pcg32;
pub use transform::Transform;

/// π as f32.
pub(crate) const PI: f32 = std::f32::consts::PI;
/// 1/π.
pub(crate) const INV_PI: f32 = std::f32::consts::FRAC_1_PI;
/// 1/(2π).
pub(crate) const INV_2PI: f32 = 0.5 * std::f32::consts::FRAC_1_PI;
/// 1/(4π).
pub(crate) const INV_4PI: f32 = 0.25 * std::f32::consts::FRAC_1_PI;

/// Largest f32 strictly below 1, so that samples stay in [0, 1).
pub(crate) const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// sqrt that returns 0 for (slightly) negative arguments produced by rounding.
#[inline]
pub(crate) fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// acos clamped to the valid domain.
#[inline]
pub(crate) fn safe_acos(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).acos()
}

/// Reflects `w` about the normal `n` (both pointing away from the surface).
#[inline]
pub(crate) fn reflect(w: Vec3, n: Vec3) -> Vec3 {
    2.0 * w.dot(n) * n - w
}

/// Refracts `wi` (pointing away from the surface, on the side of `n`) through an interface with
/// relative index `eta` = n_transmitted / n_incident. Returns `None` on total internal reflection.
#[inline]
pub(crate) fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = n.dot(wi);
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    Some(-wi / eta + (cos_i / eta - cos_t) * n)
}

/// The bracket [lo, hi] around where an increasing `f` reaches `target`, after `steps` halvings
/// of the starting bracket: each step keeps the half whose lower end has f < target.
pub fn bisect_increasing(
    f: impl Fn(f64) -> f64,
    target: f64,
    (mut lo, mut hi): (f64, f64),
    steps: u32,
) -> (f64, f64) {
    for _ in 0..steps {
        let mid = 0.5 * (lo + hi);
        if f(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo, hi)
}

/// Power heuristic with β = 2 for multiple importance sampling (Veach 1997).
#[inline]
pub fn power_heuristic(f_pdf: f32, g_pdf: f32) -> f32 {
    power_heuristic_lanes(f_pdf, g_pdf)
}

/// [`power_heuristic`] on lanes.
#[inline(always)]
pub fn power_heuristic_lanes<F: crate::simd::Float>(f_pdf: F, g_pdf: F) -> F {
    let f = f_pdf * f_pdf;
    let g = g_pdf * g_pdf;
    let sum = f + g;
    let w = F::select(sum.eq(F::splat(0.0)), F::splat(0.0), f / sum);
    F::select(f.eq(F::splat(f32::INFINITY)), F::splat(1.0), w)
}

#[cfg(test)]
/// Spherical direction from angles (z-up).
#[inline]
pub(crate) fn spherical_direction(sin_theta: f32, cos_theta: f32, phi: f32) -> Vec3 {
    let (s, c) = phi.sin_cos();
    Vec3::new(
        sin_theta.clamp(-1.0, 1.0) * c,
        sin_theta.clamp(-1.0, 1.0) * s,
        cos_theta.clamp(-1.0, 1.0),
    )
}
