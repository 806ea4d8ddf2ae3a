//! Rays and robust ray-origin offsetting.
//!
//! The offset follows Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
//! Ray Tracing Gems (2019), ch. 6: the origin is moved along the geometric normal by a number of
//! ulps that scales with the magnitude of the coordinates, so it works at any scene scale.

use crate::simd::{Float, Int, V3};
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
        Ray::new(spawn_origin(p.into(), ng.into(), d.into()).into(), d)
    }

    /// A shadow ray from surface point `p` (normal `ng`) towards `target`, stopping just short.
    #[inline]
    pub fn spawn_to(p: Vec3, ng: Vec3, target: Vec3) -> Ray {
        let (o, d, t_max) = spawn_to(p.into(), ng.into(), target.into());
        Ray {
            o: o.into(),
            d: d.into(),
            t_max,
        }
    }
}

/// The origin of [`Ray::spawn`] on lanes.
#[inline(always)]
pub fn spawn_origin<F: Float>(p: V3<F>, ng: V3<F>, d: V3<F>) -> V3<F> {
    let flip = ng.dot(d).lt(F::splat(0.0));
    offset_origin(p, V3::select(flip, -ng, ng))
}

/// [`Ray::spawn_to`] on lanes: (origin, unit direction, t_max).
#[inline(always)]
pub fn spawn_to<F: Float>(p: V3<F>, ng: V3<F>, target: V3<F>) -> (V3<F>, V3<F>, F) {
    let to = target - p;
    let flip = ng.dot(to).lt(F::splat(0.0));
    let o = offset_origin(p, V3::select(flip, -ng, ng));
    let d = target - o;
    let dist = d.length();
    (o, d / dist, dist * F::splat(1.0 - 1e-4))
}

const ORIGIN: f32 = 1.0 / 32.0;
const FLOAT_SCALE: f32 = 1.0 / 65536.0;
const INT_SCALE: f32 = 256.0;

/// Moves `p` off the surface along `n` (which must point to the side the new ray leaves into).
#[inline]
pub fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    offset_origin(p.into(), n.into()).into()
}

/// [`offset_ray_origin`] on lanes.
#[inline(always)]
pub fn offset_origin<F: Float>(p: V3<F>, n: V3<F>) -> V3<F> {
    #[inline(always)]
    fn one<F: Float>(p: F, n: F) -> F {
        let of_i = (F::splat(INT_SCALE) * n).to_int();
        let neg = p.lt(F::splat(0.0));
        let step = F::I::select(neg, F::I::splat(0) - of_i, of_i);
        let moved = F::from_bits(p.to_bits() + step);
        F::select(
            p.abs().lt(F::splat(ORIGIN)),
            p + F::splat(FLOAT_SCALE) * n,
            moved,
        )
    }
    V3::new(one(p.x, n.x), one(p.y, n.y), one(p.z, n.z))
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
