//! Sampling warps from the unit square, each with its density (Shirley & Chiu 1997 for the
//! concentric disk; the rest are standard inversions, see pbrt-v4 ch. A.5).

use super::{safe_sqrt, INV_4PI, INV_PI, PI};
use glam::{Vec2, Vec3};

/// Uniform point on the unit disk (concentric mapping, low distortion).
#[inline]
pub(crate) fn square_to_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, PI / 4.0 * (o.y / o.x))
    } else {
        (o.y, PI / 2.0 - PI / 4.0 * (o.x / o.y))
    };
    let (s, c) = theta.sin_cos();
    Vec2::new(r * c, r * s)
}

/// Cosine-weighted direction on the upper (z > 0) hemisphere.
#[inline]
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_uniform_disk_concentric(u);
    let z = safe_sqrt(1.0 - d.length_squared());
    Vec3::new(d.x, d.y, z)
}

/// Density of [`square_to_cosine_hemisphere`] (solid angle).
#[inline]
pub(crate) fn square_to_cosine_hemisphere_pdf(v: Vec3) -> f32 {
    v.z.max(0.0) * INV_PI
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
pub(crate) fn square_to_uniform_triangle(u: Vec2) -> Vec2 {
    let (b0, b1);
    if u.x < u.y {
        b0 = u.x / 2.0;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.0;
        b0 = u.x - b1;
    }
    Vec2::new(b0, b1)
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
