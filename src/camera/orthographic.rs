//! `orthographic`: a camera without perspective (Mitsuba's `orthographic` sensor) — a planar
//! sensor that measures radiance along its normal.
//!
//! Model. In camera space the sensor is the rectangle x ∈ [−1, 1], y ∈ [−1/a, 1/a] (a = width /
//! height) on the near plane z = `near_clip`; every ray leaves it along +z. As with
//! `perspective`, local +x is the left of the image. The sensor's size is set by scaling
//! `to_world` (e.g. `<scale x="10" y="10"/>` before the `lookat` makes it 20 units wide), as in
//! Mitsuba.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `near_clip` (0.6: `nearClip`) | float | 0.01 | world units | distance along the view axis where rays start; positive |
//! | `far_clip` (0.6: `farClip`) | float | 10000.0 | world units | distance along the view axis where rays end, beyond `near_clip`; positive |
//! | `to_world` (0.6: `toWorld`) | transform | — | — | camera-to-world: the camera looks down its local +z, +y up, +x to the image's left |
//! | `(nested)` | film | `hdrfilm` | — | the film: image size and reconstruction filter |
//! | `(nested)` | sampler | `independent` | — | the sampler: samples per pixel and seed |
//!
//! Known limits: the pixel footprint for texture filtering is the pixel's width on the sensor
//! at every distance (exact for this projection, but it ignores the surface's slant).

use super::{Camera, Common, Sensor};
use crate::math::{Ray, Transform, Vec2, Vec3};
use crate::plugin::{declare, Args, SceneError};

declare!(PLUGIN: Sensor, Option<(u32, u32)> = Sensor "orthographic" []
    "parallel projection from a planar sensor sized by `to_world`"
    [super::SENSOR] load);

fn load(a: &mut Args, resolution: Option<(u32, u32)>) -> Result<Sensor, SceneError> {
    let c = Common::read(a, resolution)?;
    let (w, h) = (c.film.width, c.film.height);
    let camera = OrthographicCamera::new(c.to_world, w, h, c.near_clip, c.far_clip);
    Ok(c.sensor(Camera::Orthographic(camera)))
}

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
    pub(crate) fn pixel_width(&self, height: u32) -> f32 {
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
