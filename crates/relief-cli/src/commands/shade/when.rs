//! When and where the sun shines on the DEM for `relief shade`: `--date`, `--time`,
//! `--timezone`, `--step`, `--lat` and `--lon`, turned (with the DEM's georeference) into one
//! sun for the instantaneous shadow layer or the sun's samples over days for insolation.

use crate::parse;
use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use relief_io::{GeographicPosition, Georeference};
use relief_shade::shade_map::SunPosition;
use relief_shade::solar::{
    parse_date_range, parse_step, parse_time, parse_timezone, solar_position, sun_samples_over,
    DateRange, Observer, SunSample, TimeOfDay, UtcInstant, UtcOffset,
};

/// The time step of insolation unless `--step` says otherwise, in seconds.
pub const DEFAULT_STEP_S: f64 = 900.0;

/// When the sun shines, and from where it is seen.
#[derive(Debug, Clone, Default, Args)]
pub struct SunTimeArgs {
    /// The sun of a date, YYYY-MM-DD: with --time, one sun for the shadow layer; alone, or as a
    /// range FROM..TO of dates (inclusive), the sun every --step over those days for
    /// insolation and sun hours. Positions by NREL's solar position algorithm.
    #[arg(long, value_name = "DATE[..DATE]", value_parser = date_range)]
    pub date: Option<DateRange>,
    /// The time of day of --date, HH:MM (00:00 to 23:59) on the clocks of --timezone.
    #[arg(long, value_name = "HH:MM", value_parser = time, requires = "date")]
    pub time: Option<TimeOfDay>,
    /// The offset from UTC of the clocks of --date and --time: +HH:MM, -HH:MM or Z
    /// [default: Z, UTC].
    #[arg(long, value_name = "+HH:MM", value_parser = timezone, allow_hyphen_values = true,
          requires = "date")]
    pub timezone: Option<UtcOffset>,
    /// The time step over the days of --date for insolation and sun hours: 30s, 15m, 1h (up
    /// to 24h); each step counts the sun at its middle [default: 15m].
    #[arg(long, value_name = "STEP", value_parser = step, requires = "date")]
    pub step: Option<f64>,
    /// The latitude in degrees (north positive) the sun is seen from [default: the DEM's
    /// centre, from its georeference].
    #[arg(long, value_name = "DEG", value_parser = latitude, allow_hyphen_values = true,
          requires_all = ["lon", "date"])]
    pub lat: Option<f64>,
    /// The longitude in degrees (east positive) the sun is seen from [default: the DEM's
    /// centre, from its georeference].
    #[arg(long, value_name = "DEG", value_parser = longitude, allow_hyphen_values = true,
          requires_all = ["lat", "date"])]
    pub lon: Option<f64>,
}

/// The sun that `--date` and its companions ask for, its azimuths on the DEM's grid (degrees
/// clockwise from +y: from true north turned by the meridians' convergence of a UTM DEM).
#[derive(Debug, Clone, PartialEq)]
pub enum SunTimes {
    /// No `--date`: the suns are those of `--sun`, or the default.
    NotAsked,
    /// `--date` of one day and `--time`: the sun at that instant, above the horizon.
    Instant(SunPosition),
    /// `--date` (a day or a range) without `--time`: the sun at the middle of every step of
    /// those days, night included (its beam is 0).
    Period(Vec<SunSample>),
}

/// The sun of `args` for a DEM of `width x height` samples placed by `georeference` (seen
/// from `--lat`/`--lon`, else from the DEM's centre): [`SunTimes::Instant`] for a date and a
/// time (an error when the sun is below the horizon then), [`SunTimes::Period`] for a date or
/// a range without a time.
pub fn sun_samples(
    args: &SunTimeArgs,
    georeference: Option<&Georeference>,
    width: usize,
    height: usize,
) -> Result<SunTimes> {
    let Some(days) = args.date else {
        if args.time.is_some() || args.step.is_some() || args.lat.is_some() || args.lon.is_some() {
            bail!("--time, --step, --lat and --lon need --date");
        }
        return Ok(SunTimes::NotAsked);
    };
    let place = place(args, georeference, width, height)?;
    // Compass azimuths onto the grid; a CRS that says nothing of it is taken as north-up.
    let true_north = georeference.and_then(|g| g.true_north_deg(width, height).ok()).unwrap_or(0.0);
    let on_grid = |azimuth_deg: f64| (azimuth_deg + true_north).rem_euclid(360.0);
    let observer = Observer::at(place.latitude_deg, place.longitude_deg);
    let offset = args.timezone.unwrap_or(UtcOffset::UTC);
    match args.time {
        Some(time) => {
            if days.first != days.last {
                bail!(
                    "--time {} asks for one instant, but --date {}..{} is a range of days: give \
                     one date with --time, or leave --time out for insolation over the range",
                    clock_text(time),
                    days.first,
                    days.last
                );
            }
            if args.step.is_some() {
                bail!("--step is the time step over days; --time asks for one instant");
            }
            let instant = UtcInstant::from_civil(days.first, time, offset);
            let sun = solar_position(instant, &observer)?;
            if sun.apparent_elevation_deg <= 0.0 {
                bail!(
                    "the sun is below the horizon at {} seen from {} (elevation {:.2} degrees): \
                     the shadow layer needs it up; choose another --time",
                    instant.local_text(offset),
                    place_text(place),
                    sun.apparent_elevation_deg
                );
            }
            Ok(SunTimes::Instant(SunPosition {
                azimuth_deg: on_grid(sun.azimuth_deg),
                elevation_deg: sun.apparent_elevation_deg,
            }))
        }
        None => {
            let step = args.step.unwrap_or(DEFAULT_STEP_S);
            let mut suns = sun_samples_over(days, offset, step, &observer)?;
            for sun in &mut suns {
                sun.azimuth_deg = on_grid(sun.azimuth_deg);
            }
            Ok(SunTimes::Period(suns))
        }
    }
}

/// Where the sun is seen from: `--lat`/`--lon`, else the centre of the DEM by its
/// georeference.
fn place(
    args: &SunTimeArgs,
    georeference: Option<&Georeference>,
    width: usize,
    height: usize,
) -> Result<GeographicPosition> {
    match (args.lat, args.lon, georeference) {
        (Some(latitude_deg), Some(longitude_deg), _) => {
            Ok(GeographicPosition { latitude_deg, longitude_deg })
        }
        (Some(_), None, _) | (None, Some(_), _) => bail!("give both --lat and --lon, or neither"),
        (None, None, Some(georeference)) => georeference
            .centre_position(width, height)
            .context("give the place of the sun with --lat and --lon"),
        (None, None, None) => Err(anyhow!(
            "the DEM has no georeference to say where on the earth it lies: give --lat and --lon"
        )),
    }
}

/// `46.95 N, 7.45 E`.
fn place_text(place: GeographicPosition) -> String {
    let (lat, lon) = (place.latitude_deg, place.longitude_deg);
    let ns = if lat < 0.0 { 'S' } else { 'N' };
    let ew = if lon < 0.0 { 'W' } else { 'E' };
    format!("{:.4} {ns}, {:.4} {ew}", lat.abs(), lon.abs())
}

/// `09:30`.
fn clock_text(time: TimeOfDay) -> String {
    let minutes = (time.seconds_since_midnight() / 60.0) as u32;
    format!("{:02}:{:02}", minutes / 60, minutes % 60)
}

/// `--date`: a date or a range of dates.
fn date_range(s: &str) -> Result<DateRange, String> {
    parse_date_range(s).map_err(|e| e.to_string())
}

/// `--time`: a time of day.
fn time(s: &str) -> Result<TimeOfDay, String> {
    parse_time(s).map_err(|e| e.to_string())
}

/// `--timezone`: an offset from UTC.
fn timezone(s: &str) -> Result<UtcOffset, String> {
    parse_timezone(s).map_err(|e| e.to_string())
}

/// `--step`: a time step in seconds.
fn step(s: &str) -> Result<f64, String> {
    parse_step(s).map_err(|e| e.to_string())
}

/// `--lat`: degrees in [-90, 90].
fn latitude(s: &str) -> Result<f64, String> {
    parse::number_in(s, "latitude", &(-90.0..=90.0))
}

/// `--lon`: degrees in [-180, 180].
fn longitude(s: &str) -> Result<f64, String> {
    parse::number_in(s, "longitude", &(-180.0..=180.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    /// A command of only these options.
    #[derive(Debug, Parser)]
    struct When {
        #[command(flatten)]
        when: SunTimeArgs,
    }

    fn parse(args: &[&str]) -> Result<SunTimeArgs, String> {
        let argv = std::iter::once("relief").chain(args.iter().copied());
        When::try_parse_from(argv).map(|w| w.when).map_err(|e| e.to_string())
    }

    /// A 1" SRTM tile around 46.5 N, 7.5 E.
    fn alps() -> Georeference {
        Georeference::srtm_tile(46, 7, 3601)
    }

    #[test]
    fn options_parse_and_refuse_by_name() {
        let args = parse(&["--date", "2026-06-21", "--time", "09:30", "--timezone", "+02:00"]);
        let args = args.unwrap();
        assert_eq!(args.timezone.unwrap().minutes(), 120);
        assert_eq!(args.time.unwrap().seconds_since_midnight(), 34_200.0);
        let args =
            parse(&["--date", "2026-06-01..2026-06-30", "--step", "1h", "--timezone", "-05:00"]);
        assert_eq!(args.unwrap().date.unwrap().days(), 30);
        let args = parse(&["--date", "2026-06-21", "--lat", "-33.9", "--lon", "-70.6"]).unwrap();
        assert_eq!((args.lat, args.lon), (Some(-33.9), Some(-70.6)));
        for (bad, says) in [
            (vec!["--date", "2026-02-30"], "2026-02-30 does not exist"),
            (vec!["--date", "2026-06-21", "--time", "24:00"], "is not a time of day"),
            (vec!["--date", "2026-06-21", "--timezone", "CET"], "is not an offset from UTC"),
            (vec!["--date", "2026-06-21", "--step", "15"], "is not a step like"),
            (vec!["--date", "2026-06-30..2026-06-01"], "before it begins"),
            (vec!["--time", "09:30"], "--date"),
            (vec!["--date", "2026-06-21", "--lat", "46"], "--lon"),
            (vec!["--date", "2026-06-21", "--lat", "91", "--lon", "0"], "latitude 91 is outside"),
        ] {
            let error = parse(&bad).unwrap_err();
            assert!(error.contains(says), "{bad:?}: {error}");
        }
    }

    #[test]
    fn one_instant_for_the_shadow_layer() {
        let args = parse(&["--date", "2026-06-21", "--time", "12:30", "--timezone", "+01:00"]);
        let SunTimes::Instant(sun) =
            sun_samples(&args.unwrap(), Some(&alps()), 3601, 3601).unwrap()
        else {
            panic!("not one instant");
        };
        // Solar noon at 7.5 E on the solstice is 11:31:40 UTC (12:31:40 at +01:00): the sun
        // stands south, 90 - 46.5 + 23.44 = 66.94 degrees up.
        assert!((sun.azimuth_deg - 180.0).abs() < 2.0, "{sun:?}");
        assert!((sun.elevation_deg - 66.94).abs() < 0.05, "{sun:?}");
        let night = parse(&["--date", "2026-06-21", "--time", "23:30"]).unwrap();
        let error = sun_samples(&night, Some(&alps()), 3601, 3601).unwrap_err().to_string();
        assert!(
            error.starts_with("the sun is below the horizon at 2026-06-21 23:30:00 +00:00"),
            "{error}"
        );
        assert!(error.contains("46.5000 N, 7.5000 E"), "{error}");
        let range = parse(&["--date", "2026-06-01..2026-06-02", "--time", "09:30"]).unwrap();
        let error = sun_samples(&range, Some(&alps()), 3601, 3601).unwrap_err().to_string();
        assert!(error.contains("is a range of days"), "{error}");
        let both = parse(&["--date", "2026-06-21", "--time", "09:30", "--step", "1h"]).unwrap();
        assert!(sun_samples(&both, Some(&alps()), 3601, 3601).is_err());
    }

    #[test]
    fn samples_over_days_for_insolation() {
        let args = parse(&["--date", "2026-06-21..2026-06-22", "--lat", "46.5", "--lon", "7.5"]);
        let SunTimes::Period(suns) = sun_samples(&args.unwrap(), None, 10, 10).unwrap() else {
            panic!("not a period");
        };
        // Two days at the default 15 minutes; the night's samples stay, with no beam.
        assert_eq!(suns.len(), 192);
        assert_eq!(suns.iter().map(|s| s.hours).sum::<f64>(), 48.0);
        assert!(suns.iter().any(|s| s.elevation_deg < 0.0 && s.beam_w_m2 == 0.0));
        let alone = parse(&["--date", "2026-06-21", "--step", "1h"]).unwrap();
        let SunTimes::Period(hourly) = sun_samples(&alone, Some(&alps()), 3601, 3601).unwrap()
        else {
            panic!("not a period");
        };
        assert_eq!(hourly.len(), 24);
        assert_eq!(sun_samples(&SunTimeArgs::default(), None, 1, 1).unwrap(), SunTimes::NotAsked);
    }

    #[test]
    fn azimuths_on_a_utm_grid_turn_with_the_meridians() {
        // 1000 x 1000 pixels of 10 m centred on (690237, 5202641) in UTM zone 32 N (46.95 N,
        // 11.5 E): true north lies 1.827 degrees counterclockwise of the grid's north.
        let tags = relief_io::GeoTiffTags {
            model_pixel_scale: Some(vec![10.0, 10.0, 0.0]),
            model_tiepoint: Some(vec![0.0, 0.0, 0.0, 685_237.14, 5_207_641.64, 0.0]),
            // GTModelType projected, GTRasterType PixelIsArea, ProjectedCSType 32632.
            geo_key_directory: Some(vec![
                1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, 32632,
            ]),
            ..relief_io::GeoTiffTags::default()
        };
        let utm = Georeference::from_geotiff_tags(tags).unwrap();
        let args = parse(&["--date", "2026-06-21", "--time", "11:00"]).unwrap();
        let SunTimes::Instant(on_grid) = sun_samples(&args, Some(&utm), 1000, 1000).unwrap() else {
            panic!("not one instant");
        };
        let there =
            parse(&["--date", "2026-06-21", "--time", "11:00", "--lat", "46.95", "--lon", "11.5"]);
        let SunTimes::Instant(compass) = sun_samples(&there.unwrap(), None, 1, 1).unwrap() else {
            panic!("not one instant");
        };
        assert!((on_grid.elevation_deg - compass.elevation_deg).abs() < 1e-6);
        let turned = on_grid.azimuth_deg - compass.azimuth_deg;
        assert!((turned - -1.8274).abs() < 1e-3, "{turned}");
    }

    #[test]
    fn where_the_sun_is_seen_from() {
        let day = parse(&["--date", "2026-06-21"]).unwrap();
        let error = sun_samples(&day, None, 10, 10).unwrap_err().to_string();
        assert!(error.contains("no georeference") && error.contains("--lat and --lon"), "{error}");
        let bare = Georeference::north_up_grid(0.0, 100.0, 1.0, 1.0);
        let error = format!("{:#}", sun_samples(&day, Some(&bare), 10, 10).unwrap_err());
        assert!(
            error.contains("--lat and --lon") && error.contains("neither geographic"),
            "{error}"
        );
        // --lat and --lon win over the georeference.
        let there = parse(&["--date", "2026-06-21", "--lat", "-33.9", "--lon", "18.4"]).unwrap();
        let (SunTimes::Period(a), SunTimes::Period(b)) = (
            sun_samples(&there, Some(&alps()), 3601, 3601).unwrap(),
            sun_samples(&there, None, 1, 1).unwrap(),
        ) else {
            panic!("not periods");
        };
        assert_eq!(a, b);
        // Midwinter in Cape Town: the sun stands north at noon.
        let noon = a.iter().max_by(|x, y| x.elevation_deg.total_cmp(&y.elevation_deg)).unwrap();
        assert!((noon.azimuth_deg - 0.0).abs() < 15.0 || noon.azimuth_deg > 345.0, "{noon:?}");
        assert_eq!(
            place_text(GeographicPosition { latitude_deg: -1.0, longitude_deg: -2.0 }),
            "1.0000 S, 2.0000 W"
        );
    }
}
