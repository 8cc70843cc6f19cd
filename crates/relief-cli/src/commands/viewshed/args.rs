//! `relief viewshed`.

use crate::args::*;
use crate::parse;
use clap::Args;
use relief_core::Surface;
use std::path::PathBuf;

/// `relief viewshed`.
#[derive(Debug, Args)]
pub struct ViewshedArgs {
    /// The DEM: .tif/.tiff (GeoTIFF), .hgt, .asc, .png, .npy or .npz.
    pub input: PathBuf,
    /// How to read it (voids are filled for tracing, and are NaN in the output).
    #[command(flatten)]
    pub read: ReadArgs,
    /// The file to write: a float32 GeoTIFF on the DEM's grid, with its georeference, CRS and
    /// nodata; band `visible` (1 seen, 0 not) for one observer, `observers` (how many see
    /// each sample) for several.
    #[arg(short, long)]
    pub output: PathBuf,
    /// An observer, X,Y or X,Y,HEIGHT: X and Y in the DEM's own coordinates (its CRS; grid units,
    /// the first sample at 0.5,0.5, for a file without a georeference), HEIGHT of the eye
    /// above the ground in metres [default: 1.7]. Give it again for a cumulative viewshed.
    #[arg(long, value_parser = observer, allow_hyphen_values = true,
          action = clap::ArgAction::Append, value_name = "X,Y[,HEIGHT]")]
    pub observer: Vec<(f64, f64, Option<f64>)>,
    /// Height of the target above the ground at each sample, in metres.
    #[arg(long, default_value = "0", value_name = "M", value_parser = height,
          allow_hyphen_values = true)]
    pub target_height: f64,
    /// Horizontal distance in metres beyond which an observer sees nothing [default:
    /// unlimited].
    #[arg(long, value_name = "M", value_parser = radius, allow_hyphen_values = true)]
    pub radius: Option<f64>,
    /// The surface lines of sight must clear: triangles (through the samples) or boxes (a
    /// flat-topped column per sample).
    #[arg(long, default_value = "triangles")]
    pub surface: Surface,
    /// Texel spacing `DX[,DY]` in metres (default: from the file's georeference, else 1).
    #[arg(long, value_parser = parse::spacing, allow_hyphen_values = true)]
    pub spacing: Option<(f64, f64)>,
    /// Multiply heights by this (1e-6 to 1e7), after their unit is turned into metres (see
    /// --z-unit).
    #[arg(long, default_value = "1", value_parser = parse::z_scale, allow_hyphen_values = true)]
    pub z_scale: f64,
    /// Write the stage timings and ray counts to this .json file.
    #[arg(long, value_name = "F.json")]
    pub stats: Option<PathBuf>,
}

/// `--observer X,Y[,HEIGHT]`: finite coordinates, a height that is finite and at least 0.
pub fn observer(s: &str) -> Result<(f64, f64, Option<f64>), String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if !(2..=3).contains(&parts.len()) {
        return Err(format!("expected X,Y or X,Y,HEIGHT for an observer, got '{s}'"));
    }
    let number = |p: &str| -> Result<f64, String> {
        let v = p.parse::<f64>().map_err(|_| format!("'{p}' is not a number"))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("'{p}' is not a finite number"))
        }
    };
    let (x, y) = (number(parts[0])?, number(parts[1])?);
    let eye = match parts.get(2) {
        Some(p) => Some(height(p).map_err(|e| format!("observer height: {e}"))?),
        None => None,
    };
    Ok((x, y, eye))
}

/// A height above the ground: a finite number of metres, at least 0.
pub fn height(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        Ok(v) => Err(format!("{v} is not a finite height >= 0")),
        Err(_) => Err(format!("'{s}' is not a number")),
    }
}

/// `--radius`: a finite distance above 0.
fn radius(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        Ok(v) => Err(format!("{v} is not a finite distance > 0")),
        Err(_) => Err(format!("'{s}' is not a number")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn observers_are_parsed_and_checked() {
        assert_eq!(observer("10,-20"), Ok((10.0, -20.0, None)));
        assert_eq!(observer("10, 20, 5"), Ok((10.0, 20.0, Some(5.0))));
        assert!(observer("10").is_err() && observer("1,2,3,4").is_err());
        assert!(observer("1,2,-1").is_err() && observer("1,2,nan").is_err());
        assert!(observer("nan,2").is_err() && observer("1,inf").is_err());
        assert!(height("-0.5").is_err() && height("0").is_ok());
        assert!(radius("0").is_err() && radius("10").is_ok());
    }
}
