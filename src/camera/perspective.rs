//! `perspective`: a pinhole camera with Mitsuba's conventions.
//!
//! | XML name    | type      | default | meaning                                              |
//! |-------------|-----------|---------|------------------------------------------------------|
//! | `fov`       | float     | —       | field of view in degrees along `fov_axis`            |
//! | `fov_axis`  | string    | `x`     | `x`, `y`, `diagonal`, `smaller` or `larger`          |
//! | `near_clip` | float     | 0.01    | distance along the view axis where rays start        |
//! | `far_clip`  | float     | 10000   | distance along the view axis where rays end          |
//! | `to_world`  | transform | id.     | camera-to-world; the camera looks down its local +z  |
//! | `focal_length` | string | `50mm`  | alternative to `fov`: 35 mm film equivalent (diagonal) |
//! | `focus_distance` | float | —      | read and ignored, as Mitsuba's pinhole does (`thinlens` uses it) |
//!
//! As in Mitsuba, the camera's local +x axis points to the *left* of the image and +y up, so a
//! `lookat` transform (x = up × dir) gives an upright, unmirrored picture. Mitsuba 0.6's `fovAxis`
//! and `nearClip`/`farClip` arrive here through the loader's camelCase upgrade.

use crate::math::{Ray, Transform, Vec2, Vec3};
use crate::simd::{Float, V3};

/// Which image axis `fov` refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FovAxis {
    X,
    Y,
    Diagonal,
    Smaller,
    Larger,
}

impl FovAxis {
    /// Parses Mitsuba's names.
    pub fn from_name(s: &str) -> Option<FovAxis> {
        Some(match s {
            "x" => FovAxis::X,
            "y" => FovAxis::Y,
            "diagonal" => FovAxis::Diagonal,
            "smaller" => FovAxis::Smaller,
            "larger" => FovAxis::Larger,
            _ => return None,
        })
    }
}

/// A perspective camera.
#[derive(Clone, Debug)]
pub struct PerspectiveCamera {
    pub to_world: Transform,
    /// tan of half the field of view along x and y.
    tan_half: Vec2,
    pub near_clip: f32,
    pub far_clip: f32,
}

impl PerspectiveCamera {
    /// Builds a camera for an image of `width`×`height` pixels. `fov_deg` must be in (0, 180).
    pub fn new(
        to_world: Transform,
        fov_deg: f32,
        axis: FovAxis,
        width: u32,
        height: u32,
        near_clip: f32,
        far_clip: f32,
    ) -> PerspectiveCamera {
        let aspect = width as f32 / height as f32;
        let t = (0.5 * fov_deg.to_radians()).tan();
        let axis = match axis {
            FovAxis::Smaller if aspect > 1.0 => FovAxis::Y,
            FovAxis::Smaller => FovAxis::X,
            FovAxis::Larger if aspect > 1.0 => FovAxis::X,
            FovAxis::Larger => FovAxis::Y,
            a => a,
        };
        let tan_half = match axis {
            FovAxis::X => Vec2::new(t, t / aspect),
            FovAxis::Y => Vec2::new(t * aspect, t),
            _ => {
                // tan of the half diagonal is split according to the aspect ratio.
                let d = (aspect * aspect + 1.0).sqrt();
                Vec2::new(t * aspect / d, t / d)
            }
        };
        PerspectiveCamera {
            to_world,
            tan_half,
            near_clip,
            far_clip,
        }
    }

    /// Angle one pixel subtends at the image centre, for an image `height` pixels tall
    /// (a footprint estimate for texture filtering).
    pub fn pixel_angle(&self, height: u32) -> f32 {
        2.0 * self.tan_half.y / height.max(1) as f32
    }

    /// The camera-space direction (not normalised, z = 1) through the film point `film` ∈ [0,1]²
    /// (x right, y down).
    #[inline]
    pub fn local_direction(&self, film: Vec2) -> Vec3 {
        Vec3::new(
            (1.0 - 2.0 * film.x) * self.tan_half.x,
            (1.0 - 2.0 * film.y) * self.tan_half.y,
            1.0,
        )
    }

    /// The camera ray through the film point `film` ∈ [0,1]² (x right, y down).
    #[inline]
    pub fn generate_ray(&self, film: Vec2) -> Ray {
        let (o, d, t_max) = self.generate_ray_lanes(film.x, film.y);
        Ray {
            o: o.into(),
            d: d.into(),
            t_max,
        }
    }

    /// [`PerspectiveCamera::generate_ray`] on lanes: (origin, direction, t_max).
    #[inline(always)]
    pub fn generate_ray_lanes<F: Float>(&self, fx: F, fy: F) -> (V3<F>, V3<F>, F) {
        let one = F::splat(1.0);
        let two = F::splat(2.0);
        let d_cam = V3::new(
            (one - two * fx) * F::splat(self.tan_half.x),
            (one - two * fy) * F::splat(self.tan_half.y),
            one,
        );
        let len = d_cam.length();
        let d_local = d_cam / len;
        // The clip planes are perpendicular to the view axis: along d_local (z = 1/len) they are
        // `len` times farther than their z.
        let o = self
            .to_world
            .point_lanes(d_local * (F::splat(self.near_clip) * len));
        let dw = self.to_world.vector_lanes(d_local);
        let d = dw.normalize();
        // A scaled to_world changes lengths; measure the clip range in world units.
        let scale = dw.length();
        (o, d, F::splat(self.far_clip - self.near_clip) * len * scale)
    }

    /// Camera position in world space.
    pub fn position(&self) -> Vec3 {
        self.to_world.point(Vec3::ZERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_looks_down_z_and_corners_match_fov() {
        let cam =
            PerspectiveCamera::new(Transform::IDENTITY, 90.0, FovAxis::X, 200, 100, 0.01, 100.0);
        let r = cam.generate_ray(Vec2::new(0.5, 0.5));
        assert!((r.d - Vec3::Z).length() < 1e-6);
        // Left edge of the image is local +x; 90° horizontal fov → 45° half angle.
        let l = cam.generate_ray(Vec2::new(0.0, 0.5));
        assert!((l.d.x - l.d.z).abs() < 1e-5 && l.d.x > 0.0);
        // Top edge: half the vertical extent because of the 2:1 aspect.
        let t = cam.generate_ray(Vec2::new(0.5, 0.0));
        assert!((t.d.y / t.d.z - 0.5).abs() < 1e-5);
    }

    #[test]
    fn fov_axis_y_and_smaller_agree_for_landscape() {
        let a =
            PerspectiveCamera::new(Transform::IDENTITY, 40.0, FovAxis::Y, 300, 200, 0.01, 100.0);
        let b = PerspectiveCamera::new(
            Transform::IDENTITY,
            40.0,
            FovAxis::Smaller,
            300,
            200,
            0.01,
            100.0,
        );
        assert_eq!(a.tan_half, b.tan_half);
    }
}
