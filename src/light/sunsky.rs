//! Daylight (Mitsuba 0.6's `sunsky`, `sun` and `sky`): Preetham, Shirley & Smits's clear sky
//! ("A Practical Analytic Model for Daylight", SIGGRAPH 1999) and the solar disk, placed by a sun
//! direction or by a place and a local time.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `turbidity` | float | 3.0 | — | haze: 2 very clear, 3 clear, 6 hazy, 10 very hazy; between 1.7 and 10 |
//! | `sun_direction` (0.6: `sunDirection`) | vector | — | — | towards the sun, world space; overrides the time and place |
//! | `latitude` | float | 35.6894 | degrees | north positive (default: Tokyo, as Mitsuba 0.6); between -90 and 90 |
//! | `longitude` | float | 139.6917 | degrees | east positive; between -360 and 360 |
//! | `timezone` | float | 9.0 | hours | offset of the local clock from UTC; between -14 and 14 |
//! | `year` | integer | 2010 | — | local date; between 1000 and 3000 |
//! | `month` | integer | 7 | — | local date; between 1 and 12 |
//! | `day` | integer | 10 | — | local date; between 1 and 31 |
//! | `hour` | float | 15.0 | — | local clock time; between 0 and 24 |
//! | `minute` | float | 0.0 | — | local clock time; between 0 and 60 |
//! | `second` | float | 0.0 | — | local clock time; between 0 and 60 |
//! | `to_world` | transform | — | — | rotation from the sky's frame (+y up, −z north, +x east) to the world |
//! | `albedo` | spectrum | — | — | accepted and ignored (Preetham's sky has no ground term), with a warning |
//! | `sun_scale` (0.6: `sunScale`) | float | 1.0 | — | multiplies the sun's radiance; non-negative |
//! | `sky_scale` (0.6: `skyScale`) | float | 1.0 | — | multiplies the sky's radiance; non-negative |
//! | `sun_radius_scale` (0.6: `sunRadiusScale`) | float | 1.0 | — | scales the disk's angular radius (0.2667°) keeping its power; 0: a directional light; non-negative |
//!
//! `sun` and `sky` alone take one `scale` in place of `sun_scale` and `sky_scale`; `sky` has no
//! `sun_radius_scale`.
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

pub(crate) mod preetham;
mod sky;
pub(crate) mod solar;
mod sun;

pub use sky::SkyLight;
pub(crate) use solar::{solar_position, DateTime};
pub use sun::SunLight;

use super::Light;
use crate::math::{Transform, Vec3};
use crate::plugin::{
    declare, Args, Check, DefaultValue, Param, SceneError, SpectrumKind, Ty, Warning,
};

/// A field of the local date, between `lo` and `hi`.
const fn date(name: &'static str, default: i64, lo: i64, hi: i64) -> Param {
    Param::int(name, default)
        .check(Check::Range(lo as f64, hi as f64))
        .doc("local date")
}

/// A field of the local clock time, from 0 to `hi`.
const fn clock(name: &'static str, default: f32, hi: f64) -> Param {
    Param::float(name, default)
        .check(Check::Range(0.0, hi))
        .doc("local clock time")
}

/// Where and when: shared by `sunsky`, `sun` and `sky`.
const PLACE: &[Param] = &[
    Param::float("turbidity", 3.0)
        .check(Check::Range(1.7, 10.0))
        .doc("haze: 2 very clear, 3 clear, 6 hazy, 10 very hazy"),
    Param::new("sun_direction", Ty::Vector, DefaultValue::None)
        .v06("sunDirection")
        .doc("towards the sun, world space; overrides the time and place"),
    Param::float("latitude", 35.6894)
        .check(Check::Range(-90.0, 90.0))
        .unit("degrees")
        .doc("north positive (default: Tokyo, as Mitsuba 0.6)"),
    Param::float("longitude", 139.6917)
        .check(Check::Range(-360.0, 360.0))
        .unit("degrees")
        .doc("east positive"),
    Param::float("timezone", 9.0)
        .check(Check::Range(-14.0, 14.0))
        .unit("hours")
        .doc("offset of the local clock from UTC"),
    date("year", 2010, 1000, 3000),
    date("month", 7, 1, 12),
    date("day", 10, 1, 31),
    clock("hour", 15.0, 24.0),
    clock("minute", 0.0, 60.0),
    clock("second", 0.0, 60.0),
    Param::new("to_world", Ty::Transform, DefaultValue::None)
        .doc("rotation from the sky's frame (+y up, −z north, +x east) to the world"),
    Param::new(
        "albedo",
        Ty::Spectrum(SpectrumKind::Albedo),
        DefaultValue::None,
    )
    .doc("accepted and ignored (Preetham's sky has no ground term), with a warning"),
];
/// The scales of `sunsky`.
const SUNSKY_SCALES: &[Param] = &[
    Param::float("sun_scale", 1.0)
        .check(Check::NonNegative)
        .v06("sunScale")
        .doc("multiplies the sun's radiance"),
    Param::float("sky_scale", 1.0)
        .check(Check::NonNegative)
        .v06("skyScale")
        .doc("multiplies the sky's radiance"),
];
/// The scale of `sun` or `sky` alone.
const SCALE: &[Param] = &[Param::float("scale", 1.0)
    .check(Check::NonNegative)
    .doc("multiplies the radiance")];
/// The sun's disk.
const SUN_RADIUS: &[Param] = &[Param::float("sun_radius_scale", 1.0)
    .check(Check::NonNegative)
    .v06("sunRadiusScale")
    .doc("scales the disk's angular radius (0.2667°) keeping its power; 0: a directional light")];

declare!(PLUGIN: Vec<Light>, Option<u32> = Emitter "sunsky" []
    "Preetham's clear sky and the sun, by direction or by place and time"
    [PLACE, SUNSKY_SCALES, SUN_RADIUS] load_sunsky);
declare!(SUN_PLUGIN: Vec<Light>, Option<u32> = Emitter "sun" []
    "the solar disk of `sunsky` alone"
    [PLACE, SCALE, SUN_RADIUS] load_sun);
declare!(SKY_PLUGIN: Vec<Light>, Option<u32> = Emitter "sky" []
    "the clear sky of `sunsky` alone"
    [PLACE, SCALE] load_sky);

fn load_sunsky(a: &mut Args, _: Option<u32>) -> Result<Vec<Light>, SceneError> {
    daylight(a, true, true)
}
fn load_sun(a: &mut Args, _: Option<u32>) -> Result<Vec<Light>, SceneError> {
    daylight(a, true, false)
}
fn load_sky(a: &mut Args, _: Option<u32>) -> Result<Vec<Light>, SceneError> {
    daylight(a, false, true)
}

/// The lights of a `sunsky` (sun then sky), `sun` or `sky` emitter.
fn daylight(a: &mut Args, with_sun: bool, with_sky: bool) -> Result<Vec<Light>, SceneError> {
    let placement = match a.vector_opt("sun_direction")? {
        Some(d) => SunPlacement::Direction(d),
        None => SunPlacement::Time {
            latitude: a.float("latitude")? as f64,
            longitude: a.float("longitude")? as f64,
            time: DateTime {
                year: a.int("year")? as i32,
                month: a.u32("month")?,
                day: a.u32("day")?,
                hour: a.float("hour")? as f64,
                minute: a.float("minute")? as f64,
                second: a.float("second")? as f64,
                timezone: a.float("timezone")? as f64,
            },
        },
    };
    let (sun_scale, sky_scale) = if with_sun && with_sky {
        (a.float("sun_scale")?, a.float("sky_scale")?)
    } else {
        (a.float("scale")?, a.float("scale")?)
    };
    let params = SunSkyParams {
        turbidity: a.float("turbidity")?,
        placement,
        sun_scale,
        sky_scale,
        sun_radius_scale: if with_sun {
            a.float("sun_radius_scale")?
        } else {
            1.0
        },
        to_world: a.transform("to_world")?,
    };
    if let Some(loc) = a.node().props.location("albedo").cloned() {
        a.ignore("albedo")?;
        let message = format!(
            "{}: 'albedo' is ignored (Preetham's sky has no ground term)",
            a.describe()
        );
        a.warnings().push(Warning { loc, message });
    }
    let parts = SunSky::new(&params, with_sun, with_sky)
        .ok_or_else(|| a.error("sun_direction", "must be a non-zero vector"))?;
    if !parts.sun_is_up() {
        let elevation = parts.sun_local.y.clamp(-1.0, 1.0).asin().to_degrees();
        a.warn(format!(
            "{}: the sun is below the horizon (elevation {elevation:.1}°); sun and sky are black",
            a.describe()
        ));
    }
    let mut lights = Vec::new();
    lights.extend(parts.sun.map(|sun| Light::Sun(sun.into())));
    lights.extend(parts.sky.map(|sky| Light::Sky(sky.into())));
    Ok(lights)
}

/// Where the sun is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum SunPlacement {
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
pub(crate) struct SunSkyParams {
    pub turbidity: f32,
    pub placement: SunPlacement,
    pub sun_scale: f32,
    pub sky_scale: f32,
    pub sun_radius_scale: f32,
    pub to_world: Transform,
}

/// The lights of one daylight emitter.
#[derive(Clone, Debug)]
pub(crate) struct SunSky {
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
    pub(crate) fn sun_is_up(&self) -> bool {
        self.sun_local.y > 0.0
    }
}

#[cfg(test)]
pub(crate) use super::test_util;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::infinite::InfiniteLight;

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
