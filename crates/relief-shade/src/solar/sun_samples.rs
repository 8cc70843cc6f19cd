//! The sun over a period as insolation sums it: [`SunSample`]s at the middles of equal time
//! steps over a range of days of local clocks, each with its clear-sky beam and the hours it
//! stands for.

use super::civil_time::{TimeOfDay, UtcInstant, UtcOffset, SECONDS_PER_DAY};
use super::clear_sky::clear_sky_beam;
use super::spa::{solar_position, Observer};
use super::time_text::DateRange;
use crate::shade_map::InsolationSun;
use crate::ShadeError;

/// Most sun samples one period may have (a year at 5-minute steps is 105 120).
pub const MAX_SUN_SAMPLES: u64 = 1_000_000;

/// The sun over one span of time, as insolation counts it: the shade map's
/// [`InsolationSun`] (its direction, apparent elevation, the hours it stands for and its
/// beam).
pub type SunSample = InsolationSun;

impl SunSample {
    /// The sun seen by `observer` at `instant`, standing for `hours`, with the clear-sky beam
    /// of [`clear_sky_beam`].
    pub fn at(
        instant: UtcInstant,
        observer: &Observer,
        hours: f64,
    ) -> Result<SunSample, ShadeError> {
        let sun = solar_position(instant, observer)?;
        Ok(SunSample {
            azimuth_deg: sun.azimuth_deg,
            elevation_deg: sun.apparent_elevation_deg,
            hours,
            beam_w_m2: clear_sky_beam(sun.apparent_elevation_deg),
        })
    }
}

/// The sun over every day of `days` on clocks `offset` from UTC (from the first day's 00:00
/// to the end of the last day), at the middle of each step of `step_s` seconds; a last step
/// cut short by the period's end stands for the time left. Samples with the sun below the
/// horizontal are kept (their beam is 0; insolation counts them zero), so the samples tile
/// the whole period.
///
/// ```
/// use relief_shade::solar::{parse_date_range, sun_samples_over, Observer, UtcOffset};
/// let june = parse_date_range("2026-06-21").unwrap();
/// let suns = sun_samples_over(june, UtcOffset::UTC, 900.0, &Observer::at(46.5, 7.9)).unwrap();
/// assert_eq!(suns.len(), 96);
/// assert_eq!(suns.iter().map(|s| s.hours).sum::<f64>(), 24.0);
/// ```
pub fn sun_samples_over(
    days: DateRange,
    offset: UtcOffset,
    step_s: f64,
    observer: &Observer,
) -> Result<Vec<SunSample>, ShadeError> {
    observer.validate()?;
    if !(step_s.is_finite() && step_s > 0.0) {
        return Err(ShadeError::parameter("step", format!("{step_s} s is not a time step > 0")));
    }
    let start = UtcInstant::from_civil(days.first, TimeOfDay::MIDNIGHT, offset);
    let span_s = (days.days() * SECONDS_PER_DAY) as f64;
    let steps = (span_s / step_s).ceil();
    if steps > MAX_SUN_SAMPLES as f64 {
        return Err(ShadeError::Limits(format!(
            "{} days at steps of {step_s} s are {steps} sun positions, over the {MAX_SUN_SAMPLES} \
             allowed: take a longer step",
            days.days()
        )));
    }
    (0..steps as u64)
        .map(|k| {
            let begin = k as f64 * step_s;
            let end = (begin + step_s).min(span_s);
            let middle = start.plus_seconds(0.5 * (begin + end));
            SunSample::at(middle, observer, (end - begin) / 3600.0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solar::time_text::parse_date_range;

    #[test]
    fn a_day_at_steps_that_do_not_divide_it() {
        let day = parse_date_range("2026-03-20").unwrap();
        let observer = Observer::at(0.0, 0.0);
        // 7 h steps: three of 7 h and one of 3 h.
        let suns = sun_samples_over(day, UtcOffset::UTC, 7.0 * 3600.0, &observer).unwrap();
        let hours: Vec<f64> = suns.iter().map(|s| s.hours).collect();
        assert_eq!(hours, vec![7.0, 7.0, 7.0, 3.0]);
        // The middle of the second step is 10:30 UTC: morning on the equator at 0 E.
        let expected = UtcInstant::from_civil_text("2026-03-20", "10:30", "Z").unwrap();
        assert_eq!(suns[1], SunSample::at(expected, &observer, 7.0).unwrap());
        assert!(suns[1].elevation_deg > 0.0 && suns[1].beam_w_m2 > 0.0);
        // Midnight's sample: the sun is down and its beam 0.
        assert!(suns[3].elevation_deg < 0.0 && suns[3].beam_w_m2 == 0.0);
    }

    #[test]
    fn local_days_follow_the_offset() {
        let day = parse_date_range("2026-06-21").unwrap();
        let observer = Observer::at(47.0, 8.0);
        let zurich = UtcOffset::from_minutes(120).unwrap();
        let local = sun_samples_over(day, zurich, 3600.0, &observer).unwrap();
        let utc = sun_samples_over(day, UtcOffset::UTC, 3600.0, &observer).unwrap();
        // 12:30 local is 10:30 UTC.
        assert_eq!(local[12], utc[10]);
        let noon = local.iter().max_by(|a, b| a.elevation_deg.total_cmp(&b.elevation_deg));
        assert!(noon.unwrap().elevation_deg > 65.0);
    }

    #[test]
    fn too_many_samples_and_bad_steps_are_refused() {
        let century = parse_date_range("2000-01-01..2099-12-31").unwrap();
        let observer = Observer::at(0.0, 0.0);
        let error = sun_samples_over(century, UtcOffset::UTC, 60.0, &observer).unwrap_err();
        assert!(matches!(error, ShadeError::Limits(_)), "{error}");
        let day = parse_date_range("2026-06-21").unwrap();
        assert!(sun_samples_over(day, UtcOffset::UTC, 0.0, &observer).is_err());
        assert!(sun_samples_over(day, UtcOffset::UTC, 60.0, &Observer::at(95.0, 0.0)).is_err());
    }
}
