//! Command-line arguments of every subcommand.

use crate::tracers::TracerChoice;
use clap::{Args, Parser, Subcommand, ValueEnum};
use relief_core::{DVec3, Precision, Surface};
use relief_shade::mlhm::MlhmPreset;
use relief_trace::{MlhmBacktrack, SafetyOptions, Simd};
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
    /// Render a height field or an MLHM scene (.json or .mlhm) to a PNG (and optionally its depth and
    /// normals as .npy).
    Render(Box<RenderArgs>),
    /// Write a synthetic terrain.
    #[command(subcommand)]
    Generate(GenerateCommand),
    /// Describe a height file.
    Info(InfoArgs),
    /// Convert a height file to another format (by the output's extension).
    Convert(ConvertArgs),
    /// Measure the tracers on fixed views of the seeded fBm terrain.
    Bench(BenchArgs),
}

/// How height files are read.
#[derive(Debug, Args)]
pub struct ReadArgs {
    /// Voids (nodata): fill them from their surroundings, or keep them as holes [default: fill;
    /// for convert, hole, so that they stay the output's nodata].
    #[arg(long, value_enum)]
    pub voids: Option<Voids>,
    /// Memory a raster may take, e.g. 512M, 8G (default: half the machine's memory).
    #[arg(long, value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    /// How a PNG encodes heights.
    #[arg(long, value_enum, default_value = "grey")]
    pub png_encoding: PngHeights,
    /// The array to read from an .npz archive (default: the first).
    #[arg(long)]
    pub array: Option<String>,
}

/// `--voids`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Voids {
    /// Nearest valid sample, then smoothed.
    Fill,
    /// Empty texels the rays pass through.
    Hole,
}

/// `--png-encoding`.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PngHeights {
    /// 16- or 8-bit grey values.
    Grey,
    /// Mapbox terrain-RGB tiles.
    TerrainRgb,
    /// Terrarium tiles.
    Terrarium,
}

/// Where the height field comes from and how it is placed in the world.
#[derive(Debug, Args)]
pub struct InputArgs {
    /// Height file: .tif/.tiff (GeoTIFF), .hgt (SRTM), .asc (ESRI ASCII grid), .png (16-bit grey,
    /// terrain-RGB, Terrarium), .npy or .npz; or a multi-layered height map scene (.json, the
    /// reference simulator's format, or .mlhm, relief's own). Without one, the seeded fBm
    /// terrain is used.
    pub input: Option<PathBuf>,
    /// How to read it.
    #[command(flatten)]
    pub read: ReadArgs,
    /// Texel spacing DX[,DY] in world units (default: from the file's georeference, else 1).
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
    /// Surface to render: boxes (flat-topped texels) or triangles [default: triangles; an MLHM
    /// scene is always boxes, see --mode].
    #[arg(long)]
    pub surface: Option<Surface>,
    /// Tracer: naive, mipmap (both exact, no precomputation) or safety (precomputed safety
    /// shapes for static terrain, triangles only; see --safety), or a safety variant by name
    /// [default: mipmap]. For an MLHM scene (.json or .mlhm): naive or hierarchy [default: hierarchy].
    #[arg(long)]
    pub tracer: Option<TracerChoice>,
    /// MLHM scenes: how their columns are rendered: boxes, or smooth (the terrain they stand
    /// for, smoothed in all three dimensions over a cube of half-size --sigma) [default: boxes].
    #[arg(long, value_parser = parse_mlhm_render_mode)]
    pub mode: Option<MlhmRenderMode>,
    /// MLHM smooth mode: the smoothing radius in metres, the half-size of the cube whose
    /// terrain volume defines the surface [default: one cell].
    #[arg(long)]
    pub sigma: Option<f64>,
    /// MLHM scenes: quality preset (Nilles & Müller 2025, section 5): low (no secondary rays,
    /// no AO), mid (water reflections and refractions with cheap absorption, sun shadows, AO
    /// of radius 1 m), high (expensive absorption, shadows and AO on reflected and refracted
    /// surfaces too) or max (AO of radius 2 m) [default: mid].
    #[arg(long)]
    pub preset: Option<MlhmPreset>,
    /// MLHM scenes, hierarchy tracer: store its bounds as f32 or f16 (half the memory, rounded
    /// outwards so they stay conservative; the same image) [default: f32].
    #[arg(long, value_parser = parse_precision)]
    pub hierarchy_bounds: Option<Precision>,
    /// MLHM scenes, hierarchy tracer: how its traversal climbs back up, by a stack of exit
    /// distances or a miss counter: stack or miss [default: stack].
    #[arg(long)]
    pub backtrack: Option<MlhmBacktrack>,
    /// Safety-shape options.
    #[command(flatten)]
    pub safety: SafetyArgs,
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
    /// MLHM scenes: leave the preset's ambient occlusion out.
    #[arg(long)]
    pub no_ao: bool,
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

/// `--mode`: how an MLHM scene's columns are rendered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MlhmRenderMode {
    /// Every column as a box over its cell (Nilles & Müller 2025, 4.1).
    Boxes,
    /// The smooth implicit surface of the boxes: where a cube of half-size `--sigma` around a
    /// point is half full of terrain (Nilles & Müller 2025, 3.3 and 4.3-4.6).
    Smooth,
}

fn parse_precision(s: &str) -> Result<Precision, String> {
    match s {
        "f32" => Ok(Precision::F32),
        "f16" => Ok(Precision::F16),
        _ => Err(format!("unknown precision '{s}' (expected f32 or f16)")),
    }
}

fn parse_mlhm_render_mode(s: &str) -> Result<MlhmRenderMode, String> {
    match s {
        "boxes" => Ok(MlhmRenderMode::Boxes),
        "smooth" => Ok(MlhmRenderMode::Smooth),
        _ => Err(format!("unknown mode '{s}' (expected boxes or smooth)")),
    }
}

/// Options of the safety tracer (Baboud et al. 2011).
#[derive(Debug, Args)]
pub struct SafetyArgs {
    /// Safety shapes: cyl_all or cyl_ext (cylinders for all rays, or for exterior rays only:
    /// cameras outside the terrain's box), optionally +cone_all (conservative cones), +cone_ext
    /// (exact cones for exterior rays) or +cone_exact (exact cones for all rays).
    #[arg(long, default_value = "cyl_all+cone_all")]
    pub safety: SafetyOptions,
    /// Build the shapes for rays at most this many degrees from horizontal (e.g. -45: views
    /// looking down at least 45 degrees); other views are refused.
    #[arg(long, allow_hyphen_values = true)]
    pub phi_max: Option<f64>,
    /// One shape per texel for all four ray classes (less memory, slower).
    #[arg(long)]
    pub isotropic: bool,
    /// Clamp safety distances to at least one: faster, small errors at sharp silhouettes.
    #[arg(long)]
    pub positive: bool,
    /// Final test on the view-dependent linear surface instead of the two triangles: faster,
    /// approximate between centerlines.
    #[arg(long)]
    pub linear_surface: bool,
    /// Farthest step, in texels, a shape may allow.
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u16).range(1..))]
    pub safety_reach: u16,
    /// Where precomputed shapes are kept [default: $RELIEF_CACHE_DIR, $XDG_CACHE_HOME/relief
    /// or ~/.cache/relief].
    #[arg(long)]
    pub cache_dir: Option<PathBuf>,
    /// Neither read nor write the shape cache.
    #[arg(long)]
    pub no_cache: bool,
}

/// `relief generate`.
#[derive(Debug, Subcommand)]
pub enum GenerateCommand {
    /// Seeded fractional Brownian motion mountains.
    Fbm(FbmArgs),
    /// A multi-layered height map scene (the reference simulator's JSON + .dat).
    Mlhm(MlhmArgs),
}

/// `relief generate mlhm`.
#[derive(Debug, Args)]
pub struct MlhmArgs {
    /// Scene: rivers-rain (fBm hills on a slope, one column per cell), or a carved scene with
    /// overhangs: arches, cave, chasm, overhangs, combined. Every scene is 256 m square.
    #[arg(long, value_name = "NAME")]
    pub scene: String,
    /// Cells per side (the cell size is 256 m / N).
    #[arg(long, value_name = "N")]
    pub size: usize,
    /// Seed of rivers-rain's noise (the carved scenes are fixed shapes).
    #[arg(long, default_value_t = relief_sim::RIVERS_RAIN_SEED)]
    pub seed: u64,
    /// Column slots per cell, 1 to 127 (carved scenes need up to 4; fewer fills their
    /// thinnest air gaps).
    #[arg(long, default_value_t = 4, value_name = "L")]
    pub max_layers: usize,
    /// Store the values as f16 (rounded conservatively) instead of f32.
    #[arg(long)]
    pub half: bool,
    /// Memory generation may take, e.g. 512M, 8G (default: half the machine's memory).
    #[arg(long, value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    /// Output: scene.mlhm (relief's own file, an NPZ archive) or scene.json (the reference
    /// simulator's scene, its .dat written beside it with the same name).
    #[arg(short, long)]
    pub output: PathBuf,
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
    /// Height file.
    pub input: PathBuf,
    /// How to read it.
    #[command(flatten)]
    pub read: ReadArgs,
}

/// `relief convert`.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// Height file to read.
    pub input: PathBuf,
    /// File to write: .tif (float32 GeoTIFF), .hgt, .asc, .png (16-bit grey) or .npy; an MLHM
    /// scene converts between .json and .mlhm.
    pub output: PathBuf,
    /// How to read the input (voids are kept as nodata unless --voids fill is given).
    #[command(flatten)]
    pub read: ReadArgs,
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
    /// Tracers to measure (comma-separated): naive, mipmap, safety, or safety variants by name
    /// (cyl_all, cyl_all+cone_all, cyl_ext, ...). Safety shapes are always precomputed afresh
    /// here, and their build time reported.
    #[arg(long, value_delimiter = ',', default_values = ["naive", "mipmap"])]
    pub tracers: Vec<TracerChoice>,
    /// Safety-shape options (for every safety tracer measured).
    #[command(flatten)]
    pub safety: SafetyArgs,
    /// Surfaces to measure (comma-separated).
    #[arg(long, value_delimiter = ',', default_values = ["boxes", "triangles"])]
    pub surfaces: Vec<Surface>,
    /// Views to measure (comma-separated): three-quarter, flight, top-down, cover (the terrain
    /// fills the image, seen from 60 degrees up: every ray looks down at least 45 degrees).
    #[arg(long, value_delimiter = ',', default_values = ["three-quarter", "flight", "top-down"])]
    pub views: Vec<String>,
    /// Measure this height file (spacing 1, z scale 1) instead of generating the fBm terrain.
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// Print one JSON object per measurement (with the camera) instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write each measurement's depth image (.npy, as `render --depth`) into this folder.
    #[arg(long)]
    pub depth_dir: Option<PathBuf>,
    /// Trace every view this many times and report the fastest (the G-buffer is allocated
    /// once, as a renderer drawing frame after frame does).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    pub repeat: u32,
    /// Instructions of the mipmap tracer's packet tests: auto (the fastest this processor
    /// has), avx2 or portable.
    #[arg(long, default_value = "auto")]
    pub simd: Simd,
    /// Trace one ray at a time instead of in batches (the mipmap tracer's single-ray
    /// traversal instead of its packets), for comparison.
    #[arg(long)]
    pub single_rays: bool,
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

fn parse_bytes(s: &str) -> Result<u64, String> {
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
        _ => return Err(format!("'{s}': expected a size like 512M or 8G")),
    };
    let value: f64 =
        digits.parse().map_err(|_| format!("'{s}': expected a size like 512M or 8G"))?;
    if !(value.is_finite() && value > 0.0) {
        return Err(format!("'{s}' must be a positive size"));
    }
    Ok((value * factor as f64) as u64)
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
        assert_eq!(parse_mlhm_render_mode("boxes"), Ok(MlhmRenderMode::Boxes));
        assert_eq!(parse_mlhm_render_mode("smooth"), Ok(MlhmRenderMode::Smooth));
        assert!(parse_mlhm_render_mode("spheres").is_err());
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("2GiB"), Ok(2 << 30));
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert!(parse_bytes("12Q").is_err() && parse_bytes("-1G").is_err());
    }
}
