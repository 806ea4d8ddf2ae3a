//! Daylight (Mitsuba 0.6's `sunsky`, `sun` and `sky`): Preetham, Shirley & Smits's clear sky
//! ("A Practical Analytic Model for Daylight", SIGGRAPH 1999) and the solar disk, placed by a sun
//! direction or by a place and a local time.
//!
//! | XML name           | type      | default    | unit / meaning                                   |
//! |--------------------|-----------|------------|--------------------------------------------------|
//! | `turbidity`        | float     | 3          | haze, 1.7–10 (2 = very clear, 3 = clear, 6 = hazy, 10 = very hazy) |
//! | `sun_direction`    | vector    | —          | towards the sun, world space; overrides the time and place |
//! | `latitude`         | float     | 35.6894    | degrees, north positive (default: Tokyo, as Mitsuba 0.6) |
//! | `longitude`        | float     | 139.6917   | degrees, east positive                           |
//! | `timezone`         | float     | 9          | hours from UTC of the local clock                |
//! | `year` `month` `day` | integer | 2010 7 10  | local calendar date                              |
//! | `hour` `minute` `second` | float | 15 0 0  | local clock time                                 |
//! | `sun_scale`        | float     | 1          | `sunsky`: multiplies the sun's radiance          |
//! | `sky_scale`        | float     | 1          | `sunsky`: multiplies the sky's radiance          |
//! | `scale`            | float     | 1          | `sun` / `sky` alone: multiplies the radiance     |
//! | `sun_radius_scale` | float     | 1          | scales the disk's angular radius (0.2667°) keeping its power; 0: a directional light |
//! | `to_world`         | transform | identity   | rotation from the sky's frame (+y up, −z north, +x east) to the world |
//! | `albedo`           | spectrum  | —          | accepted and ignored (Preetham's sky has no ground term); a warning says so |
//!
//! Mitsuba 0.6's camelCase names (`sunDirection`, `sunScale`, `skyScale`, `sunRadiusScale`,
//! `toWorld`) arrive snake_cased by the 0.6 upgrade. Its `resolution`, `stretch` and `extend`
//! have no counterpart and are reported as unused.
//!
//! Radiance is physical, W·m⁻²·sr⁻¹·nm⁻¹: the clear sky's luminance is thousands of cd/m², the
//! sun's disk ≈ 2·10⁴ W·m⁻²·sr⁻¹·nm⁻¹, so a white diffuse surface under a high sun renders at
//! ≈ 0.5 — the scales default to 1 and need no exposure tweak.
//!
//! Parts: the sky ([`preetham`]: Perez distribution, zenith luminance and chromaticity, CIE
//! daylight basis; [`SkyLight`]: lat–long importance sampling), the sun ([`SunLight`]: blackbody
//! with the paper's Rayleigh and aerosol transmittances) and the solar position ([`solar`]: the
//! NOAA / Meeus algorithm). `sunsky` becomes two lights, sun and sky, each seeing only its own
//! radiance in `le`, so that multiple importance sampling counts neither twice.
//!
//! Known limits: below the horizon the sky is black (put a ground in the scene); with the sun
//! below the horizon both are black (no twilight) and the scene builder warns; no atmospheric
//! refraction, no ozone / water-vapour absorption in the sun, no limb darkening; the sky is the
//! 1999 model, not Hosek & Wilkie's 2012 one that Mitsuba 0.6 used (colours and the circumsolar
//! region differ somewhat, notably at low sun).

pub mod preetham;
mod sky;
pub mod solar;
mod sun;

pub use sky::SkyLight;
pub use solar::{solar_position, DateTime, SolarPosition};
pub use sun::{SunLight, SunSpectrum, SUN_ANGULAR_RADIUS_DEG};

use crate::math::{Transform, Vec3};

/// Where the sun is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SunPlacement {
    /// A direction towards the sun, world space.
    Direction(Vec3),
    /// A place (degrees) and a local time.
    Time {
        latitude: f64,
        longitude: f64,
        time: DateTime,
    },
}

/// Everything `sunsky`, `sun` and `sky` share.
#[derive(Clone, Copy, Debug)]
pub struct SunSkyParams {
    pub turbidity: f32,
    pub placement: SunPlacement,
    pub sun_scale: f32,
    pub sky_scale: f32,
    pub sun_radius_scale: f32,
    pub to_world: Transform,
}

/// The lights of one daylight emitter.
#[derive(Clone, Debug)]
pub struct SunSky {
    pub sun: Option<SunLight>,
    pub sky: Option<SkyLight>,
    /// Unit direction towards the sun in the sky's frame (+y up).
    pub sun_local: Vec3,
}

impl SunSky {
    /// Builds the sun (if `with_sun`) and the sky (if `with_sky`); `None` if the sun direction
    /// is zero.
    pub fn new(p: &SunSkyParams, with_sun: bool, with_sky: bool) -> Option<SunSky> {
        let sun_local = match p.placement {
            SunPlacement::Direction(d) => p.to_world.inverse().vector(d).normalize_or_zero(),
            SunPlacement::Time {
                latitude,
                longitude,
                time,
            } => solar_position(latitude, longitude, &time).direction(),
        };
        if sun_local == Vec3::ZERO || !sun_local.is_finite() {
            return None;
        }
        let sun_world = p.to_world.vector(sun_local);
        let theta_s = crate::math::safe_acos(sun_local.y);
        let sun = if with_sun {
            Some(SunLight::new(
                sun_world,
                theta_s,
                p.turbidity,
                p.sun_scale,
                p.sun_radius_scale,
            )?)
        } else {
            None
        };
        let sky = with_sky.then(|| SkyLight::new(p.turbidity, sun_local, p.sky_scale, p.to_world));
        Some(SunSky {
            sun,
            sky,
            sun_local,
        })
    }

    /// Whether the sun is above the horizon (otherwise both parts are black).
    pub fn sun_is_up(&self) -> bool {
        self.sun_local.y > 0.0
    }
}

#[cfg(test)]
pub(crate) use super::test_util;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_and_place_put_the_morning_sun_in_the_east() {
        // Tokyo, 2010-07-10 08:00 JST: morning sun in the east-north-east, ≈ 35° up.
        let p = SunSkyParams {
            turbidity: 3.0,
            placement: SunPlacement::Time {
                latitude: 35.6894,
                longitude: 139.6917,
                time: DateTime {
                    year: 2010,
                    month: 7,
                    day: 10,
                    hour: 8.0,
                    minute: 0.0,
                    second: 0.0,
                    timezone: 9.0,
                },
            },
            sun_scale: 1.0,
            sky_scale: 1.0,
            sun_radius_scale: 1.0,
            to_world: Transform::IDENTITY,
        };
        let s = SunSky::new(&p, true, true).unwrap();
        assert!(s.sun_is_up());
        let d = s.sun_local;
        assert!(d.x > 0.6 && d.y > 0.4 && d.y < 0.7, "{d}");
        // A rotated frame turns the sun with it.
        let rot = Transform::rotate(Vec3::Y, 90.0).unwrap();
        let r = SunSky::new(&SunSkyParams { to_world: rot, ..p }, true, true).unwrap();
        assert_eq!(r.sun_local, d);
        let want = rot.vector(d);
        let got = r.sun.unwrap().le(want, &test_util::wl());
        assert!(!got.is_black());
    }
}
