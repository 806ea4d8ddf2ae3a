//! `orthographic`: a camera without perspective (Mitsuba's `orthographic` sensor) — a planar
//! sensor that measures radiance along its normal.
//!
//! Model. In camera space the sensor is the rectangle x ∈ [−1, 1], y ∈ [−1/a, 1/a] (a = width /
//! height) on the near plane z = `near_clip`; every ray leaves it along +z. As with
//! `perspective`, local +x is the left of the image. The sensor's size is set by scaling
//! `to_world` (e.g. `<scale x="10" y="10"/>` before the `lookat` makes it 20 units wide), as in
//! Mitsuba.
//!
//! | XML name    | type      | default | unit        | meaning                                   |
//! |-------------|-----------|---------|-------------|-------------------------------------------|
//! | `near_clip` | float     | 0.01    | camera units| where rays start (along the view axis)    |
//! | `far_clip`  | float     | 10000   | camera units| where rays end                            |
//! | `to_world`  | transform | identity| —           | camera-to-world, its scale sizing the sensor |
//!
//! Limits: the pixel footprint for texture filtering is the pixel's width on the sensor at every
//! distance (exact for this projection, but it ignores the surface's slant).

use crate::math::{Ray, Transform, Vec2, Vec3};

/// An orthographic camera.
#[derive(Clone, Debug)]
pub struct OrthographicCamera {
    pub to_world: Transform,
    /// Half extent of the sensor in camera space: (1, 1/aspect).
    half: Vec2,
    pub near_clip: f32,
    pub far_clip: f32,
}

impl OrthographicCamera {
    /// An orthographic camera for a `width`×`height` image.
    pub fn new(
        to_world: Transform,
        width: u32,
        height: u32,
        near_clip: f32,
        far_clip: f32,
    ) -> OrthographicCamera {
        let aspect = width.max(1) as f32 / height.max(1) as f32;
        OrthographicCamera {
            to_world,
            half: Vec2::new(1.0, 1.0 / aspect),
            near_clip,
            far_clip,
        }
    }

    /// The ray from film point `film` ∈ [0,1]² (x right, y down).
    #[inline]
    pub fn generate_ray(&self, film: Vec2) -> Ray {
        let p = Vec3::new(
            (1.0 - 2.0 * film.x) * self.half.x,
            (1.0 - 2.0 * film.y) * self.half.y,
            self.near_clip,
        );
        let axis = self.to_world.vector(Vec3::Z);
        let scale = axis.length();
        Ray {
            o: self.to_world.point(p),
            d: axis / scale,
            t_max: (self.far_clip - self.near_clip) * scale,
        }
    }

    /// Width of one pixel on the sensor, in world units, for an image `height` pixels tall.
    pub fn pixel_width(&self, height: u32) -> f32 {
        let up = self.to_world.vector(Vec3::new(0.0, 2.0 * self.half.y, 0.0));
        up.length() / height.max(1) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;

    #[test]
    fn rays_are_parallel_and_leave_the_scaled_sensor() {
        let s = Transform::scale(Vec3::new(10.0, 10.0, 1.0)).unwrap();
        let l = Transform::look_at(Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, 2.0, 1.0), Vec3::Z)
            .unwrap();
        let cam = OrthographicCamera::new(l.compose(&s), 400, 200, 0.01, 100.0);
        let mut rng = Pcg32::new(5, 5);
        let centre = cam.generate_ray(Vec2::splat(0.5));
        assert!((centre.d - Vec3::Y).length() < 1e-6);
        for _ in 0..100 {
            let r = cam.generate_ray(rng.next_vec2());
            assert!((r.d - centre.d).length() < 1e-6, "not parallel");
            // On the sensor plane through the near point: no offset along the view axis.
            assert!(((r.o - centre.o).dot(r.d)).abs() < 1e-4);
        }
        // 20 units wide and, at 2:1, 10 tall: corners at ±10 along x' and ±5 along up (+z).
        let c = cam.generate_ray(Vec2::ZERO).o - centre.o;
        assert!((c.z - 5.0).abs() < 1e-4, "{c}");
        assert!((c.x.abs() - 10.0).abs() < 1e-4, "{c}");
        assert!((cam.pixel_width(200) - 0.05).abs() < 1e-6);
    }

    #[test]
    fn image_is_not_mirrored() {
        // Same handedness as `perspective`: the left of the image is local +x.
        let cam = OrthographicCamera::new(Transform::IDENTITY, 100, 100, 0.01, 100.0);
        assert!(cam.generate_ray(Vec2::new(0.0, 0.5)).o.x > 0.9);
        assert!(cam.generate_ray(Vec2::new(0.5, 0.0)).o.y > 0.9);
    }
}
