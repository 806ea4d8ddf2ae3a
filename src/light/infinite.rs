//! What the lights at infinity share (`constant`, `directional`, `envmap`, `sky`, `sun`): the
//! scene's bounding sphere they keep, and the latitude–longitude sampling of the map lights
//! (`envmap`, `sky`).

use super::envmap::{direction_to_uv, uv_to_direction};
use super::{point_at_infinity, LightLiSample, LightSampleContext};
use crate::math::{Transform, Vec2, Vec3, PI};
use crate::spectrum::SampledSpectrum;

/// The scene's bounding sphere, as a light at infinity keeps it: where its shadow rays end and
/// what its power is spread over (the unit sphere until the scene is known).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SceneSphere {
    pub center: Vec3,
    pub radius: f32,
}

impl SceneSphere {
    pub(crate) const fn new(center: Vec3, radius: f32) -> SceneSphere {
        SceneSphere { center, radius }
    }

    /// A point beyond the sphere along `wi` from `p` (the end of a shadow ray to the light).
    #[inline]
    pub(crate) fn beyond(&self, p: Vec3, wi: Vec3) -> Vec3 {
        point_at_infinity(p, wi, self.center, self.radius)
    }
}

impl Default for SceneSphere {
    fn default() -> Self {
        SceneSphere::new(Vec3::ZERO, 1.0)
    }
}

/// Solid-angle density of a latitude–longitude map light towards the local direction `d`,
/// given the density `map_pdf` of the map point (u, v) there (0 at the poles).
#[inline]
pub(crate) fn latlong_pdf(d: Vec3, map_pdf: impl FnOnce(Vec2) -> f32) -> f32 {
    let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
    if sin_theta.is_nan() || sin_theta <= 0.0 {
        return 0.0;
    }
    map_pdf(direction_to_uv(d)) / (2.0 * PI * PI * sin_theta)
}

/// The sample of a latitude–longitude map light towards the map point `uv`. Density and
/// radiance are re-derived from the direction (by `pdf_li` and `le`) so that they agree exactly
/// with what those report for it.
#[inline]
pub(crate) fn latlong_sample(
    ctx: &LightSampleContext,
    to_world: &Transform,
    uv: Vec2,
    sphere: &SceneSphere,
    pdf_li: impl FnOnce(Vec3) -> f32,
    le: impl FnOnce(Vec3) -> SampledSpectrum,
) -> Option<LightLiSample> {
    let wi = to_world.vector(uv_to_direction(uv)).normalize_or_zero();
    let pdf = pdf_li(wi);
    if !(pdf > 0.0 && pdf.is_finite()) {
        return None;
    }
    Some(LightLiSample {
        l: le(wi),
        wi,
        pdf,
        p_light: sphere.beyond(ctx.p, wi),
        is_delta: false,
    })
}
