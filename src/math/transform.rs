//! Affine transforms stored with their inverse.

use glam::{Mat3, Mat4, Vec3};

/// A 4×4 transform and its inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub m: Mat4,
    pub inv: Mat4,
}

impl Default for Transform {
    fn default() -> Self {
        Transform::IDENTITY
    }
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Transform = Transform {
        m: Mat4::IDENTITY,
        inv: Mat4::IDENTITY,
    };

    /// A transform from its matrix; `None` if it is singular or not finite.
    pub fn new(m: Mat4) -> Option<Transform> {
        let det = m.determinant();
        if !det.is_finite() || det.abs() < 1e-30 || !m.is_finite() {
            return None;
        }
        Some(Transform {
            m,
            inv: m.inverse(),
        })
    }

    /// Translation.
    pub fn translate(v: Vec3) -> Transform {
        Transform {
            m: Mat4::from_translation(v),
            inv: Mat4::from_translation(-v),
        }
    }

    /// Non-uniform scale; `None` if a factor is zero.
    pub fn scale(v: Vec3) -> Option<Transform> {
        Transform::new(Mat4::from_scale(v))
    }

    /// Rotation by `angle_deg` degrees about `axis` (right-handed); `None` for a zero axis.
    pub fn rotate(axis: Vec3, angle_deg: f32) -> Option<Transform> {
        let len = axis.length();
        if !(len > 0.0) || !angle_deg.is_finite() {
            return None;
        }
        let m = Mat4::from_axis_angle(axis / len, angle_deg.to_radians());
        Some(Transform {
            m,
            inv: m.transpose(),
        })
    }

    /// Camera-to-world "look at" transform with Mitsuba's convention: local +z looks at
    /// `target`, local +y is `up` made orthogonal, local +x = up × dir.
    pub(crate) fn look_at(origin: Vec3, target: Vec3, up: Vec3) -> Option<Transform> {
        let dir = (target - origin).normalize_or_zero();
        if dir == Vec3::ZERO {
            return None;
        }
        let left = up.normalize_or_zero().cross(dir);
        if left.length_squared() < 1e-12 {
            return None;
        }
        let left = left.normalize();
        let new_up = dir.cross(left);
        let m = Mat4::from_cols(
            left.extend(0.0),
            new_up.extend(0.0),
            dir.extend(0.0),
            origin.extend(1.0),
        );
        Transform::new(m)
    }

    /// `self` applied after `other` (`self ∘ other`).
    pub fn compose(&self, other: &Transform) -> Transform {
        Transform {
            m: self.m * other.m,
            inv: other.inv * self.inv,
        }
    }

    /// The inverse transform.
    pub(crate) fn inverse(&self) -> Transform {
        Transform {
            m: self.inv,
            inv: self.m,
        }
    }

    /// Transforms a point.
    #[inline]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.m.transform_point3(p)
    }

    /// [`Transform::point`] on lanes (glam's operation order: the columns scaled by x, y, z
    /// summed in turn, the translation added last).
    #[inline(always)]
    pub fn point_lanes<F: crate::simd::Float>(&self, p: crate::simd::V3<F>) -> crate::simd::V3<F> {
        let v = self.vector_lanes(p);
        let w = self.m.w_axis;
        crate::simd::V3::new(
            F::splat(w.x) + v.x,
            F::splat(w.y) + v.y,
            F::splat(w.z) + v.z,
        )
    }

    /// [`Transform::vector`] on lanes.
    #[inline(always)]
    pub fn vector_lanes<F: crate::simd::Float>(&self, v: crate::simd::V3<F>) -> crate::simd::V3<F> {
        #[inline(always)]
        fn row<F: crate::simd::Float>(a: f32, b: f32, c: f32, v: crate::simd::V3<F>) -> F {
            F::splat(c) * v.z + (F::splat(b) * v.y + F::splat(a) * v.x)
        }
        let (x, y, z) = (self.m.x_axis, self.m.y_axis, self.m.z_axis);
        crate::simd::V3::new(
            row(x.x, y.x, z.x, v),
            row(x.y, y.y, z.y, v),
            row(x.z, y.z, z.z, v),
        )
    }

    /// Transforms a direction (no translation).
    #[inline]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.m.transform_vector3(v)
    }

    /// Transforms a surface normal (inverse transpose); the result is not normalised.
    #[inline]
    pub fn normal(&self, n: Vec3) -> Vec3 {
        Mat3::from_mat4(self.inv).transpose() * n
    }

    /// Whether the transform flips handedness (negative determinant).
    pub(crate) fn swaps_handedness(&self) -> bool {
        Mat3::from_mat4(self.m).determinant() < 0.0
    }

    /// Whether this is (numerically) the identity.
    pub(crate) fn is_identity(&self) -> bool {
        self.m.abs_diff_eq(Mat4::IDENTITY, 1e-7)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_points_z_at_target() {
        let t = Transform::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y).unwrap();
        let d = t.vector(Vec3::Z);
        assert!((d - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert!((t.vector(Vec3::Y) - Vec3::Y).length() < 1e-6);
        assert!((t.point(Vec3::ZERO) - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-6);
    }

    #[test]
    fn normals_stay_perpendicular_under_nonuniform_scale() {
        let t = Transform::scale(Vec3::new(1.0, 4.0, 1.0)).unwrap();
        let tangent = t.vector(Vec3::new(1.0, -1.0, 0.0));
        let n = t.normal(Vec3::new(1.0, 1.0, 0.0));
        assert!(tangent.dot(n).abs() < 1e-5);
    }
}
