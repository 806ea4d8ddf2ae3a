//! Analytic disk (stub API; implemented by the geometry work).
use super::{Hit, ShapeSample, SurfaceInteraction};
use crate::math::{Bounds3, Ray, Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct Disk {
    pub to_world: crate::math::Transform,
    pub flip_normals: bool,
}
impl Disk {
    pub fn bounds(&self) -> Bounds3 {
        todo!()
    }
    pub fn intersect(&self, _ray: &Ray) -> Option<(f32, Vec2)> {
        todo!()
    }
    pub fn interaction(&self, _hit: &Hit, _ray: &Ray) -> SurfaceInteraction {
        todo!()
    }
    pub fn area(&self) -> f32 {
        todo!()
    }
    pub fn sample_direct(&self, _ref_p: Vec3, _u: Vec2) -> Option<ShapeSample> {
        todo!()
    }
    pub fn pdf_direct(&self, _ref_p: Vec3, _p: Vec3, _n: Vec3) -> f32 {
        todo!()
    }
}
