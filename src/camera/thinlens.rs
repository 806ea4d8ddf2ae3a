//! `thinlens`: a perspective camera with a thin lens in a circular aperture, for depth of field
//! (Mitsuba's `thinlens` sensor; the model is the classic one of Cook, Porter & Carpenter,
//! "Distributed ray tracing", SIGGRAPH 1984, and Kolb, Mitchell & Hanrahan 1995).
//!
//! Model. Every film point looks, as the pinhole camera would, along a direction d = (x, y, 1)
//! in camera space; the thin lens focuses all light from the point where that direction meets
//! the *focal plane* z = `focus_distance` (a plane perpendicular to the view axis, not a sphere)
//! onto that film point. A camera ray therefore starts at a point a uniformly distributed on the
//! aperture disk of radius `aperture_radius` in the lens plane z = 0 (Shirley–Chiu concentric map)
//! and passes through the focus point d·`focus_distance`. Points on the focal plane are sharp;
//! a point at depth z is seen as a disk whose radius, as a tangent of the view angle (the unit of
//! the film's x, y above), is `aperture_radius`·|1/`focus_distance` − 1/z| — the thin-lens
//! circle of confusion (its size on a sensor is this times the image distance, whatever the
//! focal length). Rays start on the near clip plane, as in Mitsuba.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `aperture_radius` (0.6: `apertureRadius`) | float | required | world units | radius of the lens aperture (0: a pinhole); non-negative |
//! | `focus_distance` (0.6: `focusDistance`) | float | `far_clip` | world units | distance of the focal plane along the view axis; positive |
//! | `fov` | float | from `focal_length` | degrees | field of view along `fov_axis`; strictly between 0 and 180 |
//! | `fov_axis` (0.6: `fovAxis`) | string | `x`; `diagonal` without `fov` | — | the image axis `fov` spans; one of 'x', 'y', 'diagonal', 'smaller', 'larger' |
//! | `focal_length` (0.6: `focalLength`) | string | `50mm` | — | read without `fov`: the 35 mm film equivalent focal length, as `50mm` |
//! | `near_clip` (0.6: `nearClip`) | float | 0.01 | world units | distance along the view axis where rays start; positive |
//! | `far_clip` (0.6: `farClip`) | float | 10000.0 | world units | distance along the view axis where rays end, beyond `near_clip`; positive |
//! | `to_world` (0.6: `toWorld`) | transform | — | — | camera-to-world: the camera looks down its local +z, +y up, +x to the image's left |
//! | `(nested)` | film | `hdrfilm` | — | the film: image size and reconstruction filter |
//! | `(nested)` | sampler | `independent` | — | the sampler: samples per pixel and seed |
//!
//! For a macro photograph: an aperture of f-number N and focal length f has radius f/(2N), e.g. a
//! 100 mm lens at f/8 is 6.25 mm. Limits: no lens distortion, no vignetting, no bokeh shapes (the
//! aperture is a disk); the pixel footprint used for texture filtering is the pinhole's.

use super::{Camera, Common, PerspectiveCamera, Sensor};
use crate::math::warp::square_to_uniform_disk_concentric;
use crate::math::{Ray, Vec2, Vec3};
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Ty};

declare!(PLUGIN: Sensor, Option<(u32, u32)> = Sensor "thinlens" []
    "perspective camera with a thin lens: depth of field"
    [&[
        Param::new("aperture_radius", Ty::Float, DefaultValue::Required)
            .v06("apertureRadius")
            .check(Check::NonNegative)
            .unit("world units")
            .doc("radius of the lens aperture (0: a pinhole)"),
        Param::new("focus_distance", Ty::Float, DefaultValue::Derived("`far_clip`"))
            .v06("focusDistance")
            .check(Check::Positive)
            .unit("world units")
            .doc("distance of the focal plane along the view axis"),
    ], super::perspective::FIELD_OF_VIEW, super::SENSOR] load);

fn load(a: &mut Args, resolution: Option<(u32, u32)>) -> Result<Sensor, SceneError> {
    let c = Common::read(a, resolution)?;
    let pinhole = c.pinhole(a)?;
    let focus_distance = a.float_opt("focus_distance")?.unwrap_or(c.far_clip);
    let camera = ThinLensCamera {
        pinhole,
        aperture_radius: a.float("aperture_radius")?,
        focus_distance,
    };
    Ok(c.sensor(Camera::ThinLens(camera)))
}

/// A thin-lens camera.
#[derive(Clone, Debug)]
pub struct ThinLensCamera {
    /// Field of view, clip planes and placement.
    pub pinhole: PerspectiveCamera,
    pub aperture_radius: f32,
    pub focus_distance: f32,
}

impl ThinLensCamera {
    /// The camera ray through film point `film` ∈ [0,1]² (x right, y down), through the aperture
    /// at the point `aperture` ∈ [0,1]² maps to.
    #[inline]
    pub fn generate_ray(&self, film: Vec2, aperture: Vec2) -> Ray {
        let cam = &self.pinhole;
        let focus = cam.local_direction(film) * self.focus_distance;
        let a = square_to_uniform_disk_concentric(aperture) * self.aperture_radius;
        let lens = Vec3::new(a.x, a.y, 0.0);
        let d_local = (focus - lens).normalize();
        // Start on the near plane and end on the far plane, both perpendicular to the view axis.
        let inv_z = 1.0 / d_local.z;
        let o = cam.to_world.point(lens + d_local * (cam.near_clip * inv_z));
        let d = cam.to_world.vector(d_local).normalize();
        Ray {
            o,
            d,
            t_max: (cam.far_clip - cam.near_clip) * inv_z,
        }
    }

    #[cfg(test)]
    /// The thin-lens circle of confusion of a point at depth `z` (camera space), as a radius in
    /// the tangent-of-angle units of the film plane.
    pub(crate) fn confusion_radius(&self, z: f32) -> f32 {
        self.aperture_radius * (1.0 / self.focus_distance - 1.0 / z).abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::FovAxis;
    use crate::math::{Pcg32, Transform};

    fn camera(to_world: Transform) -> ThinLensCamera {
        ThinLensCamera {
            pinhole: PerspectiveCamera::new(to_world, 40.0, FovAxis::X, 300, 200, 0.01, 1e4),
            aperture_radius: 0.05,
            focus_distance: 2.0,
        }
    }

    fn world_cam() -> (ThinLensCamera, Transform) {
        let t = Transform::look_at(Vec3::new(0.3, 1.0, -2.0), Vec3::new(0.0, 0.2, 0.5), Vec3::Y)
            .unwrap();
        (camera(t), t)
    }

    /// Distance from point `p` to the line of a ray.
    fn miss(r: &Ray, p: Vec3) -> f32 {
        let v = p - r.o;
        (v - r.d * v.dot(r.d)).length()
    }

    #[test]
    fn a_point_at_the_focus_distance_stays_sharp() {
        let (cam, to_world) = world_cam();
        let mut rng = Pcg32::new(3, 1);
        for _ in 0..50 {
            let film = rng.next_vec2();
            // The pinhole ray's point on the focal plane (camera z = focus distance).
            let p = to_world.point(cam.pinhole.local_direction(film) * cam.focus_distance);
            for _ in 0..20 {
                let r = cam.generate_ray(film, rng.next_vec2());
                assert!((r.d.length() - 1.0).abs() < 1e-5);
                assert!(miss(&r, p) < 2e-6 * cam.focus_distance, "{}", miss(&r, p));
            }
        }
    }

    #[test]
    fn the_circle_of_confusion_follows_thin_lens_optics() {
        // A point on the axis at depth z is reached, through lens point a, from the film point
        // whose pinhole direction meets the focal plane where the line from a through the point
        // does: at tangent a·(1/f_d − 1/z). So the film points that see it fill a disk of radius
        // A·|1/f_d − 1/z|. Check both that each such ray reaches the point and the disk's radius.
        let (cam, to_world) = world_cam();
        let half = cam.pinhole.local_direction(Vec2::ZERO); // tan at the film's corner
        let mut rng = Pcg32::new(9, 2);
        for z in [0.5f32, 1.0, 1.5, 3.0, 8.0] {
            let target = Vec3::new(0.0, 0.0, z);
            let mut largest = 0.0f32;
            for _ in 0..400 {
                let u = rng.next_vec2();
                let a = square_to_uniform_disk_concentric(u) * cam.aperture_radius;
                // The ray from a through the target meets the focal plane at q; its film tangent
                // is q / f_d.
                let q = Vec3::new(a.x, a.y, 0.0)
                    + (target - Vec3::new(a.x, a.y, 0.0)) * (cam.focus_distance / z);
                let tan = Vec2::new(q.x, q.y) / cam.focus_distance;
                let film = Vec2::new(0.5 - 0.5 * tan.x / half.x, 0.5 - 0.5 * tan.y / half.y);
                let r = cam.generate_ray(film, u);
                assert!(miss(&r, to_world.point(target)) < 1e-5, "z {z}");
                largest = largest.max(tan.length());
            }
            let expected = cam.confusion_radius(z);
            // The concentric map sends the square's edge to the rim, so 400 samples come within
            // a few per cent of it.
            assert!(
                largest <= expected * (1.0 + 1e-5) && largest > 0.9 * expected,
                "z {z}: {largest} vs {expected}"
            );
        }
    }

    #[test]
    fn zero_aperture_is_the_pinhole() {
        let mut cam = camera(Transform::IDENTITY);
        cam.aperture_radius = 0.0;
        let mut rng = Pcg32::new(1, 1);
        for _ in 0..20 {
            let f = rng.next_vec2();
            let a = cam.generate_ray(f, rng.next_vec2());
            let b = cam.pinhole.generate_ray(f);
            assert!((a.d - b.d).length() < 1e-6 && (a.o - b.o).length() < 1e-6);
            assert!((a.t_max - b.t_max).abs() < 1e-2);
        }
    }
}
