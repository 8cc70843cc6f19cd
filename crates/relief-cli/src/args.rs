//! Command-line arguments of every subcommand.

use clap::{Args, Parser, Subcommand};
use relief_core::{DVec3, Surface};
use relief_trace::TracerKind;
use std::path::PathBuf;

/// relief: exact, fast ray casting of terrain on the CPU.
#[derive(Debug, Parser)]
#[command(name = "relief", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a height field to a PNG (and optionally its depth and normals as .npy).
    Render(Box<RenderArgs>),
    /// Write a synthetic terrain.
    #[command(subcommand)]
    Generate(GenerateCommand),
    /// Describe a height-field file.
    Info(InfoArgs),
    /// Measure the tracers on fixed views of the seeded fBm terrain.
    Bench(BenchArgs),
}

/// Where the height field comes from and how it is placed in the world.
#[derive(Debug, Args)]
pub struct InputArgs {
    /// Height-field file (.npy). Without one, the seeded fBm terrain is used.
    pub input: Option<PathBuf>,
    /// Texel spacing DX[,DY] in world units (default 1).
    #[arg(long, value_parser = parse_spacing)]
    pub spacing: Option<(f64, f64)>,
    /// The array's row 0 is its north edge (as in most north-up rasters): flip the rows.
    #[arg(long)]
    pub north_up: bool,
    /// Multiply sample values by this to get world heights.
    #[arg(long, default_value_t = 1.0)]
    pub z_scale: f64,
    /// Size of the default fBm terrain (when no INPUT is given).
    #[arg(long, default_value_t = 1024)]
    pub fbm_size: usize,
    /// Seed of the default fBm terrain.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// `relief render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Input and its placement.
    #[command(flatten)]
    pub input: InputArgs,
    /// Surface to render: boxes (flat-topped texels) or triangles.
    #[arg(long, default_value = "triangles")]
    pub surface: Surface,
    /// Tracer: naive or mipmap (both exact).
    #[arg(long, default_value = "mipmap")]
    pub tracer: TracerKind,
    /// Camera position X,Y,Z (world units); framed automatically when absent.
    #[arg(long, value_parser = parse_vec3, requires = "target")]
    pub eye: Option<DVec3>,
    /// Point looked at X,Y,Z.
    #[arg(long, value_parser = parse_vec3, requires = "eye")]
    pub target: Option<DVec3>,
    /// Camera up vector X,Y,Z.
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,1")]
    pub up: DVec3,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 45.0)]
    pub fov: f64,
    /// Image size WxH in pixels.
    #[arg(long, value_parser = parse_size, default_value = "1280x720")]
    pub size: (u32, u32),
    /// Sun AZIMUTH,ELEVATION in degrees (azimuth clockwise from north).
    #[arg(long, value_parser = parse_sun, default_value = "315,35", allow_hyphen_values = true)]
    pub sun: (f64, f64),
    /// Do not trace shadow rays.
    #[arg(long)]
    pub no_shadows: bool,
    /// Colour texture (PNG) draped over the terrain's footprint, top row north.
    #[arg(long)]
    pub texture: Option<PathBuf>,
    /// Exposure applied before tone mapping.
    #[arg(long, default_value_t = 1.0)]
    pub exposure: f64,
    /// Output PNG.
    #[arg(short, long, default_value = "relief.png")]
    pub output: PathBuf,
    /// Also write the distance to the first hit per pixel (.npy, f32, H x W, +inf on a miss).
    #[arg(long)]
    pub depth: Option<PathBuf>,
    /// Also write the unit world normal per pixel (.npy, f32, H x W x 3, zero on a miss).
    #[arg(long)]
    pub normals: Option<PathBuf>,
}

/// `relief generate`.
#[derive(Debug, Subcommand)]
pub enum GenerateCommand {
    /// Seeded fractional Brownian motion mountains.
    Fbm(FbmArgs),
}

/// `relief generate fbm`.
#[derive(Debug, Args)]
pub struct FbmArgs {
    /// Width and height in samples.
    #[arg(long, default_value_t = 1024)]
    pub size: usize,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output file (.npy, float32).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `relief info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Height-field file.
    pub input: PathBuf,
}

/// `relief bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Size of the fBm terrain in samples per side.
    #[arg(long, default_value_t = 4096)]
    pub size: usize,
    /// Image size WxH.
    #[arg(long, value_parser = parse_size, default_value = "1920x1080")]
    pub res: (u32, u32),
    /// Seed of the terrain.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Tracers to measure (comma-separated).
    #[arg(long, value_delimiter = ',', default_values = ["naive", "mipmap"])]
    pub tracers: Vec<TracerKind>,
    /// Surfaces to measure (comma-separated).
    #[arg(long, value_delimiter = ',', default_values = ["boxes", "triangles"])]
    pub surfaces: Vec<Surface>,
}

fn parse_numbers<const N: usize>(s: &str, what: &str) -> Result<[f64; N], String> {
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

fn parse_vec3(s: &str) -> Result<DVec3, String> {
    parse_numbers::<3>(s, "X,Y,Z").map(DVec3::from_array)
}

fn parse_sun(s: &str) -> Result<(f64, f64), String> {
    let [azimuth, elevation] = parse_numbers::<2>(s, "AZIMUTH,ELEVATION")?;
    if !(-90.0..=90.0).contains(&elevation) {
        return Err(format!("sun elevation {elevation} is outside -90..90 degrees"));
    }
    Ok((azimuth, elevation))
}

fn parse_spacing(s: &str) -> Result<(f64, f64), String> {
    let values = if s.contains(',') {
        parse_numbers::<2>(s, "DX,DY")?
    } else {
        let [d] = parse_numbers::<1>(s, "DX")?;
        [d, d]
    };
    if values.iter().any(|&v| v <= 0.0) {
        return Err(format!("spacing '{s}' must be positive"));
    }
    Ok((values[0], values[1]))
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("expected WxH, got '{s}'"))?;
    let parse =
        |v: &str| {
            v.trim().parse::<u32>().ok().filter(|&n| (1..=32768).contains(&n)).ok_or_else(|| {
                format!("'{v}' in '{s}' is not an image dimension between 1 and 32768")
            })
        };
    Ok((parse(w)?, parse(h)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_refuses_values() {
        assert_eq!(parse_size("96x64"), Ok((96, 64)));
        assert!(parse_size("0x64").is_err() && parse_size("96").is_err());
        assert_eq!(parse_spacing("2"), Ok((2.0, 2.0)));
        assert_eq!(parse_spacing("2,3"), Ok((2.0, 3.0)));
        assert!(parse_spacing("-1").is_err());
        assert!(parse_vec3("1,2").is_err() && parse_vec3("1,2,nan").is_err());
        assert!(parse_sun("10,95").is_err());
    }
}
