//! Sampling warps from the unit square, each with its density (Shirley & Chiu 1997 for the
//! concentric disk; the rest are standard inversions, see pbrt-v4 ch. A.5).

use super::{safe_sqrt, INV_4PI, INV_PI, PI};
use crate::simd::fastmath::sin_cos;
use crate::simd::{Float, V3};
use glam::{Vec2, Vec3};

/// Uniform point on the unit disk (concentric mapping, low distortion).
#[inline]
pub fn square_to_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let (x, y) = disk_concentric(u.x, u.y);
    Vec2::new(x, y)
}

/// [`square_to_uniform_disk_concentric`] on lanes.
#[inline(always)]
pub fn disk_concentric<F: Float>(ux: F, uy: F) -> (F, F) {
    let one = F::splat(1.0);
    let zero = F::splat(0.0);
    let ox = F::splat(2.0) * ux - one;
    let oy = F::splat(2.0) * uy - one;
    let centre = ox.eq(zero) & oy.eq(zero);
    let wide = ox.abs().gt(oy.abs());
    let r = F::select(wide, ox, oy);
    let theta = F::select(
        wide,
        F::splat(PI / 4.0) * (oy / ox),
        F::splat(PI / 2.0) - F::splat(PI / 4.0) * (ox / oy),
    );
    let (s, c) = sin_cos(theta);
    (
        F::select(centre, zero, r * c),
        F::select(centre, zero, r * s),
    )
}

/// Cosine-weighted direction on the upper (z > 0) hemisphere.
#[inline]
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    cosine_hemisphere(u.x, u.y).into()
}

/// [`square_to_cosine_hemisphere`] on lanes.
#[inline(always)]
pub fn cosine_hemisphere<F: Float>(ux: F, uy: F) -> V3<F> {
    let (x, y) = disk_concentric(ux, uy);
    let z = (F::splat(1.0) - (x * x + y * y)).safe_sqrt();
    V3::new(x, y, z)
}

/// Density of [`square_to_cosine_hemisphere`] (solid angle).
#[inline]
pub fn square_to_cosine_hemisphere_pdf(v: Vec3) -> f32 {
    cosine_hemisphere_pdf(v.z)
}

/// [`square_to_cosine_hemisphere_pdf`] on lanes, from the direction's z.
#[inline(always)]
pub fn cosine_hemisphere_pdf<F: Float>(z: F) -> F {
    z.max(F::splat(0.0)) * F::splat(INV_PI)
}

/// Uniform direction on the unit sphere.
#[inline]
pub(crate) fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = safe_sqrt(1.0 - z * z);
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`square_to_uniform_sphere`].
#[inline]
pub(crate) fn square_to_uniform_sphere_pdf() -> f32 {
    INV_4PI
}

#[cfg(test)]
/// Uniform direction in the cone around +z with cos(half-angle) = `cos_max`.
#[inline]
pub(crate) fn square_to_uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let cos_t = (1.0 - u.x) + u.x * cos_max;
    let sin_t = safe_sqrt(1.0 - cos_t * cos_t);
    let phi = 2.0 * PI * u.y;
    Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// Uniform barycentric coordinates (b0, b1) on a triangle (Heitz 2019, "A Low-Distortion Map
/// Between Triangle and Square"); b2 = 1 − b0 − b1.
#[inline]
pub fn square_to_uniform_triangle(u: Vec2) -> Vec2 {
    let (b0, b1) = uniform_triangle(u.x, u.y);
    Vec2::new(b0, b1)
}

/// [`square_to_uniform_triangle`] on lanes.
#[inline(always)]
pub fn uniform_triangle<F: Float>(ux: F, uy: F) -> (F, F) {
    let first = ux.lt(uy);
    let half = F::splat(2.0);
    let (a0, a1) = (ux / half, uy / half);
    let b0 = F::select(first, a0, ux - a1);
    let b1 = F::select(first, uy - a0, a1);
    (b0, b1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;

    #[test]
    fn warps_land_in_their_domain() {
        let mut rng = Pcg32::new(3, 0);
        for _ in 0..10_000 {
            let u = rng.next_vec2();
            let d = square_to_uniform_disk_concentric(u);
            assert!(d.length() <= 1.0 + 1e-6);
            let h = square_to_cosine_hemisphere(u);
            assert!(h.z >= 0.0 && (h.length() - 1.0).abs() < 1e-5);
            let s = square_to_uniform_sphere(u);
            assert!((s.length() - 1.0).abs() < 1e-5);
            let c = square_to_uniform_cone(u, 0.8);
            assert!(c.z >= 0.8 - 1e-6);
            let b = square_to_uniform_triangle(u);
            assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
        }
    }

    #[test]
    fn cosine_hemisphere_mean_cosine() {
        // E[cos θ] under the cosine density is 2/3; variance of cos is 1/2 − 4/9 = 1/18.
        let mut rng = Pcg32::new(5, 0);
        let n = 200_000;
        let m: f64 = (0..n)
            .map(|_| square_to_cosine_hemisphere(rng.next_vec2()).z as f64)
            .sum::<f64>()
            / n as f64;
        let sigma = (1.0f64 / 18.0 / n as f64).sqrt();
        assert!((m - 2.0 / 3.0).abs() < 4.0 * sigma, "{m}");
    }
}
