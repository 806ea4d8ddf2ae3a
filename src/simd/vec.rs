//! Vectors of lanes: [`V3`] and [`V2`] hold one [`Float`] per component, with the operations
//! in the same order as `glam`'s `Vec3`/`Vec2` (a dot product is `(x·x′ + y·y′) + z·z′`, a
//! normalisation multiplies by `1 / length`), so one lane reproduces glam's bits.
use super::Float;
use crate::math::{Vec2, Vec3};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Three lanes of vectors.
#[derive(Clone, Copy, Debug)]
pub struct V3<F> {
    pub x: F,
    pub y: F,
    pub z: F,
}

/// Two lanes of vectors.
#[derive(Clone, Copy, Debug)]
pub struct V2<F> {
    pub x: F,
    pub y: F,
}

impl<F: Float> V3<F> {
    #[inline(always)]
    pub fn new(x: F, y: F, z: F) -> Self {
        V3 { x, y, z }
    }
    /// The same vector in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        V3::new(F::splat(v.x), F::splat(v.y), F::splat(v.z))
    }
    #[inline(always)]
    pub fn dot(self, o: Self) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        V3::new(
            self.y * o.z - o.y * self.z,
            self.z * o.x - o.z * self.x,
            self.x * o.y - o.x * self.y,
        )
    }
    #[inline(always)]
    pub fn length_squared(self) -> F {
        self.dot(self)
    }
    #[inline(always)]
    pub fn length(self) -> F {
        self.dot(self).sqrt()
    }
    /// `self · (1 / |self|)`, as glam's `normalize`.
    #[inline(always)]
    pub fn normalize(self) -> Self {
        self * (F::splat(1.0) / self.length())
    }
    /// glam's `normalize_or_zero`: zero where 1/|self| is not a positive finite number.
    #[inline(always)]
    pub fn normalize_or_zero(self) -> Self {
        let rcp = F::splat(1.0) / self.length();
        let ok = rcp.is_finite() & rcp.gt(F::splat(0.0));
        let n = self * rcp;
        let z = F::splat(0.0);
        V3::new(
            F::select(ok, n.x, z),
            F::select(ok, n.y, z),
            F::select(ok, n.z, z),
        )
    }
    /// Component-wise absolute value.
    #[inline(always)]
    pub fn abs(self) -> Self {
        V3::new(self.x.abs(), self.y.abs(), self.z.abs())
    }
    /// `m ? a : b` per lane.
    #[inline(always)]
    pub fn select(m: F::M, a: Self, b: Self) -> Self {
        V3::new(
            F::select(m, a.x, b.x),
            F::select(m, a.y, b.y),
            F::select(m, a.z, b.z),
        )
    }
    /// Whether all three components are finite, per lane.
    #[inline(always)]
    pub fn is_finite(self) -> F::M {
        self.x.is_finite() & self.y.is_finite() & self.z.is_finite()
    }
    /// Whether the vector is exactly zero, per lane.
    #[inline(always)]
    pub fn is_zero(self) -> F::M {
        let z = F::splat(0.0);
        self.x.eq(z) & self.y.eq(z) & self.z.eq(z)
    }
    /// Lane `i` as a glam vector.
    #[inline(always)]
    pub fn lane(self, i: usize) -> Vec3 {
        Vec3::new(self.x.lane(i), self.y.lane(i), self.z.lane(i))
    }
    /// Components with `m` clear keep `self`, the others take `o`.
    #[inline(always)]
    pub fn blend(self, m: F::M, o: Self) -> Self {
        V3::select(m, o, self)
    }
}

impl<F: Float> V2<F> {
    #[inline(always)]
    pub fn new(x: F, y: F) -> Self {
        V2 { x, y }
    }
    #[inline(always)]
    pub fn length_squared(self) -> F {
        self.x * self.x + self.y * self.y
    }
    /// Lane `i` as a glam vector.
    #[inline(always)]
    pub fn lane(self, i: usize) -> Vec2 {
        Vec2::new(self.x.lane(i), self.y.lane(i))
    }
}

impl<F: Float> Add for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl<F: Float> Sub for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl<F: Float> Neg for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V3::new(-self.x, -self.y, -self.z)
    }
}
impl<F: Float> Mul<F> for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: F) -> Self {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
}
impl<F: Float> Div<F> for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn div(self, s: F) -> Self {
        V3::new(self.x / s, self.y / s, self.z / s)
    }
}

impl From<Vec3> for V3<f32> {
    #[inline(always)]
    fn from(v: Vec3) -> Self {
        V3::new(v.x, v.y, v.z)
    }
}
impl From<V3<f32>> for Vec3 {
    #[inline(always)]
    fn from(v: V3<f32>) -> Self {
        Vec3::new(v.x, v.y, v.z)
    }
}
impl From<Vec2> for V2<f32> {
    #[inline(always)]
    fn from(v: Vec2) -> Self {
        V2::new(v.x, v.y)
    }
}
impl From<V2<f32>> for Vec2 {
    #[inline(always)]
    fn from(v: V2<f32>) -> Self {
        Vec2::new(v.x, v.y)
    }
}
