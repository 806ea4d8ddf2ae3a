//! Cameras (Mitsuba's sensors): `perspective` (a pinhole), `thinlens` (depth of field) and
//! `orthographic`. Each plugin's model and parameter table is in its own file.
//!
//! Conventions shared by all three (Mitsuba's): the camera looks down its local +z, local +y is
//! up and local +x is the *left* of the image, so a `lookat` transform gives an upright,
//! unmirrored picture; film coordinates run over [0, 1]² with x to the right and y down.

pub mod orthographic;
pub mod perspective;
pub mod thinlens;

pub use orthographic::OrthographicCamera;
pub use perspective::{FovAxis, PerspectiveCamera};
pub use thinlens::ThinLensCamera;

use crate::math::{Ray, Vec2, Vec3};

/// A scene's camera.
#[derive(Clone, Debug)]
pub enum Camera {
    Perspective(PerspectiveCamera),
    ThinLens(ThinLensCamera),
    Orthographic(OrthographicCamera),
}

impl Camera {
    /// Whether [`Camera::generate_ray`] uses its aperture sample (the render loop draws one only
    /// then, so that pinhole images keep their sample sequences).
    #[inline]
    pub fn needs_aperture_sample(&self) -> bool {
        matches!(self, Camera::ThinLens(_))
    }

    /// The camera ray through film point `film` ∈ [0,1]² (x right, y down); `aperture` ∈ [0,1]²
    /// picks the point on the lens (ignored by cameras without one).
    #[inline]
    pub fn generate_ray(&self, film: Vec2, aperture: Vec2) -> Ray {
        match self {
            Camera::Perspective(c) => c.generate_ray(film),
            Camera::ThinLens(c) => c.generate_ray(film, aperture),
            Camera::Orthographic(c) => c.generate_ray(film),
        }
    }

    /// Estimated width, in world units, that one pixel covers at distance `path_length` along
    /// a path (for texture filtering; no ray differentials yet), for an image `height` tall.
    #[inline]
    pub fn footprint(&self, height: u32, path_length: f32) -> f32 {
        match self {
            Camera::Perspective(c) => c.pixel_angle(height) * path_length,
            Camera::ThinLens(c) => c.pinhole.pixel_angle(height) * path_length,
            Camera::Orthographic(c) => c.pixel_width(height),
        }
    }

    /// The camera's position (the centre of its lens or sensor) in world space.
    pub fn position(&self) -> Vec3 {
        match self {
            Camera::Perspective(c) => c.position(),
            Camera::ThinLens(c) => c.pinhole.position(),
            Camera::Orthographic(c) => c.to_world.point(Vec3::ZERO),
        }
    }
}
