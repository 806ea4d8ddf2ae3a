//! Orthonormal frames for moving directions between world space and a z-up local space.
//!
//! The basis construction is the branchless one of Duff et al., "Building an Orthonormal Basis,
//! Revisited", JCGT 6(1), 2017.

use crate::simd::{Float, Mask, V3};
use glam::Vec3;

/// An orthonormal basis (s, t, n) with n as the local z axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// A frame whose z axis is the unit vector `n`.
    #[inline]
    pub fn from_z(n: Vec3) -> Frame {
        FrameL::from_z(n.into()).into()
    }

    /// A frame with z axis `n` whose x axis is `dpdu` made orthogonal to `n` (Gram–Schmidt);
    /// falls back to [`Frame::from_z`] when `dpdu` is degenerate or parallel to `n`.
    #[inline]
    pub fn from_normal_tangent(n: Vec3, dpdu: Vec3) -> Frame {
        FrameL::from_normal_tangent(n.into(), dpdu.into()).into()
    }

    /// World → local.
    #[inline]
    pub(crate) fn to_local(self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local → world.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// [`Frame`] on lanes: the same constructions, operation for operation.
#[derive(Clone, Copy, Debug)]
pub struct FrameL<F> {
    pub s: V3<F>,
    pub t: V3<F>,
    pub n: V3<F>,
}

impl<F: Float> FrameL<F> {
    /// [`Frame::from_z`].
    #[inline(always)]
    pub fn from_z(n: V3<F>) -> Self {
        let one = F::splat(1.0);
        let sign = one.copysign(n.z);
        let a = -one / (sign + n.z);
        let b = n.x * n.y * a;
        let s = V3::new(one + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = V3::new(b, sign + n.y * n.y * a, -n.y);
        FrameL { s, t, n }
    }

    /// [`Frame::from_normal_tangent`].
    #[inline(always)]
    pub fn from_normal_tangent(n: V3<F>, dpdu: V3<F>) -> Self {
        let s = dpdu - n * n.dot(dpdu);
        let len2 = s.length_squared();
        let s = s / len2.sqrt();
        let ok = len2.gt(F::splat(1e-12)) & len2.is_finite();
        let z = Self::from_z(n);
        if !ok.any() {
            return z;
        }
        let t = n.cross(s);
        FrameL {
            s: V3::select(ok, s, z.s),
            t: V3::select(ok, t, z.t),
            n,
        }
    }

    /// World → local.
    #[inline(always)]
    pub fn to_local(&self, v: V3<F>) -> V3<F> {
        V3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local → world.
    #[inline(always)]
    pub fn to_world(&self, v: V3<F>) -> V3<F> {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

impl From<FrameL<f32>> for Frame {
    #[inline(always)]
    fn from(f: FrameL<f32>) -> Frame {
        Frame {
            s: f.s.into(),
            t: f.t.into(),
            n: f.n.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal_and_round_trip() {
        let mut rng = crate::math::Pcg32::new(7, 1);
        for _ in 0..1000 {
            let n = crate::math::warp::square_to_uniform_sphere(rng.next_vec2());
            let f = Frame::from_z(n);
            assert!((f.s.length() - 1.0).abs() < 1e-5);
            assert!((f.t.length() - 1.0).abs() < 1e-5);
            assert!(f.s.dot(f.t).abs() < 1e-5 && f.s.dot(f.n).abs() < 1e-5);
            assert!((f.s.cross(f.t) - f.n).length() < 1e-4, "right-handed");
            let v = Vec3::new(0.3, -0.2, 0.9);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-5);
        }
    }
}
