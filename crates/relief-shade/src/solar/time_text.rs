//! Civil time as people write it: dates `YYYY-MM-DD`, ranges of dates `FROM..TO`, times
//! `HH:MM[:SS]`, timezones `+HH:MM`, `-HH:MM` or `Z`, time steps `15m`, `1h`, `30s`, and
//! ISO-8601 instants with an offset (`2026-06-21T09:30:00+02:00`); every refusal names the
//! text and says what was expected.

use super::civil_time::{CivilDate, TimeOfDay, UtcInstant, UtcOffset, SECONDS_PER_DAY};
use crate::ShadeError;

/// Most days a range of dates may span (a century).
pub const MAX_RANGE_DAYS: i64 = 36_525;

/// An inclusive range of calendar days, `first <= last`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DateRange {
    /// The first day.
    pub first: CivilDate,
    /// The last day (included).
    pub last: CivilDate,
}

impl DateRange {
    /// Days in the range, at least 1.
    pub fn days(&self) -> i64 {
        self.last.days_since_epoch() - self.first.days_since_epoch() + 1
    }
}

/// A date `YYYY-MM-DD` that exists.
///
/// ```
/// use relief_shade::solar::parse_date;
/// assert_eq!(parse_date("2026-06-21").unwrap().to_string(), "2026-06-21");
/// let error = parse_date("2026-02-30").unwrap_err().to_string();
/// assert!(error.contains("2026-02-30 does not exist"), "{error}");
/// ```
pub fn parse_date(text: &str) -> Result<CivilDate, ShadeError> {
    let refuse = || ShadeError::parameter("date", format!("{text:?} is not a date YYYY-MM-DD"));
    let parts: Vec<&str> = text.trim().split('-').collect();
    let [year, month, day] = parts.as_slice() else {
        return Err(refuse());
    };
    if year.len() != 4 || month.len() != 2 || day.len() != 2 {
        return Err(refuse());
    }
    CivilDate::new(
        digits(year).ok_or_else(refuse)?,
        digits(month).ok_or_else(refuse)?,
        digits(day).ok_or_else(refuse)?,
    )
}

/// A date `YYYY-MM-DD` or an inclusive range `FROM..TO` of them (`FROM <= TO`, at most
/// [`MAX_RANGE_DAYS`] days).
pub fn parse_date_range(text: &str) -> Result<DateRange, ShadeError> {
    let Some((from, to)) = text.split_once("..") else {
        let day = parse_date(text)?;
        return Ok(DateRange { first: day, last: day });
    };
    let range = DateRange { first: parse_date(from)?, last: parse_date(to)? };
    if range.first > range.last {
        return Err(ShadeError::parameter(
            "date",
            format!("{text}: the range ends ({}) before it begins ({})", range.last, range.first),
        ));
    }
    if range.days() > MAX_RANGE_DAYS {
        return Err(ShadeError::parameter(
            "date",
            format!("{text}: {} days, over the {MAX_RANGE_DAYS} a range may span", range.days()),
        ));
    }
    Ok(range)
}

/// A time of day `HH:MM` (00:00 to 23:59), or `HH:MM:SS[.fff]`.
pub fn parse_time(text: &str) -> Result<TimeOfDay, ShadeError> {
    let refuse = || {
        ShadeError::parameter(
            "time",
            format!("{text:?} is not a time of day HH:MM (00:00 to 23:59)"),
        )
    };
    let parts: Vec<&str> = text.trim().split(':').collect();
    let (hour, minute, second) = match parts.as_slice() {
        [h, m] => (*h, *m, 0.0),
        [h, m, s] => {
            let (whole, fraction) = s.split_once('.').unwrap_or((s, ""));
            if whole.len() != 2 || digits::<u32>(whole).is_none() {
                return Err(refuse());
            }
            if !fraction.is_empty() && digits::<u64>(fraction).is_none() {
                return Err(refuse());
            }
            (*h, *m, s.parse::<f64>().map_err(|_| refuse())?)
        }
        _ => return Err(refuse()),
    };
    if hour.len() != 2 || minute.len() != 2 {
        return Err(refuse());
    }
    let (hour, minute) = (digits(hour).ok_or_else(refuse)?, digits(minute).ok_or_else(refuse)?);
    TimeOfDay::new(hour, minute, second).map_err(|_| refuse())
}

/// A timezone as an offset from UTC: `Z` (or `UTC`), `+HH:MM`, `-HH:MM`, `+HHMM` or `+HH`.
pub fn parse_timezone(text: &str) -> Result<UtcOffset, ShadeError> {
    let refuse = || {
        ShadeError::parameter(
            "timezone",
            format!("{text:?} is not an offset from UTC: +HH:MM, -HH:MM or Z"),
        )
    };
    let text = text.trim();
    if text == "Z" || text == "z" || text.eq_ignore_ascii_case("UTC") {
        return Ok(UtcOffset::UTC);
    }
    let (sign, rest) = match text.as_bytes().first() {
        Some(b'+') => (1, &text[1..]),
        Some(b'-') => (-1, &text[1..]),
        _ => return Err(refuse()),
    };
    if !rest.is_ascii() {
        return Err(refuse());
    }
    let (hours, minutes) = match (rest.len(), rest.split_once(':')) {
        (_, Some((h, m))) => (h, m),
        (4, None) => rest.split_at(2),
        (2, None) => (rest, "00"),
        _ => return Err(refuse()),
    };
    if hours.len() != 2 || minutes.len() != 2 {
        return Err(refuse());
    }
    let (hours, minutes): (i32, i32) =
        (digits(hours).ok_or_else(refuse)?, digits(minutes).ok_or_else(refuse)?);
    if minutes >= 60 {
        return Err(refuse());
    }
    UtcOffset::from_minutes(sign * (hours * 60 + minutes))
}

/// A time step in seconds: a positive whole number with a unit, `s`, `m` (minutes) or `h`
/// (`30s`, `15m`, `1h`), at most a day.
pub fn parse_step(text: &str) -> Result<f64, ShadeError> {
    let refuse = |why: &str| ShadeError::parameter("step", format!("{text:?} {why}"));
    let text = text.trim();
    let units = [('s', 1), ('m', 60), ('h', 3600)];
    let Some((number, scale)) =
        units.iter().find_map(|&(unit, scale)| Some((text.strip_suffix(unit)?, scale)))
    else {
        return Err(refuse("is not a step like 30s, 15m or 1h"));
    };
    let count: i64 = digits(number).ok_or_else(|| refuse("is not a step like 30s, 15m or 1h"))?;
    let seconds = count.saturating_mul(scale);
    if seconds == 0 || seconds > SECONDS_PER_DAY {
        return Err(refuse("is not a step of 1 s to 24 h"));
    }
    Ok(seconds as f64)
}

/// An ISO-8601 instant with its offset from UTC: `YYYY-MM-DDTHH:MM[:SS[.fff]]` (or a space
/// for the `T`) followed by `Z`, `+HH:MM`, `-HH:MM` or `+HHMM`. An instant without an offset
/// is refused: it names no instant.
///
/// ```
/// use relief_shade::solar::parse_iso8601_instant;
/// let instant = parse_iso8601_instant("2026-06-21T09:30:00+02:00").unwrap();
/// assert_eq!(instant, parse_iso8601_instant("2026-06-21T07:30Z").unwrap());
/// assert!(parse_iso8601_instant("2026-06-21T09:30:00").is_err());
/// ```
pub fn parse_iso8601_instant(text: &str) -> Result<UtcInstant, ShadeError> {
    let trimmed = text.trim();
    let Some((date, clock)) = trimmed.split_once(['T', 't', ' ']) else {
        return Err(ShadeError::parameter(
            "time",
            format!("{text:?} is not an ISO-8601 instant YYYY-MM-DDTHH:MM:SS+HH:MM"),
        ));
    };
    let zone_at = clock.find(['Z', 'z', '+', '-']).ok_or_else(|| {
        ShadeError::parameter(
            "time",
            format!("{text:?} has no offset from UTC: end it with Z or +HH:MM"),
        )
    })?;
    let (time, zone) = clock.split_at(zone_at);
    Ok(UtcInstant::from_civil(parse_date(date)?, parse_time(time)?, parse_timezone(zone)?))
}

/// A non-negative whole number of ASCII digits only (no sign, no spaces).
fn digits<T: std::str::FromStr>(text: &str) -> Option<T> {
    if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    text.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_and_ranges() {
        assert_eq!(parse_date(" 2024-02-29 ").unwrap(), CivilDate::new(2024, 2, 29).unwrap());
        for bad in ["2026-6-21", "2026/06/21", "21-06-2026", "2026-06-21x", "", "+026-06-21"] {
            let error = parse_date(bad).unwrap_err().to_string();
            assert!(error.contains("is not a date YYYY-MM-DD"), "{bad}: {error}");
        }
        assert!(parse_date("2026-02-30").unwrap_err().to_string().contains("2026-02-30"));
        let range = parse_date_range("2026-06-01..2026-06-30").unwrap();
        assert_eq!(range.days(), 30);
        assert_eq!(parse_date_range("2026-06-21").unwrap().days(), 1);
        let error = parse_date_range("2026-06-30..2026-06-01").unwrap_err().to_string();
        assert!(error.contains("ends (2026-06-01) before it begins (2026-06-30)"), "{error}");
        assert!(parse_date_range("2026-06-01..2026-02-30").is_err());
        assert!(parse_date_range("1900-01-01..2026-01-01").is_err());
    }

    #[test]
    fn times_of_day() {
        assert_eq!(parse_time("09:30").unwrap().seconds_since_midnight(), 34_200.0);
        assert_eq!(parse_time("00:00").unwrap(), TimeOfDay::MIDNIGHT);
        assert_eq!(parse_time("23:59:30.5").unwrap().seconds_since_midnight(), 86_370.5);
        for bad in ["24:00", "9:30", "09:60", "09-30", "09:30:60", "ab:cd", "09:30:5", ""] {
            let error = parse_time(bad).unwrap_err().to_string();
            assert!(error.contains("is not a time of day HH:MM"), "{bad}: {error}");
        }
    }

    #[test]
    fn timezones() {
        assert_eq!(parse_timezone("Z").unwrap(), UtcOffset::UTC);
        assert_eq!(parse_timezone("+02:00").unwrap().minutes(), 120);
        assert_eq!(parse_timezone("-07:00").unwrap().minutes(), -420);
        assert_eq!(parse_timezone("+0530").unwrap().minutes(), 330);
        assert_eq!(parse_timezone("-03").unwrap().minutes(), -180);
        for bad in ["02:00", "+2:00", "+02:60", "CET", "+", "+02:00:00", "+1\u{e9}1", "\u{e9}"] {
            assert!(parse_timezone(bad).is_err(), "{bad}");
        }
        assert!(parse_timezone("+19:00").unwrap_err().to_string().contains("18:00"));
    }

    #[test]
    fn steps() {
        assert_eq!(parse_step("15m").unwrap(), 900.0);
        assert_eq!(parse_step("1h").unwrap(), 3600.0);
        assert_eq!(parse_step("30s").unwrap(), 30.0);
        assert_eq!(parse_step("24h").unwrap(), 86_400.0);
        for bad in ["0m", "15", "m", "-5m", "1.5h", "25h", "15 m", "1d", "", "15\u{e9}"] {
            assert!(parse_step(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn iso8601_instants() {
        let a = parse_iso8601_instant("2026-06-21T09:30:00+02:00").unwrap();
        let b = UtcInstant::from_civil_text("2026-06-21", "07:30", "Z").unwrap();
        assert_eq!(a, b);
        let c = parse_iso8601_instant("2026-06-21 02:30:00.25-05:00").unwrap();
        assert_eq!(c.unix_seconds(), b.unix_seconds() + 0.25);
        let error = parse_iso8601_instant("2026-06-21T09:30:00").unwrap_err().to_string();
        assert!(error.contains("no offset from UTC"), "{error}");
        assert!(parse_iso8601_instant("2026-06-21").is_err());
        assert!(parse_iso8601_instant("2026-02-30T09:30Z").is_err());
    }
}
