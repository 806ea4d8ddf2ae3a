//! Orthonormal frames for moving directions between world space and a z-up local space.
//!
//! The basis construction is the branchless one of Duff et al., "Building an Orthonormal Basis,
//! Revisited", JCGT 6(1), 2017.

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
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { s, t, n }
    }

    /// A frame with z axis `n` whose x axis is `dpdu` made orthogonal to `n` (Gram–Schmidt);
    /// falls back to [`Frame::from_z`] when `dpdu` is degenerate or parallel to `n`.
    #[inline]
    pub(crate) fn from_normal_tangent(n: Vec3, dpdu: Vec3) -> Frame {
        let s = dpdu - n * n.dot(dpdu);
        let len2 = s.length_squared();
        if !(len2 > 1e-12) || !len2.is_finite() {
            return Frame::from_z(n);
        }
        let s = s / len2.sqrt();
        Frame {
            s,
            t: n.cross(s),
            n,
        }
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
