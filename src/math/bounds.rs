//! Axis-aligned bounding boxes.

use glam::Vec3;

/// An axis-aligned box; the empty box has min = +∞, max = −∞.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds3 {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Bounds3 {
    fn default() -> Self {
        Bounds3::EMPTY
    }
}

impl Bounds3 {
    /// The empty box.
    pub(crate) const EMPTY: Bounds3 = Bounds3 {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The box holding one point.
    #[inline]
    pub(crate) fn from_point(p: Vec3) -> Bounds3 {
        Bounds3 { min: p, max: p }
    }

    /// Grows the box to include `p`.
    #[inline]
    pub(crate) fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// The union of two boxes.
    #[inline]
    pub(crate) fn union(&self, b: &Bounds3) -> Bounds3 {
        Bounds3 {
            min: self.min.min(b.min),
            max: self.max.max(b.max),
        }
    }

    /// Whether the box holds no point.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// Box centre.
    #[inline]
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Slab test against a ray given by origin and reciprocal direction; returns the entry and
    /// exit parameters clipped to `[0, t_max]` when the ray hits.
    #[inline]
    pub fn intersect(&self, o: Vec3, inv_d: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let t0 = (self.min - o) * inv_d;
        let t1 = (self.max - o) * inv_d;
        let tmin = t0.min(t1).max_element().max(0.0);
        // Slightly enlarge the exit distance to stay conservative (pbrt's 1 + 2γ3 factor).
        let tmax = t0.max(t1).min_element().min(t_max) * (1.0 + 3.0 * f32::EPSILON);
        if tmin <= tmax {
            Some((tmin, tmax))
        } else {
            None
        }
    }

    /// Bounding sphere (centre, radius).
    pub(crate) fn bounding_sphere(&self) -> (Vec3, f32) {
        if self.is_empty() {
            return (Vec3::ZERO, 0.0);
        }
        let c = self.center();
        (c, (self.max - c).length())
    }
}
