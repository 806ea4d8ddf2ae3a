//! The sun's position in the sky for a place and a local clock time, by the NOAA solar
//! calculator's algorithm (NOAA Global Monitoring Laboratory, "Solar Calculation Details"), which
//! takes its low-accuracy solar coordinates from J. Meeus, "Astronomical Algorithms" (2nd ed.,
//! 1998), ch. 7 (Julian day), 25 (solar coordinates) and 28 (equation of time, Smart's formula).
//! Accuracy ≈ 0.01° in declination for years 1800–2100; atmospheric refraction is not applied
//! (it lifts the sun by up to ≈ 0.6° at the horizon, and by < 0.02° above 45° elevation).
//!
//! Angles are in degrees; the azimuth is measured clockwise from north (90° = east).

use crate::math::Vec3;

/// A moment given as a local clock time at a place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DateTime {
    pub year: i32,
    pub month: u32,
    pub day: u32,
    pub hour: f64,
    pub minute: f64,
    pub second: f64,
    /// Offset of the local clock from UTC in hours (e.g. +1 for Central European Time, −8 for
    /// Pacific Standard Time), as Mitsuba 0.6's `timezone`.
    pub timezone: f64,
}

/// Where the sun is, seen from the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SolarPosition {
    /// Angle from the zenith, degrees (> 90 below the horizon).
    pub zenith: f64,
    /// Clockwise from north, degrees in [0, 360).
    pub azimuth: f64,
}

impl SolarPosition {
    /// Unit direction towards the sun in a frame with +y up, −z north and +x east.
    pub fn direction(&self) -> Vec3 {
        let (sz, cz) = self.zenith.to_radians().sin_cos();
        let (sa, ca) = self.azimuth.to_radians().sin_cos();
        Vec3::new((sz * sa) as f32, cz as f32, (-sz * ca) as f32)
    }
}

/// Julian day (Meeus ch. 7) of a Gregorian calendar date; `day` may carry a fraction.
pub(crate) fn julian_day(year: i32, month: u32, day: f64) -> f64 {
    let (y, m) = if month <= 2 {
        (year as f64 - 1.0, month as f64 + 12.0)
    } else {
        (year as f64, month as f64)
    };
    let a = (y / 100.0).floor();
    let b = 2.0 - a + (a / 4.0).floor();
    (365.25 * (y + 4716.0)).floor() + (30.6001 * (m + 1.0)).floor() + day + b - 1524.5
}

/// The sun's apparent declination (degrees) and the equation of time (minutes) at Julian day
/// `jd` (Meeus ch. 25, low accuracy, and ch. 28 eq. 28.3).
pub(crate) fn declination_and_equation_of_time(jd: f64) -> (f64, f64) {
    let t = (jd - 2_451_545.0) / 36_525.0;
    let l0 = (280.46646 + t * (36_000.769_83 + 0.0003032 * t)).rem_euclid(360.0);
    let m = 357.52911 + t * (35_999.050_29 - 0.0001537 * t);
    let e = 0.016708634 - t * (0.000042037 + 0.0000001267 * t);
    let mr = m.to_radians();
    let center = mr.sin() * (1.914602 - t * (0.004817 + 0.000014 * t))
        + (2.0 * mr).sin() * (0.019993 - 0.000101 * t)
        + (3.0 * mr).sin() * 0.000289;
    let true_long = l0 + center;
    let omega = (125.04 - 1934.136 * t).to_radians();
    let lambda = (true_long - 0.00569 - 0.00478 * omega.sin()).to_radians();
    let eps0 = 23.0 + (26.0 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60.0) / 60.0;
    let eps = (eps0 + 0.00256 * omega.cos()).to_radians();
    let decl = (eps.sin() * lambda.sin()).asin().to_degrees();
    let y = (eps / 2.0).tan().powi(2);
    let l0r = l0.to_radians();
    let eot = y * (2.0 * l0r).sin() - 2.0 * e * mr.sin()
        + 4.0 * e * y * mr.sin() * (2.0 * l0r).cos()
        - 0.5 * y * y * (4.0 * l0r).sin()
        - 1.25 * e * e * (2.0 * mr).sin();
    (decl, 4.0 * eot.to_degrees())
}

/// The sun's position at `latitude` (degrees, north positive), `longitude` (degrees, east
/// positive) and local time `t`.
pub(crate) fn solar_position(latitude: f64, longitude: f64, t: &DateTime) -> SolarPosition {
    let local_minutes = t.hour * 60.0 + t.minute + t.second / 60.0;
    let utc_day_fraction = (local_minutes - 60.0 * t.timezone) / 1440.0;
    let jd = julian_day(t.year, t.month, t.day as f64 + utc_day_fraction);
    let (decl, eot) = declination_and_equation_of_time(jd);
    let true_solar_minutes =
        (local_minutes + eot + 4.0 * longitude - 60.0 * t.timezone).rem_euclid(1440.0);
    let hour_angle = (true_solar_minutes / 4.0 - 180.0).to_radians();
    let (phi, delta) = (latitude.to_radians(), decl.to_radians());
    let cos_zenith =
        (phi.sin() * delta.sin() + phi.cos() * delta.cos() * hour_angle.cos()).clamp(-1.0, 1.0);
    let zenith = cos_zenith.acos();
    // Azimuth from north through east: the sun's east and north components in the local
    // horizon frame.
    let east = -delta.cos() * hour_angle.sin();
    let north = delta.sin() * phi.cos() - delta.cos() * phi.sin() * hour_angle.cos();
    let azimuth = east.atan2(north).to_degrees().rem_euclid(360.0);
    SolarPosition {
        zenith: zenith.to_degrees(),
        azimuth,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn julian_day_matches_meeus_examples() {
        // Meeus, Astronomical Algorithms, example 7.a: 1957 October 4.81 = JD 2436116.31;
        // J2000.0 (2000 January 1.5) = JD 2451545.0; example 7.b: 333 January 27.5 is Julian
        // calendar, not used here.
        assert!((julian_day(1957, 10, 4.81) - 2_436_116.31).abs() < 1e-6);
        assert!((julian_day(2000, 1, 1.5) - 2_451_545.0).abs() < 1e-9);
    }

    #[test]
    fn solar_coordinates_match_meeus_examples() {
        // Meeus example 25.a: 1992 October 13.0 TD (JDE 2448908.5): apparent declination
        // δ = −7.78507°. Example 28.b (Smart's formula, the one used here): E = +13m 42.7s
        // = 13.712 min. (TD − UT ≈ 1 min in 1992 shifts δ by < 0.0003°.)
        let jd = julian_day(1992, 10, 13.0);
        assert_eq!(jd, 2_448_908.5);
        let (decl, eot) = declination_and_equation_of_time(jd);
        assert!((decl - -7.78507).abs() < 2e-3, "declination {decl}");
        assert!((eot - 13.712).abs() < 0.02, "equation of time {eot} min");
    }

    #[test]
    fn position_at_solar_noon_and_sunrise() {
        // Greenwich, 1992-10-13: solar noon is at 12:00 − E = 11:46:17.3 UTC, when the sun stands
        // due south at zenith angle latitude − δ, with δ ≈ −7.785° − 0.39°/day · 0.49 day
        // (Meeus's δ moved on by half a day) = −7.97°.
        let t = DateTime {
            year: 1992,
            month: 10,
            day: 13,
            hour: 11.0,
            minute: 46.0,
            second: 17.3,
            timezone: 0.0,
        };
        let p = solar_position(51.4769, 0.0, &t);
        let (decl, _) = declination_and_equation_of_time(julian_day(1992, 10, 13.4905));
        assert!((decl - -7.97).abs() < 0.02, "{decl}");
        assert!((p.zenith - (51.4769 - decl)).abs() < 0.02, "{p:?}");
        assert!((p.azimuth - 180.0).abs() < 0.05, "{p:?}");
        // The same moment in a UTC+2 clock, with the clock reading two hours later.
        let later = DateTime {
            hour: 13.0,
            timezone: 2.0,
            ..t
        };
        let q = solar_position(51.4769, 0.0, &later);
        assert!((q.zenith - p.zenith).abs() < 1e-9 && (q.azimuth - p.azimuth).abs() < 1e-9);
        // Equinox-like geometry on the equator: 6 h before solar noon the sun is on the horizon
        // in the east (δ ≈ 0 at the 2000 March 20 equinox, 07:35 UT).
        let morning = DateTime {
            year: 2000,
            month: 3,
            day: 20,
            hour: 6.0,
            minute: 7.0,
            second: 0.0,
            timezone: 0.0,
        };
        let r = solar_position(0.0, 0.0, &morning);
        assert!(
            (r.zenith - 90.0).abs() < 0.5 && (r.azimuth - 90.0).abs() < 0.5,
            "{r:?}"
        );
        let d = r.direction();
        assert!(d.x > 0.99 && d.y.abs() < 0.01, "{d}");
        // Direction convention: due south at 60° zenith is (0, 0.5, +0.866).
        let s = SolarPosition {
            zenith: 60.0,
            azimuth: 180.0,
        }
        .direction();
        assert!((s - Vec3::new(0.0, 0.5, 0.8660254)).length() < 1e-5);
    }
}
