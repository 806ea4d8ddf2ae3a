//! Rays and robust ray-origin offsetting.
//!
//! The offset follows Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
//! Ray Tracing Gems (2019), ch. 6: the origin is moved along the geometric normal by a number of
//! ulps that scales with the magnitude of the coordinates, so it works at any scene scale.

use glam::Vec3;

/// A ray with origin `o`, unit direction `d`, and a parametric extent `[0, t_max)`.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub o: Vec3,
    pub d: Vec3,
    pub t_max: f32,
}

impl Ray {
    /// A ray of infinite extent.
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Ray {
        Ray {
            o,
            d,
            t_max: f32::INFINITY,
        }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + self.d * t
    }

    /// A ray leaving surface point `p` with geometric normal `ng` in direction `d`, offset to the
    /// side of the surface that `d` points into.
    #[inline]
    pub fn spawn(p: Vec3, ng: Vec3, d: Vec3) -> Ray {
        let n = if ng.dot(d) < 0.0 { -ng } else { ng };
        Ray::new(offset_ray_origin(p, n), d)
    }

    /// A shadow ray from surface point `p` (normal `ng`) towards `target`, stopping just short.
    #[inline]
    pub fn spawn_to(p: Vec3, ng: Vec3, target: Vec3) -> Ray {
        let to = target - p;
        let n = if ng.dot(to) < 0.0 { -ng } else { ng };
        let o = offset_ray_origin(p, n);
        let d = target - o;
        let dist = d.length();
        Ray {
            o,
            d: d / dist,
            t_max: dist * (1.0 - 1e-4),
        }
    }
}

const ORIGIN: f32 = 1.0 / 32.0;
const FLOAT_SCALE: f32 = 1.0 / 65536.0;
const INT_SCALE: f32 = 256.0;

/// Moves `p` off the surface along `n` (which must point to the side the new ray leaves into).
#[inline]
pub fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    #[inline]
    fn one(p: f32, n: f32) -> f32 {
        let of_i = (INT_SCALE * n) as i32;
        let bits = p.to_bits() as i32;
        let moved = f32::from_bits((bits + if p < 0.0 { -of_i } else { of_i }) as u32);
        if p.abs() < ORIGIN {
            p + FLOAT_SCALE * n
        } else {
            moved
        }
    }
    Vec3::new(one(p.x, n.x), one(p.y, n.y), one(p.z, n.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_normal_side_at_all_scales() {
        for &scale in &[1e-3f32, 1.0, 1e3, 1e5] {
            let p = Vec3::new(0.3, -0.7, 0.2) * scale;
            let n = Vec3::new(0.0, 0.6, 0.8);
            let q = offset_ray_origin(p, n);
            assert!((q - p).dot(n) > 0.0, "scale {scale}");
            assert!((q - p).length() < 1e-3 * scale.max(1.0));
        }
    }
}
