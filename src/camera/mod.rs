//! Cameras (Mitsuba's sensors): `perspective` (a pinhole), `thinlens` (depth of field) and
//! `orthographic`. Each plugin's manual, declaration, loader and model is in its own file;
//! here are the family's enum and what every sensor reads ([`SENSOR`]: clip planes,
//! placement, the nested film and sampler).
//!
//! Conventions shared by all three (Mitsuba's): the camera looks down its local +z, local +y is
//! up and local +x is the *left* of the image, so a `lookat` transform gives an upright,
//! unmirrored picture; film coordinates run over [0, 1]² with x to the right and y down.

pub mod orthographic;
pub mod perspective;
pub mod thinlens;

pub(crate) use orthographic::OrthographicCamera;
pub(crate) use perspective::{FovAxis, PerspectiveCamera};
pub(crate) use thinlens::ThinLensCamera;

use crate::film::FilmSettings;
use crate::math::{Ray, Transform, Vec2, Vec3};
use crate::plugin::{registry, Args, Check, DefaultValue, Param, SceneError, Tag, Ty, Warning};
use crate::scene::SamplerSettings;

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
    pub(crate) fn needs_aperture_sample(&self) -> bool {
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

/// What a `<sensor>` sets up: the camera, and the film and sampler nested in it.
#[derive(Clone, Debug)]
pub struct Sensor {
    pub camera: Camera,
    pub film: FilmSettings,
    pub sampler: SamplerSettings,
}

/// The parameters every sensor reads.
pub(crate) const SENSOR: &[Param] = &[
    Param::float("near_clip", 1e-2)
        .v06("nearClip")
        .check(Check::Positive)
        .unit("world units")
        .doc("distance along the view axis where rays start"),
    Param::float("far_clip", 1e4)
        .v06("farClip")
        .check(Check::Positive)
        .unit("world units")
        .doc("distance along the view axis where rays end, beyond `near_clip`"),
    Param::new("to_world", Ty::Transform, DefaultValue::None)
        .v06("toWorld")
        .doc("camera-to-world: the camera looks down its local +z, +y up, +x to the image's left"),
    Param::new(
        "(nested)",
        Ty::Object(Tag::Film),
        DefaultValue::Derived("`hdrfilm`"),
    )
    .doc("the film: image size and reconstruction filter"),
    Param::new(
        "(nested)",
        Ty::Object(Tag::Sampler),
        DefaultValue::Derived("`independent`"),
    )
    .doc("the sampler: samples per pixel and seed"),
];

/// What every sensor reads ([`SENSOR`]), before its own parameters.
pub(crate) struct Common {
    pub to_world: Transform,
    pub near_clip: f32,
    pub far_clip: f32,
    pub film: FilmSettings,
    pub sampler: SamplerSettings,
}

impl Common {
    /// Reads [`SENSOR`]; `resolution`, when given, replaces the film's size.
    pub(crate) fn read(a: &mut Args, resolution: Option<(u32, u32)>) -> Result<Common, SceneError> {
        let mut film = None;
        let mut sampler = None;
        let node = a.node();
        // In document order, so that of two films (or samplers) the last one counts.
        for child in &node.children {
            let c = &child.node;
            match c.tag {
                Tag::Film => film = Some(registry::film(c, a.warnings())?),
                Tag::Sampler => sampler = Some(registry::sampler(c, a.warnings())?),
                _ => a.warnings().push(Warning {
                    loc: c.loc.clone(),
                    message: format!("{} inside a sensor is ignored", c.describe()),
                }),
            }
        }
        let mut film = film.unwrap_or_default();
        if let Some((w, h)) = resolution {
            (film.width, film.height) = (w.max(1), h.max(1));
        }
        let near_clip = a.float("near_clip")?;
        let far_clip = a.float("far_clip")?;
        if !(far_clip > near_clip) {
            return Err(a.error(
                "far_clip",
                format!("must be greater than near_clip ({near_clip}), got {far_clip}"),
            ));
        }
        Ok(Common {
            to_world: a.transform("to_world")?,
            near_clip,
            far_clip,
            film,
            sampler: sampler.unwrap_or_default(),
        })
    }

    /// The sensor with `camera`.
    pub(crate) fn sensor(self, camera: Camera) -> Sensor {
        Sensor {
            camera,
            film: self.film,
            sampler: self.sampler,
        }
    }
}
