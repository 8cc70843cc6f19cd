//! The sun from place and time, and what it gives the terrain: NREL's solar position
//! algorithm ([`solar_position`], Reda & Andreas 2004), civil dates, times and timezones into
//! UTC instants ([`UtcInstant`], [`parse_date`], [`parse_date_range`], [`parse_time`],
//! [`parse_timezone`], [`parse_step`], [`parse_iso8601_instant`]), the clear sky's direct beam
//! ([`clear_sky_beam`]), the sun over a period ([`sun_samples_over`]) and the insolation of a
//! height field with cast shadows from its horizon angles ([`insolation`]).
//!
//! ```
//! use relief_shade::solar::{solar_position, Observer, UtcInstant};
//! let noon = UtcInstant::from_civil_text("2026-06-21", "12:00", "+02:00").unwrap();
//! let sun = solar_position(noon, &Observer::at(46.95, 7.45)).unwrap();
//! assert!(sun.apparent_elevation_deg > 60.0 && (120.0..200.0).contains(&sun.azimuth_deg));
//! ```

mod civil_time;
mod clear_sky;
mod insolation;
mod spa;
mod spa_terms;
mod sun_samples;
mod time_text;

pub use civil_time::{is_leap_year, CivilDate, TimeOfDay, UtcInstant, UtcOffset, SECONDS_PER_DAY};
pub use clear_sky::{clear_sky_beam, relative_air_mass, SOLAR_CONSTANT_W_M2};
pub(crate) use insolation::{direct_sun, SunOverGrid};
pub use insolation::{insolation, Insolation};
pub use spa::{
    solar_position, Observer, SolarPosition, DEFAULT_DELTA_T_S, DEFAULT_PRESSURE_MBAR,
    DEFAULT_TEMPERATURE_C,
};
pub use sun_samples::{sun_samples_over, SunSample, MAX_SUN_SAMPLES};
pub use time_text::{
    parse_date, parse_date_range, parse_iso8601_instant, parse_step, parse_time, parse_timezone,
    DateRange, MAX_RANGE_DAYS,
};
