//! Civil time: calendar dates of the proleptic Gregorian calendar, times of day, offsets from
//! UTC, and the UTC instants they name (seconds since 1970-01-01 00:00 UTC, Julian days).

use crate::ShadeError;
use std::fmt;

/// Seconds in a civil day (no leap seconds, as in POSIX time).
pub const SECONDS_PER_DAY: i64 = 86_400;

/// The Julian day of 1970-01-01 00:00 UTC.
const UNIX_EPOCH_JULIAN_DAY: f64 = 2_440_587.5;

/// A date of the proleptic Gregorian calendar that exists (checked when made).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct CivilDate {
    year: i32,
    month: u32,
    day: u32,
}

impl CivilDate {
    /// The date `year-month-day`; an error naming it when it does not exist (month 13,
    /// February 30, ...) or its year is outside 1..=9999.
    pub fn new(year: i32, month: u32, day: u32) -> Result<CivilDate, ShadeError> {
        let text = format!("{year:04}-{month:02}-{day:02}");
        if !(1..=9999).contains(&year) {
            return Err(ShadeError::parameter(
                "date",
                format!("{text}: the year is not in 1-9999"),
            ));
        }
        if !(1..=12).contains(&month) {
            return Err(ShadeError::parameter(
                "date",
                format!("{text} does not exist: there is no month {month}"),
            ));
        }
        let length = days_in_month(year, month);
        if !(1..=length).contains(&day) {
            return Err(ShadeError::parameter(
                "date",
                format!(
                    "{text} does not exist: {} {year} has {length} days",
                    MONTH_NAMES[month as usize - 1]
                ),
            ));
        }
        Ok(CivilDate { year, month, day })
    }

    /// The year.
    pub fn year(self) -> i32 {
        self.year
    }

    /// The month, 1 to 12.
    pub fn month(self) -> u32 {
        self.month
    }

    /// The day of the month, from 1.
    pub fn day(self) -> u32 {
        self.day
    }

    /// Days since 1970-01-01 (negative before it).
    pub fn days_since_epoch(self) -> i64 {
        // Days from civil, counting years from March so that the leap day ends a year.
        let year = i64::from(self.year) - i64::from(self.month <= 2);
        let era = year.div_euclid(400);
        let year_of_era = year - era * 400;
        let month_from_march = (i64::from(self.month) + 9) % 12;
        let day_of_year = (153 * month_from_march + 2) / 5 + i64::from(self.day) - 1;
        let day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
        era * 146_097 + day_of_era - 719_468
    }

    /// The date `days` days after this one (before it for negative `days`); an error past
    /// the calendar's years 1..=9999.
    pub fn plus_days(self, days: i64) -> Result<CivilDate, ShadeError> {
        let (year, month, day) = civil_from_days(self.days_since_epoch() + days);
        i32::try_from(year)
            .map_err(|_| ShadeError::parameter("date", format!("{self} + {days} days is too far")))
            .and_then(|year| CivilDate::new(year, month, day))
    }
}

impl fmt::Display for CivilDate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:04}-{:02}-{:02}", self.year, self.month, self.day)
    }
}

/// English month names, for messages.
const MONTH_NAMES: [&str; 12] = [
    "January",
    "February",
    "March",
    "April",
    "May",
    "June",
    "July",
    "August",
    "September",
    "October",
    "November",
    "December",
];

/// Whether `year` is a leap year of the Gregorian calendar.
pub fn is_leap_year(year: i32) -> bool {
    (year % 4 == 0 && year % 100 != 0) || year % 400 == 0
}

/// Days in `month` (1 to 12) of `year`.
fn days_in_month(year: i32, month: u32) -> u32 {
    match month {
        2 if is_leap_year(year) => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// (year, month, day) of the day `days` after 1970-01-01: the inverse of
/// [`CivilDate::days_since_epoch`].
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let shifted = days + 719_468;
    let era = shifted.div_euclid(146_097);
    let day_of_era = shifted - era * 146_097;
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_from_march = (5 * day_of_year + 2) / 153;
    let day = (day_of_year - (153 * month_from_march + 2) / 5 + 1) as u32;
    let month = if month_from_march < 10 { month_from_march + 3 } else { month_from_march - 9 };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month as u32, day)
}

/// A time of day on a clock, 00:00:00 to 23:59:59.999...
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct TimeOfDay {
    seconds: f64,
}

impl TimeOfDay {
    /// Midnight, the start of a day.
    pub const MIDNIGHT: TimeOfDay = TimeOfDay { seconds: 0.0 };

    /// `hour:minute:second`; an error unless hour < 24, minute < 60 and 0 <= second < 60.
    pub fn new(hour: u32, minute: u32, second: f64) -> Result<TimeOfDay, ShadeError> {
        if hour >= 24 || minute >= 60 || !(0.0..60.0).contains(&second) {
            return Err(ShadeError::parameter(
                "time",
                format!("{hour:02}:{minute:02}:{second:02} is not a time of day (00:00 to 23:59)"),
            ));
        }
        Ok(TimeOfDay { seconds: f64::from(hour * 3600 + minute * 60) + second })
    }

    /// Seconds since midnight.
    pub fn seconds_since_midnight(self) -> f64 {
        self.seconds
    }
}

/// An offset of local clocks from UTC, whole minutes, within +-18 hours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct UtcOffset {
    minutes: i32,
}

impl UtcOffset {
    /// UTC itself.
    pub const UTC: UtcOffset = UtcOffset { minutes: 0 };

    /// The offset of `minutes` east of Greenwich (negative west); an error beyond 18 hours.
    pub fn from_minutes(minutes: i32) -> Result<UtcOffset, ShadeError> {
        if minutes.abs() > 18 * 60 {
            return Err(ShadeError::parameter(
                "timezone",
                format!("{minutes} minutes from UTC is beyond +-18:00"),
            ));
        }
        Ok(UtcOffset { minutes })
    }

    /// Minutes east of Greenwich.
    pub fn minutes(self) -> i32 {
        self.minutes
    }
}

impl fmt::Display for UtcOffset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sign = if self.minutes < 0 { '-' } else { '+' };
        let m = self.minutes.abs();
        write!(f, "{sign}{:02}:{:02}", m / 60, m % 60)
    }
}

/// An instant in UTC: seconds since 1970-01-01 00:00:00 UTC, leap seconds not counted (POSIX
/// time, as NumPy's datetime64 and pvlib count them).
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct UtcInstant {
    unix_seconds: f64,
}

impl UtcInstant {
    /// The instant `unix_seconds` after 1970-01-01 00:00:00 UTC.
    pub fn from_unix_seconds(unix_seconds: f64) -> UtcInstant {
        UtcInstant { unix_seconds }
    }

    /// The instant at which local clocks `offset` from UTC show `date` `time`.
    pub fn from_civil(date: CivilDate, time: TimeOfDay, offset: UtcOffset) -> UtcInstant {
        let local = date.days_since_epoch() * SECONDS_PER_DAY - i64::from(offset.minutes) * 60;
        UtcInstant { unix_seconds: local as f64 + time.seconds_since_midnight() }
    }

    /// The instant of a date (`YYYY-MM-DD`), a time (`HH:MM[:SS]`) and a timezone (`+HH:MM`,
    /// `-HH:MM` or `Z`), each parsed as
    /// [`parse_date`](super::parse_date), [`parse_time`](super::parse_time) and
    /// [`parse_timezone`](super::parse_timezone) parse them.
    pub fn from_civil_text(date: &str, time: &str, zone: &str) -> Result<UtcInstant, ShadeError> {
        use super::time_text::{parse_date, parse_time, parse_timezone};
        Ok(UtcInstant::from_civil(parse_date(date)?, parse_time(time)?, parse_timezone(zone)?))
    }

    /// Seconds since 1970-01-01 00:00:00 UTC.
    pub fn unix_seconds(self) -> f64 {
        self.unix_seconds
    }

    /// The instant `seconds` later.
    pub fn plus_seconds(self, seconds: f64) -> UtcInstant {
        UtcInstant { unix_seconds: self.unix_seconds + seconds }
    }

    /// The Julian day (UT) of the instant.
    pub fn julian_day(self) -> f64 {
        self.unix_seconds / SECONDS_PER_DAY as f64 + UNIX_EPOCH_JULIAN_DAY
    }

    /// The local date and time (to the second) on clocks `offset` from UTC, as
    /// `YYYY-MM-DD HH:MM:SS +HH:MM`, for messages.
    pub fn local_text(self, offset: UtcOffset) -> String {
        let local = self.unix_seconds + f64::from(offset.minutes) * 60.0;
        if !local.is_finite() {
            return format!("{} s from 1970", self.unix_seconds);
        }
        let seconds = local.floor() as i64;
        let (days, in_day) =
            (seconds.div_euclid(SECONDS_PER_DAY), seconds.rem_euclid(SECONDS_PER_DAY));
        let (year, month, day) = civil_from_days(days);
        let (h, m, s) = (in_day / 3600, in_day / 60 % 60, in_day % 60);
        format!("{year:04}-{month:02}-{day:02} {h:02}:{m:02}:{s:02} {offset}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_count_days_from_1970_both_ways() {
        let epoch = CivilDate::new(1970, 1, 1).unwrap();
        assert_eq!(epoch.days_since_epoch(), 0);
        assert_eq!(CivilDate::new(2000, 3, 1).unwrap().days_since_epoch(), 11_017);
        assert_eq!(CivilDate::new(1969, 12, 31).unwrap().days_since_epoch(), -1);
        assert_eq!(CivilDate::new(1, 1, 1).unwrap().days_since_epoch(), -719_162);
        // Every day of four centuries round-trips, in order.
        let start = CivilDate::new(1900, 1, 1).unwrap();
        let mut previous = start;
        for k in 1..146_097 {
            let date = start.plus_days(k).unwrap();
            assert_eq!(date.days_since_epoch(), start.days_since_epoch() + k);
            assert!(date > previous);
            previous = date;
        }
        assert_eq!(previous.plus_days(1).unwrap(), CivilDate::new(2300, 1, 1).unwrap());
    }

    #[test]
    fn dates_that_do_not_exist_are_refused_by_name() {
        let error = CivilDate::new(2026, 2, 30).unwrap_err().to_string();
        assert!(error.contains("2026-02-30 does not exist: February 2026 has 28 days"), "{error}");
        assert!(CivilDate::new(2024, 2, 29).is_ok());
        assert!(CivilDate::new(1900, 2, 29).is_err());
        assert!(CivilDate::new(2000, 2, 29).is_ok());
        assert!(CivilDate::new(2026, 4, 31).is_err());
        assert!(CivilDate::new(2026, 13, 1).unwrap_err().to_string().contains("no month 13"));
        assert!(CivilDate::new(2026, 1, 0).is_err());
        assert!(CivilDate::new(0, 1, 1).is_err());
        assert!(CivilDate::new(9999, 12, 31).unwrap().plus_days(1).is_err());
    }

    #[test]
    fn instants_of_local_clocks() {
        let date = CivilDate::new(2003, 10, 17).unwrap();
        let time = TimeOfDay::new(12, 30, 30.0).unwrap();
        let offset = UtcOffset::from_minutes(-7 * 60).unwrap();
        let instant = UtcInstant::from_civil(date, time, offset);
        // 2003-10-17 19:30:30 UTC.
        assert_eq!(instant.unix_seconds(), 1_066_419_030.0);
        assert_eq!(instant.local_text(offset), "2003-10-17 12:30:30 -07:00");
        assert_eq!(instant.local_text(UtcOffset::UTC), "2003-10-17 19:30:30 +00:00");
        assert!((instant.julian_day() - 2452930.312847).abs() < 1e-6);
        assert!(TimeOfDay::new(24, 0, 0.0).is_err());
        assert!(TimeOfDay::new(23, 60, 0.0).is_err());
        assert!(UtcOffset::from_minutes(19 * 60).is_err());
    }
}
