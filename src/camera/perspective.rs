//! `perspective`: a pinhole camera with Mitsuba's conventions.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `fov` | float | from `focal_length` | degrees | field of view along `fov_axis`; strictly between 0 and 180 |
//! | `fov_axis` (0.6: `fovAxis`) | string | `x`; `diagonal` without `fov` | — | the image axis `fov` spans; one of 'x', 'y', 'diagonal', 'smaller', 'larger' |
//! | `focal_length` (0.6: `focalLength`) | string | `50mm` | — | read without `fov`: the 35 mm film equivalent focal length, as `50mm` |
//! | `focus_distance` (0.6: `focusDistance`) | float | `far_clip` | world units | read and ignored, as Mitsuba's pinhole does (`thinlens` focuses there); positive |
//! | `near_clip` (0.6: `nearClip`) | float | 0.01 | world units | distance along the view axis where rays start; positive |
//! | `far_clip` (0.6: `farClip`) | float | 10000.0 | world units | distance along the view axis where rays end, beyond `near_clip`; positive |
//! | `to_world` (0.6: `toWorld`) | transform | — | — | camera-to-world: the camera looks down its local +z, +y up, +x to the image's left |
//! | `(nested)` | film | `hdrfilm` | — | the film: image size and reconstruction filter |
//! | `(nested)` | sampler | `independent` | — | the sampler: samples per pixel and seed |
//!
//! As in Mitsuba, the camera's local +x axis points to the *left* of the image and +y up, so a
//! `lookat` transform (x = up × dir) gives an upright, unmirrored picture. Without `fov`, the
//! field of view follows from `focal_length` as on a 36 × 24 mm frame: the horizontal angle of
//! a 36 mm wide frame, applied to the diagonal (Mitsuba's rule). Mitsuba's other sensors
//! (`radiancemeter`, `irradiancemeter`, `distant`, …) load as this camera, with a warning.
//!
//! Known limits: no lens distortion (`perspective_rdist`), no crop window; the pixel footprint
//! used for texture filtering is estimated at the image centre.

use super::{Camera, Common, Sensor};
use crate::math::{Ray, Transform, Vec2, Vec3};
use crate::plugin::{declare, Args, Check, DefaultValue, Param, SceneError, Ty};
use crate::simd::{Float, V3};

declare!(PLUGIN: Sensor, Option<(u32, u32)> = Sensor "perspective" []
    "pinhole camera"
    [FIELD_OF_VIEW, &[
        Param::new("focus_distance", Ty::Float, DefaultValue::Derived("`far_clip`"))
            .v06("focusDistance")
            .check(Check::Positive)
            .unit("world units")
            .doc("read and ignored, as Mitsuba's pinhole does (`thinlens` focuses there)"),
    ], super::SENSOR] load);

/// The field of view of the perspective cameras (`thinlens` reads it too).
pub(crate) const FIELD_OF_VIEW: &[Param] = &[
    Param::new(
        "fov",
        Ty::Float,
        DefaultValue::Derived("from `focal_length`"),
    )
    .check(Check::Open(0.0, 180.0))
    .unit("degrees")
    .doc("field of view along `fov_axis`"),
    Param::new(
        "fov_axis",
        Ty::String,
        DefaultValue::Derived("`x`; `diagonal` without `fov`"),
    )
    .v06("fovAxis")
    .check(Check::OneOf(&["x", "y", "diagonal", "smaller", "larger"]))
    .doc("the image axis `fov` spans"),
    Param::string("focal_length", "50mm")
        .v06("focalLength")
        .doc("read without `fov`: the 35 mm film equivalent focal length, as `50mm`"),
];

fn load(a: &mut Args, resolution: Option<(u32, u32)>) -> Result<Sensor, SceneError> {
    let c = Common::read(a, resolution)?;
    let camera = c.pinhole(a)?;
    a.float_opt("focus_distance")?;
    Ok(c.sensor(Camera::Perspective(camera)))
}

impl Common {
    /// The pinhole camera of a perspective or thin-lens sensor: [`FIELD_OF_VIEW`] read from `a`.
    pub(crate) fn pinhole(&self, a: &Args) -> Result<PerspectiveCamera, SceneError> {
        let fov = match a.float_opt("fov")? {
            Some(f) => f,
            None => {
                let fl = a.string("focal_length")?;
                let mm: f32 = fl.trim_end_matches("mm").trim().parse().map_err(|_| {
                    a.error("focal_length", format!("must look like '50mm', got '{fl}'"))
                })?;
                if !(mm > 0.0) {
                    return Err(a.error("focal_length", "must be positive"));
                }
                // Horizontal fov of a 36 mm wide frame, applied to the diagonal as Mitsuba does.
                let fov = 2.0 * (43.266_615 / (2.0 * mm)).atan().to_degrees();
                if !(fov > 0.0 && fov < 180.0) {
                    let e = format!("gives a field of view of {fov} degrees; expected 0 to 180");
                    return Err(a.error("focal_length", e));
                }
                fov
            }
        };
        let axis = match a.string_opt("fov_axis")? {
            Some(name) => FovAxis::from_name(&name),
            None if a.has("fov") => Some(FovAxis::X),
            None => Some(FovAxis::Diagonal),
        }
        // The declaration's check has refused any other name.
        .ok_or_else(|| a.error("fov_axis", "unknown axis"))?;
        let (w, h) = (self.film.width, self.film.height);
        Ok(PerspectiveCamera::new(
            self.to_world,
            fov,
            axis,
            w,
            h,
            self.near_clip,
            self.far_clip,
        ))
    }
}

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
    pub(crate) fn from_name(s: &str) -> Option<FovAxis> {
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
    pub(crate) fn pixel_angle(&self, height: u32) -> f32 {
        2.0 * self.tan_half.y / height.max(1) as f32
    }

    /// The camera-space direction (not normalised, z = 1) through the film point `film` ∈ [0,1]²
    /// (x right, y down).
    #[inline]
    pub(crate) fn local_direction(&self, film: Vec2) -> Vec3 {
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
