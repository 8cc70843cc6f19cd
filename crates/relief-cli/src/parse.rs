//! Parsers of option values: numbers as users type them (negative ones included), each held
//! to the range the algorithm behind it handles, with messages that quote what was typed.

use relief_core::{DVec3, Precision};
use std::ops::RangeInclusive;

/// Largest distance from the origin, in metres, a camera coordinate may have: beyond it an
/// f64 world position no longer resolves a millimetre.
pub const MAX_COORDINATE: f64 = 1e9;

/// Texel spacing and height scale relief places grids with (world units per grid unit).
pub const SCALE_RANGE: RangeInclusive<f64> = 1e-6..=1e7;

/// Vertical field of view in degrees: a pinhole camera needs more than 0 and less than 180.
pub const FOV_RANGE: RangeInclusive<f64> = 0.01..=179.0;

/// Exposure before tone mapping: a factor of 10^4 either way already gives a black or a
/// white picture.
pub const EXPOSURE_RANGE: RangeInclusive<f64> = 1e-4..=1e4;

/// The `values` in `s`, comma-separated, each a finite number.
fn numbers<const N: usize>(s: &str, what: &str) -> Result<[f64; N], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!("expected {N} comma-separated numbers for {what}, got '{s}'"));
    }
    let mut out = [0.0; N];
    for (o, p) in out.iter_mut().zip(&parts) {
        *o = p.parse::<f64>().map_err(|_| format!("'{p}' is not a number"))?;
        if !o.is_finite() {
            return Err(format!("'{p}' is not a finite number"));
        }
    }
    Ok(out)
}

/// A range's ends as a reader wants them: `0.01..179`, `1e-6..1e7`.
pub fn range_text(range: &RangeInclusive<f64>) -> String {
    format!("{}..{}", readable(*range.start()), readable(*range.end()))
}

/// A number for a message: plain decimals for everyday magnitudes, scientific notation for
/// the rest (never 300 digits).
pub fn readable(v: f64) -> String {
    if v == 0.0 || (1e-4..1e9).contains(&v.abs()) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// One number within `range`; `what` names it in the message.
pub fn number_in(s: &str, what: &str, range: &RangeInclusive<f64>) -> Result<f64, String> {
    let [v] = numbers::<1>(s, what)?;
    if !range.contains(&v) {
        return Err(format!("{what} {s} is outside {}", range_text(range)));
    }
    Ok(v)
}

/// `X,Y,Z`: a camera position or target, each coordinate within ±[`MAX_COORDINATE`].
pub fn point(s: &str) -> Result<DVec3, String> {
    let v = DVec3::from_array(numbers::<3>(s, "X,Y,Z")?);
    if v.abs().max_element() > MAX_COORDINATE {
        return Err(format!(
            "'{s}' is farther than {} m from the origin on an axis",
            readable(MAX_COORDINATE)
        ));
    }
    Ok(v)
}

/// `X,Y,Z`: a direction (the camera's up), not zero.
pub fn direction(s: &str) -> Result<DVec3, String> {
    let v = DVec3::from_array(numbers::<3>(s, "X,Y,Z")?);
    if v.length() == 0.0 || !v.length().is_finite() {
        return Err(format!("'{s}' is not a direction (its length must be finite and not 0)"));
    }
    Ok(v)
}

/// `AZIMUTH,ELEVATION` in degrees: azimuth -360..360, elevation -90..90.
pub fn sun(s: &str) -> Result<(f64, f64), String> {
    let [azimuth, elevation] = numbers::<2>(s, "AZIMUTH,ELEVATION")?;
    if !(-360.0..=360.0).contains(&azimuth) {
        return Err(format!("sun azimuth in '{s}' is outside -360..360 degrees"));
    }
    if !(-90.0..=90.0).contains(&elevation) {
        return Err(format!("sun elevation in '{s}' is outside -90..90 degrees"));
    }
    Ok((azimuth, elevation))
}

/// `--view AZ,EL[,DISTANCE]`: the compass direction a framed camera looks towards, its
/// elevation above the horizon, and its distance from the target, if given.
pub use relief_render::ViewAngles;

/// `AZ,EL[,DISTANCE]`: azimuth -360..360 degrees, elevation more than 0 and at most 90,
/// distance positive and at most [`MAX_COORDINATE`] metres.
pub fn view(s: &str) -> Result<ViewAngles, String> {
    let (azimuth_deg, elevation_deg, distance) = match s.split(',').count() {
        3 => {
            let [a, e, d] = numbers::<3>(s, "AZ,EL,DISTANCE")?;
            (a, e, Some(d))
        }
        _ => {
            let [a, e] = numbers::<2>(s, "AZ,EL[,DISTANCE]")?;
            (a, e, None)
        }
    };
    if !(-360.0..=360.0).contains(&azimuth_deg) {
        return Err(format!("view azimuth in '{s}' is outside -360..360 degrees"));
    }
    if !(elevation_deg > 0.0 && elevation_deg <= 90.0) {
        return Err(format!(
            "view elevation in '{s}' must be more than 0 and at most 90 degrees (90: straight \
             down)"
        ));
    }
    if let Some(d) = distance {
        if !(d > 0.0 && d <= MAX_COORDINATE) {
            return Err(format!(
                "view distance in '{s}' must be more than 0 and at most {} m",
                readable(MAX_COORDINATE)
            ));
        }
    }
    Ok(ViewAngles { azimuth_deg, elevation_deg, distance })
}

/// `--ortho-height`: the orthographic image's height in metres, positive and at most
/// 2 [`MAX_COORDINATE`].
pub fn ortho_height(s: &str) -> Result<f64, String> {
    let [h] = numbers::<1>(s, "metres")?;
    if !(h > 0.0 && h <= 2.0 * MAX_COORDINATE) {
        return Err(format!(
            "orthographic height {s} must be more than 0 and at most {} m",
            readable(2.0 * MAX_COORDINATE)
        ));
    }
    Ok(h)
}

/// `DX[,DY]`: texel spacing, each within [`SCALE_RANGE`].
pub fn spacing(s: &str) -> Result<(f64, f64), String> {
    let values = if s.contains(',') {
        numbers::<2>(s, "DX,DY")?
    } else {
        let [d] = numbers::<1>(s, "DX")?;
        [d, d]
    };
    if values.iter().any(|v| !SCALE_RANGE.contains(v)) {
        return Err(format!(
            "spacing '{s}' must be positive, within {} world units",
            range_text(&SCALE_RANGE)
        ));
    }
    Ok((values[0], values[1]))
}

/// Heights a colour map's range and sea level may take, metres: deeper than any ocean and
/// higher than any mountain, by far.
pub const HEIGHT_RANGE: RangeInclusive<f64> = -1e6..=1e6;

/// `MIN,MAX`: the heights in metres at a colour map's two ends, within [`HEIGHT_RANGE`], the
/// lower first.
pub fn height_range(s: &str) -> Result<(f64, f64), String> {
    let [lo, hi] = numbers::<2>(s, "MIN,MAX")?;
    if !(HEIGHT_RANGE.contains(&lo) && HEIGHT_RANGE.contains(&hi)) {
        return Err(format!("heights {s} are outside {} m", range_text(&HEIGHT_RANGE)));
    }
    if lo >= hi {
        return Err(format!("'{s}' must be MIN,MAX with MIN below MAX"));
    }
    Ok((lo, hi))
}

/// A height in metres within [`HEIGHT_RANGE`] (the sea level).
pub fn height(s: &str) -> Result<f64, String> {
    number_in(s, "height", &HEIGHT_RANGE).map_err(|e| format!("{e} m"))
}

/// The height scale, within [`SCALE_RANGE`] (a negative one would turn the terrain upside
/// down).
pub fn z_scale(s: &str) -> Result<f64, String> {
    number_in(s, "z scale", &SCALE_RANGE)
}

/// The vertical field of view, within [`FOV_RANGE`] degrees.
pub fn fov(s: &str) -> Result<f64, String> {
    number_in(s, "field of view", &FOV_RANGE).map_err(|e| format!("{e} degrees"))
}

/// The exposure, within [`EXPOSURE_RANGE`].
pub fn exposure(s: &str) -> Result<f64, String> {
    number_in(s, "exposure", &EXPOSURE_RANGE)
}

/// A positive, finite length in metres (its upper and lower bounds depend on the scene and
/// are checked there).
pub fn positive_length(s: &str) -> Result<f64, String> {
    number_in(s, "length", &(f64::MIN_POSITIVE..=f64::MAX))
        .map_err(|_| format!("'{s}' must be a positive length in metres"))
}

/// The safety shapes' phi max in degrees, strictly between -90 and 90.
pub fn phi_max(s: &str) -> Result<f64, String> {
    let [phi] = numbers::<1>(s, "degrees")?;
    if !(phi > -90.0 && phi < 90.0) {
        return Err(format!("phi max {s} must be strictly between -90 and 90 degrees"));
    }
    Ok(phi)
}

/// `f32` or `f16`.
pub fn precision(s: &str) -> Result<Precision, String> {
    match s {
        "f32" => Ok(Precision::F32),
        "f16" => Ok(Precision::F16),
        _ => Err(format!("unknown precision '{s}' (expected f32 or f16)")),
    }
}

/// A size in bytes: `512M`, `8G`, `2GiB`, `1000`.
pub fn bytes(s: &str) -> Result<u64, String> {
    let s = s.trim();
    let (digits, unit) = match s.find(|c: char| !c.is_ascii_digit() && c != '.') {
        Some(i) => s.split_at(i),
        None => (s, ""),
    };
    let factor: u64 = match unit.to_ascii_uppercase().trim_end_matches("IB").trim_end_matches('B') {
        "" => 1,
        "K" => 1 << 10,
        "M" => 1 << 20,
        "G" => 1 << 30,
        "T" => 1 << 40,
        _ => return Err(format!("'{s}': expected a positive size like 512M or 8G")),
    };
    let value: f64 =
        digits.parse().map_err(|_| format!("'{s}': expected a positive size like 512M or 8G"))?;
    if !(value.is_finite() && value >= 1.0) {
        return Err(format!("'{s}' must be a size of at least 1 byte"));
    }
    Ok((value * factor as f64).min(u64::MAX as f64) as u64)
}

/// `WxH`: an image size, each side 1 to 32768 pixels.
pub fn image_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("expected WxH, got '{s}'"))?;
    let side =
        |v: &str| {
            v.trim().parse::<u32>().ok().filter(|&n| (1..=32768).contains(&n)).ok_or_else(|| {
                format!("'{v}' in '{s}' is not an image dimension between 1 and 32768")
            })
        };
    Ok((side(w)?, side(h)?))
}

/// A whole number within `range`, parsed from what was typed (negative numbers included, so
/// that they get this message and not the parser's).
pub fn whole_in(s: &str, range: RangeInclusive<u64>, what: &str) -> Result<u64, String> {
    let text = s.trim();
    let in_range = text
        .parse::<i128>()
        .ok()
        .filter(|&v| (i128::from(*range.start())..=i128::from(*range.end())).contains(&v));
    match in_range {
        Some(v) => Ok(v as u64),
        None => Err(format!(
            "{what} '{s}' is not a whole number between {} and {}",
            range.start(),
            range.end()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_parsed_and_held_to_their_ranges() {
        assert_eq!(image_size("96x64"), Ok((96, 64)));
        assert!(image_size("0x64").is_err() && image_size("96").is_err());
        assert_eq!(spacing("2"), Ok((2.0, 2.0)));
        assert_eq!(spacing("2,3"), Ok((2.0, 3.0)));
        assert!(spacing("-1").is_err() && spacing("1e300").is_err());
        assert_eq!(point("-100,-150,420"), Ok(DVec3::new(-100.0, -150.0, 420.0)));
        assert!(point("1,2").is_err() && point("1,2,nan").is_err() && point("1e10,0,0").is_err());
        assert!(direction("0,0,0").is_err());
        assert!(sun("10,95").is_err() && sun("-45,-10").is_ok());
        let v = view("-45,30").unwrap();
        assert_eq!((v.azimuth_deg, v.elevation_deg, v.distance), (-45.0, 30.0, None));
        assert_eq!(view("0,90,250").unwrap().distance, Some(250.0));
        assert!(view("0,0").is_err() && view("0,-10").is_err() && view("0,91").is_err());
        assert!(view("400,30").is_err() && view("0,30,0").is_err() && view("0,30,-5").is_err());
        assert!(view("0").is_err() && view("0,30,5,6").is_err() && view("0,nan").is_err());
        assert!(ortho_height("0").is_err() && ortho_height("-2").is_err());
        assert_eq!(ortho_height("120"), Ok(120.0));
        assert!(fov("0").is_err() && fov("180").is_err() && fov("60").is_ok());
        assert!(exposure("-1").is_err() && exposure("0").is_err() && exposure("2").is_ok());
        assert!(z_scale("-3").is_err() && z_scale("3").is_ok());
        assert!(phi_max("-45").is_ok() && phi_max("-90").is_err());
        assert_eq!(bytes("512M"), Ok(512 << 20));
        assert_eq!(bytes("2GiB"), Ok(2 << 30));
        assert_eq!(bytes("1000"), Ok(1000));
        assert!(bytes("12Q").is_err() && bytes("-1G").is_err() && bytes("0").is_err());
        assert_eq!(whole_in("7", 1..=10, "n"), Ok(7));
        assert!(whole_in("-7", 1..=10, "n").unwrap_err().contains("between 1 and 10"));
    }

    #[test]
    fn messages_print_numbers_readably() {
        assert_eq!(readable(1e300), "1e300");
        assert_eq!(readable(2.5), "2.5");
        assert_eq!(readable(1e-6), "1e-6");
        assert_eq!(range_text(&SCALE_RANGE), "1e-6..10000000");
        let message = spacing("1e300").unwrap_err();
        assert!(message.len() < 100, "{message}");
    }
}
