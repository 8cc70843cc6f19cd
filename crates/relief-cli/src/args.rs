//! Command-line arguments of every subcommand.

use crate::parse;
use crate::tracers::TracerChoice;
use clap::{Args, Parser, Subcommand, ValueEnum};
use relief_core::{DVec3, Precision, Surface};
use relief_shade::mlhm::MlhmPreset;
use relief_shade::ShadeLayer;
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
    /// Render a height field, an MLHM scene (.json or .mlhm) or a stacks terrain (.stacks, or
    /// any input with --mode mesh) to a PNG (and optionally its depth and normals as .npy).
    Render(Box<RenderArgs>),
    /// Write a synthetic terrain.
    #[command(subcommand)]
    Generate(GenerateCommand),
    /// Describe a height file, an MLHM scene (.json or .mlhm) or a stacks file (.stacks).
    Info(InfoArgs),
    /// Convert a height file to another format (by the output's extension).
    Convert(ConvertArgs),
    /// Measure the tracers on fixed views of the seeded fBm terrain.
    Bench(BenchArgs),
    /// Fly over a height field or an MLHM scene in a window (X11), rendered live: reduced
    /// while the camera moves, refined to full size at rest. Keys: F1 in the window, or the
    /// README.
    View(Box<ViewArgs>),
    /// Make shade rasters of a DEM, aligned with it sample for sample (its georeference, CRS
    /// and nodata): exact cast shadows, the sky-view factor, the Lambert hillshade and a map
    /// layer combining them.
    Shade(Box<ShadeArgs>),
    /// Run the reference simulator's layered hydraulic erosion on an MLHM scene (.json or
    /// .mlhm) and write the result; a .json scene keeps the simulation state (fluxes,
    /// stability, sediment, damage) and its step count, so runs continue where they stopped.
    Simulate(Box<SimulateArgs>),
    /// Compare a depth image with a reference one by the hybrid-rendering paper's metrics
    /// (Ammann et al. 2010, 4.1): PSNR over the pixels both hit, with R the terrain's
    /// bounding-box diagonal; wrong pixels (terrain against sky, or a hit more than a cell
    /// off along the ray); the largest relative error.
    Compare(CompareArgs),
    /// Build a tile pyramid of a raster far larger than memory, or of a mosaic of rasters
    /// (.hgt tiles placed by their names, GeoTIFFs by their georeference), for `relief render`
    /// to fly over in bounded memory. Streams the input; a build that stops resumes when run
    /// again.
    Tile(Box<TileArgs>),
    /// Render a camera path (recorded by `relief view`, R; docs/camera-path.md) over a tile
    /// store or any input `relief render` takes, frame after frame, to a folder of PNGs,
    /// printing each frame's time, tiles and memory. A store's frames after the first never
    /// wait for tiles (coarser ones stand in, so the frames depend on how fast the disk is)
    /// unless --wait is given; every other input gives the same frames every run.
    Flythrough(Box<FlythroughArgs>),
    /// Mesh a material-stack terrain (Löffler et al. 2011): a .stacks file, an MLHM scene
    /// (bedrock, sand, water) or a height file, smoothed and dual-contoured into a closed
    /// `solid` mesh and a `water` mesh, at one level of detail or at the levels a camera
    /// needs (crack-free between levels), written as glTF binary (.glb), OBJ or PLY.
    Mesh(Box<MeshArgs>),
}

/// How height files are read.
#[derive(Debug, Default, Args)]
pub struct ReadArgs {
    /// Voids (nodata): fill them from their surroundings, or keep them as holes [default: fill;
    /// for convert, hole, so that they stay the output's nodata].
    #[arg(long, value_enum)]
    pub voids: Option<Voids>,
    /// Memory a raster may take, e.g. 512M, 8G (default: half the machine's or cgroup's memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// How a PNG encodes heights (PNG input only) [default: grey].
    #[arg(long, value_enum)]
    pub png_encoding: Option<PngHeights>,
    /// The array to read from an .npz archive (.npz input only) [default: the first].
    #[arg(long)]
    pub array: Option<String>,
    /// The unit of the file's heights: m, ft (international foot) or us-ft (US survey foot)
    /// [default: the file's VerticalUnitsGeoKey, else its projected CRS's linear unit, else
    /// metres; `relief info` says which and why]. Heights are converted to metres.
    #[arg(long, value_name = "UNIT", value_parser = z_unit)]
    pub z_unit: Option<relief_io::LengthUnit>,
}

/// `--z-unit`: m, ft or us-ft.
fn z_unit(s: &str) -> Result<relief_io::LengthUnit, String> {
    s.parse()
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
    /// Texel spacing `DX[,DY]` in world units (default: from the file's georeference, else 1).
    #[arg(long, value_parser = parse::spacing, allow_hyphen_values = true)]
    pub spacing: Option<(f64, f64)>,
    /// The array's row 0 is its north edge (as in most north-up rasters): flip the rows.
    #[arg(long)]
    pub north_up: bool,
    /// Multiply heights by this (1e-6 to 1e7), after their unit is turned into metres (see
    /// --z-unit).
    #[arg(long, default_value = "1", value_parser = parse::z_scale, allow_hyphen_values = true)]
    pub z_scale: f64,
    /// Terrain samples per side of the default fBm terrain, when no INPUT is given (1 to
    /// 65536) [default: 1024].
    #[arg(long, value_name = "N", value_parser = terrain_side, allow_hyphen_values = true)]
    pub fbm_size: Option<usize>,
    /// Seed of the default fBm terrain, when no INPUT is given [default: 1].
    #[arg(long, value_parser = seed, allow_hyphen_values = true)]
    pub seed: Option<u64>,
}

/// What to render and how: the scene, the tracer, the camera and the light, shared by
/// `relief render` and `relief view`.
#[derive(Debug, Args)]
pub struct SceneArgs {
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
    /// How the terrain is drawn. MLHM scenes: boxes, or smooth (the terrain they stand for,
    /// smoothed in all three dimensions over a cube of half-size --sigma) [default: boxes].
    /// Any input: mesh (its material stacks smoothed over --sigma and dual-contoured at the
    /// camera's levels of detail, cells of at most --tau pixels, rasterized; Löffler et al.
    /// 2011), the only mode of a .stacks file.
    #[arg(long, value_parser = parse_mlhm_render_mode)]
    pub mode: Option<MlhmRenderMode>,
    /// MLHM smooth mode: the smoothing radius in metres, the half-size of the cube whose
    /// terrain volume defines the surface (1/64 of a cell to 8 cells) [default: one cell].
    /// Mesh mode: the standard deviation of the Gaussian smoothing the stacks' density, in
    /// metres [default: one cell].
    #[arg(long, value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub sigma: Option<f64>,
    /// Stacks meshes (--mode mesh; relief mesh --lod auto): the largest screen-space size of
    /// a mesh cell in pixels (Löffler et al. 2011, equation 1) [default: 10].
    #[arg(long, value_name = "PX", value_parser = tau_px, allow_hyphen_values = true)]
    pub tau: Option<f64>,
    /// Stacks meshes: the height of a density voxel at the finest level, metres; smaller
    /// voxels keep more of a DEM's relief whose spacing is coarse [default: the spacing].
    #[arg(long, value_name = "M", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub voxel_height: Option<f64>,
    /// MLHM scenes: quality preset (Nilles & Müller 2025, section 5): low (no secondary rays,
    /// no AO), mid (water reflections and refractions with cheap absorption, sun shadows, AO
    /// of radius 1 m), high (expensive absorption, shadows and AO on reflected and refracted
    /// surfaces too) or max (AO of radius 2 m) [default: mid].
    #[arg(long)]
    pub preset: Option<MlhmPreset>,
    /// MLHM scenes, hierarchy tracer: store its bounds as f32 or f16 (half the memory, rounded
    /// outwards so they stay conservative; the same image) [default: f32].
    #[arg(long, value_parser = parse::precision)]
    pub hierarchy_bounds: Option<Precision>,
    /// MLHM scenes, hierarchy tracer: how its traversal climbs back up, by a stack of exit
    /// distances or a miss counter: stack or miss [default: stack].
    #[arg(long)]
    pub backtrack: Option<MlhmBacktrack>,
    /// Safety-shape options.
    #[command(flatten)]
    pub safety: SafetyArgs,
    /// Camera position X,Y,Z in world units, e.g. --eye -100,-150,420; framed automatically
    /// when absent.
    #[arg(long, value_parser = parse::point, requires = "target", group = "placement", allow_hyphen_values = true)]
    pub eye: Option<DVec3>,
    /// Point looked at X,Y,Z (with --eye, or with --view instead of the terrain's centre).
    #[arg(long, value_parser = parse::point, requires = "placement", allow_hyphen_values = true)]
    pub target: Option<DVec3>,
    /// Camera up vector X,Y,Z, with --eye and --target; when it is parallel to the view (a
    /// camera looking straight down or up), north is at the top of the image [default: 0,0,1].
    #[arg(long, value_parser = parse::direction, requires = "eye", allow_hyphen_values = true)]
    pub up: Option<DVec3>,
    /// The camera looking towards compass AZ degrees (clockwise from north: north is +y, east
    /// +x, z is up; -360 to 360) from EL degrees above the horizon (more than 0, up to 90:
    /// straight down, with AZ at the top of the image, so 0,90 is a north-up map), at
    /// DISTANCE metres from the target (default: the framing's, at which the terrain fills the
    /// image). It looks at the terrain's centre, or at --target. Without --view and --eye the
    /// camera is --view 45,30 (from the south-west).
    #[arg(long, value_name = "AZ,EL[,DISTANCE]", value_parser = parse::view, group = "placement", allow_hyphen_values = true)]
    pub view: Option<parse::ViewAngles>,
    /// Orthographic camera: parallel rays along the view, from the plane through the eye
    /// perpendicular to it (the depth is measured from that plane); with --view 0,90 a map
    /// with a fixed ground size per pixel.
    #[arg(long)]
    pub ortho: bool,
    /// With --ortho: the image's height in metres [default: the framing's, at which the
    /// terrain fills the image].
    #[arg(long, value_name = "M", value_parser = parse::ortho_height, allow_hyphen_values = true)]
    pub ortho_height: Option<f64>,
    /// Vertical field of view in degrees (0.01 to 179) of the perspective camera [default:
    /// 45].
    #[arg(long, value_parser = parse::fov, allow_hyphen_values = true)]
    pub fov: Option<f64>,
    /// Image size WxH in pixels (not terrain samples: see --fbm-size).
    #[arg(long, value_parser = parse::image_size, default_value = "1280x720")]
    pub size: (u32, u32),
    /// Sun AZIMUTH,ELEVATION in degrees (azimuth clockwise from north, -360 to 360; elevation
    /// -90 to 90).
    #[arg(long, value_parser = parse::sun, default_value = "315,35", allow_hyphen_values = true)]
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
    /// Exposure applied before tone mapping (1e-4 to 1e4).
    #[arg(long, default_value = "1", value_parser = parse::exposure, allow_hyphen_values = true)]
    pub exposure: f64,
}

/// `relief render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene, tracer, camera and light.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output picture: .png, or .jpg/.jpeg.
    #[arg(short, long, default_value = "relief.png")]
    pub output: PathBuf,
    /// Also write the distance to the first hit per pixel (.npy, f32, H x W, +inf on a miss).
    #[arg(long)]
    pub depth: Option<PathBuf>,
    /// Also write the unit world normal per pixel (.npy, f32, H x W x 3, zero on a miss).
    #[arg(long)]
    pub normals: Option<PathBuf>,
    /// Write the stage timings to this JSON file after the render: load_ms (reading the
    /// input, framing), build_ms (the tracer's structures), trace_ms, shade_ms, write_ms and
    /// total_ms, with the rays, hits, image size and tracer. A height field's ray casters
    /// trace and shade strip by strip: trace_ms and shade_ms split that pass's time in
    /// proportion to the workers' time in each. For an MLHM scene the renderer shades as it
    /// traces: trace_ms holds both, shade_ms the tone mapping.
    #[arg(long, value_name = "JSON")]
    pub stats: Option<PathBuf>,
    /// How hard a .png picture is compressed: none, fast (several times faster to write than
    /// balanced, a slightly larger file), balanced or high (the smallest file) [default: fast].
    #[arg(long, value_name = "LEVEL")]
    pub png_compression: Option<relief_io::PngCompression>,
    /// Options of the hybrid renderer.
    #[command(flatten)]
    pub hybrid: HybridArgs,
    /// Options of tile stores.
    #[command(flatten)]
    pub tiles: TileRenderArgs,
}

/// `--lod`: a fixed level or the camera's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LodChoice {
    /// One level everywhere, 0 finest.
    Level(usize),
    /// The levels the camera needs.
    Auto,
}

fn parse_lod(s: &str) -> Result<LodChoice, String> {
    if s == "auto" {
        return Ok(LodChoice::Auto);
    }
    s.parse::<usize>()
        .map(LodChoice::Level)
        .map_err(|_| format!("'{s}' is not a level of detail (expected auto or 0, 1, 2, ...)"))
}

fn tau_px(s: &str) -> Result<f64, String> {
    parse::number_in(s, "a number of pixels", &(0.01..=1e4))
}

/// `relief mesh`: the scene options of `relief render` (input, camera, --sigma, --tau,
/// --voxel-height), the output, the level of detail and the stage timings. The options of
/// tracers, shading and MLHM rendering are hidden and refused (the sun and exposure, which have
/// defaults, are hidden and unused).
#[derive(Debug, Args)]
#[command(
    mut_arg("tracer", |a| a.hide(true)),
    mut_arg("surface", |a| a.hide(true)),
    mut_arg("mode", |a| a.hide(true)),
    mut_arg("preset", |a| a.hide(true)),
    mut_arg("hierarchy_bounds", |a| a.hide(true)),
    mut_arg("backtrack", |a| a.hide(true)),
    mut_arg("safety", |a| a.hide(true)),
    mut_arg("phi_max", |a| a.hide(true)),
    mut_arg("isotropic", |a| a.hide(true)),
    mut_arg("positive", |a| a.hide(true)),
    mut_arg("linear_surface", |a| a.hide(true)),
    mut_arg("safety_reach", |a| a.hide(true)),
    mut_arg("cache_dir", |a| a.hide(true)),
    mut_arg("no_cache", |a| a.hide(true)),
    mut_arg("sun", |a| a.hide(true)),
    mut_arg("no_shadows", |a| a.hide(true)),
    mut_arg("no_ao", |a| a.hide(true)),
    mut_arg("texture", |a| a.hide(true)),
    mut_arg("exposure", |a| a.hide(true))
)]
pub struct MeshArgs {
    /// The scene and camera (the camera matters with --lod auto).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output mesh: .glb (glTF 2.0 binary), .obj or .ply.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The level of detail, 0 the finest (the stacks themselves), each next level half as
    /// fine; or auto: per octree node, as fine as the camera needs for cells of at most --tau
    /// pixels [default: auto].
    #[arg(long, value_name = "N|auto", value_parser = parse_lod)]
    pub lod: Option<LodChoice>,
    /// Write the stage timings (load_ms, build_ms, mesh_ms, write_ms, total_ms) and the mesh's
    /// counts to this JSON file.
    #[arg(long, value_name = "JSON")]
    pub stats: Option<PathBuf>,
}

/// How a tile store (made by `relief tile`) is rendered.
#[derive(Debug, Clone, Args)]
pub struct TileRenderArgs {
    /// Tile stores: the largest screen-space error in pixels (0: the finest level
    /// everywhere) [default: 0.667, Dick et al. 2009].
    #[arg(long, value_name = "E", value_parser = non_negative_number, allow_hyphen_values = true)]
    pub max_error_px: Option<f64>,
    /// Tile stores: megabytes of tiles held in memory [default: 512].
    #[arg(long, value_name = "M", value_parser = cache_mb, allow_hyphen_values = true)]
    pub cache_mb: Option<u64>,
    /// Textured tile stores: how the ortho photo is filtered over each pixel's footprint,
    /// anisotropic (up to 16 trilinear samples along the footprint, Dick et al. 2009) or
    /// bilinear (one sample of the finest level) [default: anisotropic].
    #[arg(long, value_name = "FILTER", value_enum)]
    pub texture_filter: Option<TextureFilterChoice>,
    /// Textured tile stores: megabytes of texture tiles held in memory, besides --cache-mb
    /// [default: 256].
    #[arg(long, value_name = "M", value_parser = cache_mb, allow_hyphen_values = true)]
    pub texture_cache_mb: Option<u64>,
}

/// How a textured tile store's photo is filtered (`--texture-filter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TextureFilterChoice {
    /// The footprint's minor axis picks the mip level; up to 16 trilinear samples along its
    /// major axis.
    Anisotropic,
    /// One bilinear sample of the finest level, whatever the footprint.
    Bilinear,
}

impl TileRenderArgs {
    /// The first tile-store option given, if any (for refusing it with other inputs).
    pub fn given(&self) -> Option<&'static str> {
        [
            (self.max_error_px.is_some(), "--max-error-px"),
            (self.cache_mb.is_some(), "--cache-mb"),
            (self.texture_filter.is_some(), "--texture-filter"),
            (self.texture_cache_mb.is_some(), "--texture-cache-mb"),
        ]
        .into_iter()
        .find_map(|(given, name)| given.then_some(name))
    }

    /// The first option of textured stores given, if any (for refusing it on a store without
    /// a texture).
    pub fn texture_given(&self) -> Option<&'static str> {
        [
            (self.texture_filter.is_some(), "--texture-filter"),
            (self.texture_cache_mb.is_some(), "--texture-cache-mb"),
        ]
        .into_iter()
        .find_map(|(given, name)| given.then_some(name))
    }
}

fn non_negative_number(s: &str) -> Result<f64, String> {
    parse::number_in(s, "a number of pixels", &(0.0..=1e6))
}

fn cache_mb(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 16..=(1 << 24), "megabytes of cache")
}

/// `relief flythrough`. The camera options of `relief render` (`--eye`, `--target`, `--up`,
/// `--view`, `--fov`, `--ortho`, `--ortho-height`) are hidden and refused: the cameras come
/// from `--path`.
#[derive(Debug, Args)]
#[command(
    mut_arg("eye", |a| a.hide(true)),
    mut_arg("target", |a| a.hide(true)),
    mut_arg("up", |a| a.hide(true)),
    mut_arg("view", |a| a.hide(true)),
    mut_arg("fov", |a| a.hide(true)),
    mut_arg("ortho", |a| a.hide(true)),
    mut_arg("ortho_height", |a| a.hide(true))
)]
pub struct FlythroughArgs {
    /// The scene (INPUT: a tile store made by `relief tile`, a height file or an MLHM scene),
    /// tracer and light; --size is the frames' size.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The camera path: JSON as `relief view` records it (docs/camera-path.md).
    #[arg(long, value_name = "JSON")]
    pub path: PathBuf,
    /// Frames to render, spread evenly over the path's time span, from its first key to its
    /// last (1: the first key only; 1 to 100000).
    #[arg(long, value_name = "N", value_parser = frames, allow_hyphen_values = true)]
    pub frames: u32,
    /// The folder the frames are written to, as frame-00000.png, frame-00001.png, ...
    /// (created if missing; frames already there are overwritten).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Write every frame's figures (time_ms, tiles_drawn, tiles_standing_in, tiles_wanted,
    /// resident_bytes, rss_bytes, io_wait_ms, max_error_px, ...) and a summary (median_time_ms,
    /// ...) to this JSON file.
    #[arg(long, value_name = "JSON")]
    pub stats: Option<PathBuf>,
    /// Tile stores: every frame waits for the tiles it needs, as `relief render STORE` does
    /// (then each frame is that render of its camera, the same every run). Without it only the
    /// first frame waits; later ones draw the tiles in memory, coarser ones standing in for
    /// those still loading, so they depend on how fast the disk is.
    #[arg(long)]
    pub wait: bool,
    /// How hard the frames' PNGs are compressed: none, fast, balanced or high.
    #[arg(long, value_name = "LEVEL", default_value = "fast")]
    pub png_compression: relief_io::PngCompression,
    /// Options of tile stores.
    #[command(flatten)]
    pub tiles: TileRenderArgs,
}

/// `relief tile`.
#[derive(Debug, Args)]
pub struct TileArgs {
    /// The raster, or the rasters of a mosaic (.hgt tiles, or GeoTIFFs on one grid).
    #[arg(required = true, num_args = 1..)]
    pub inputs: Vec<PathBuf>,
    /// The store to write (a folder; resumed when it holds an interrupted build of the same
    /// inputs and options).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Samples along a tile's side (16 to 4096).
    #[arg(long, default_value_t = 512, value_parser = tile_samples)]
    pub tile: u32,
    /// Store samples as f32, or as f16 (half the disk, rounded to the nearest half) [default:
    /// f32].
    #[arg(long, value_parser = parse::precision)]
    pub precision: Option<Precision>,
    /// Memory the build's buffers may take, e.g. 512M, 2G (default: 1G).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// An ortho photo to drape over the DEM, stored as its own pyramid: an 8-bit RGB(A) PNG
    /// (taken to span the DEM's extent exactly, top row north) or GeoTIFF (placed by its
    /// georeference, which must be in the DEM's CRS and cover the DEM).
    #[arg(long, value_name = "ORTHO")]
    pub texture: Option<PathBuf>,
    /// The unit of the inputs' heights: m, ft (international foot) or us-ft (US survey foot)
    /// [default: the file's VerticalUnitsGeoKey, else its projected CRS's linear unit, else
    /// metres]. The store records it; renders take its heights in metres.
    #[arg(long, value_name = "UNIT", value_parser = z_unit)]
    pub z_unit: Option<relief_io::LengthUnit>,
}

fn tile_samples(s: &str) -> Result<u32, String> {
    parse::whole_in(s, 16..=4096, "samples per tile side").map(|v| v as u32)
}

/// Options of the hybrid renderer (`--tracer hybrid`, Ammann et al. 2010).
#[derive(Debug, Clone, Args)]
pub struct HybridArgs {
    /// Hybrid renderer: samples per side of a cell (2 to 4096; neighbouring cells share a
    /// line of samples) [default: 64].
    #[arg(long, value_name = "N", value_parser = cell_samples, allow_hyphen_values = true)]
    pub cell: Option<usize>,
    /// Hybrid renderer: rasterize a cell when its box covers more than T pixels per sample on
    /// screen (the paper's A/S > T; more than 0) [default: 70].
    #[arg(long, value_name = "T", value_parser = positive_number, allow_hyphen_values = true)]
    pub threshold: Option<f64>,
    /// Hybrid renderer: the heuristic's k (more than 0; larger gives more precise levels
    /// farther away) [default: 1.3].
    #[arg(long, value_name = "K", value_parser = positive_number, allow_hyphen_values = true)]
    pub k: Option<f64>,
    /// Hybrid renderer: number of levels of precision of the ray-cast cells (2 to 10; 4 are
    /// the paper's 55/25, 32/15, 16/10 and 8/5 linear/binary steps) [default: 4].
    #[arg(long, value_name = "N", value_parser = lop_levels, allow_hyphen_values = true)]
    pub lop: Option<usize>,
    /// Hybrid renderer: the cells it does not rasterize are ray cast exactly (exact: the whole
    /// image equals the exact tracer's) or at their levels of precision (lop: the paper's
    /// linear and binary searches, approximate, and slower on a CPU) [default: exact].
    #[arg(long, value_name = "lop|exact")]
    pub far: Option<relief_shade::FarField>,
    /// Hybrid renderer: colour each pixel by what drew it, as the paper's Figure 1: mesh
    /// (white), levels of precision from the most precise (green) to the least (red), the
    /// exact far field (blue).
    #[arg(long)]
    pub show_lop: bool,
}

impl HybridArgs {
    /// The first hybrid option given, if any (for refusing them with other tracers).
    pub fn given(&self) -> Option<&'static str> {
        [
            (self.cell.is_some(), "--cell"),
            (self.threshold.is_some(), "--threshold"),
            (self.k.is_some(), "--k"),
            (self.lop.is_some(), "--lop"),
            (self.far.is_some(), "--far"),
            (self.show_lop, "--show-lop"),
        ]
        .into_iter()
        .find_map(|(given, name)| given.then_some(name))
    }

    /// The heuristic's parameters these options give (the paper's defaults otherwise).
    pub fn params(&self) -> relief_shade::hybrid::HybridParams {
        let d = relief_shade::hybrid::HybridParams::default();
        relief_shade::hybrid::HybridParams {
            cell: self.cell.unwrap_or(d.cell),
            threshold: self.threshold.unwrap_or(d.threshold),
            k: self.k.unwrap_or(d.k),
            levels: self.lop.unwrap_or(d.levels),
        }
    }
}

/// `--cell`: 2 to 4096 samples.
fn cell_samples(s: &str) -> Result<usize, String> {
    parse::whole_in(s, 2..=4096, "cell").map(|v| v as usize)
}

/// `--lop`: 2 to 10 levels.
fn lop_levels(s: &str) -> Result<usize, String> {
    parse::whole_in(s, 2..=10, "number of levels of precision").map(|v| v as usize)
}

/// A finite number above 0.
fn positive_number(s: &str) -> Result<f64, String> {
    let v: f64 = s.trim().parse().map_err(|_| format!("'{s}' is not a number"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{s} must be a finite number above 0"))
    }
}

/// `relief compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The reference depth image (.npy, f32, H x W, +inf where the ray missed), e.g. the exact
    /// tracer's `relief render --depth`.
    pub reference: PathBuf,
    /// The depth image to judge against it, of the same shape.
    pub test: PathBuf,
    /// Print the metrics as one JSON object (psnr_db, null for identical images;
    /// wrong_pixel_fraction; max_rel_error; and the counts).
    #[arg(long)]
    pub json: bool,
    /// The terrain both were rendered from (any input relief render takes): R is the
    /// bounding-box diagonal of its solid and the cell its grid spacing (the larger of DX and
    /// DY). Without --terrain, --diagonal and --cell, R is the largest finite reference depth
    /// and the cell 1.
    #[arg(long, value_name = "IN")]
    pub terrain: Option<PathBuf>,
    /// With --terrain: its texel spacing `DX[,DY]`, as relief render's --spacing.
    #[arg(long, value_parser = parse::spacing, requires = "terrain", allow_hyphen_values = true)]
    pub spacing: Option<(f64, f64)>,
    /// With --terrain: the factor from its samples to world heights, as relief render's
    /// --z-scale [default: 1].
    #[arg(long, value_parser = parse::z_scale, requires = "terrain", allow_hyphen_values = true)]
    pub z_scale: Option<f64>,
    /// R of the PSNR in world units (overrides --terrain's).
    #[arg(long, value_name = "R", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub diagonal: Option<f64>,
    /// A hit more than this far from the reference's (world units, along the ray) is a wrong
    /// pixel (overrides --terrain's grid spacing).
    #[arg(long, value_name = "C", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub cell: Option<f64>,
    /// Memory each depth image (and --terrain) may take, e.g. 512M, 8G (default: half the
    /// machine's or cgroup's memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
}

/// `relief view`. The viewer flies pinhole cameras: `--ortho` and `--ortho-height` are
/// hidden and refused.
#[derive(Debug, Args)]
#[command(mut_arg("ortho", |a| a.hide(true)), mut_arg("ortho_height", |a| a.hide(true)))]
pub struct ViewArgs {
    /// The scene, tracer, starting camera and light (--size is the window's size when it
    /// opens; the full frame then follows the window, except in a --frames run).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// How a tile store is drawn.
    #[command(flatten)]
    pub tiles: TileRenderArgs,
    /// Render this many frames through the viewer's loop (playing --script, if given), then
    /// wait for the view to be complete at full size, save it to --screenshot and close: for
    /// tests and scripts (1 to 100000).
    #[arg(long, value_name = "N", value_parser = frames, allow_hyphen_values = true)]
    pub frames: Option<u32>,
    /// With --frames: the PNG the last frame is saved to (without the overlay).
    #[arg(long, value_name = "PNG", requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// With --frames: keys held or pressed frame by frame, instead of the keyboard: steps
    /// COUNT:KEYS separated by commas, keys joined by +, !K pressed once, - nothing. E.g.
    /// "30:W+Left,1:!T,10:-" flies forward turning left for 30 frames, switches the tracer and
    /// rests. Each frame moves the camera by 1/30 s.
    #[arg(long, requires = "frames", allow_hyphen_values = true)]
    pub script: Option<String>,
    /// Write every frame shown (size, whether the camera moved, render_ms, rays) to this JSON
    /// file when the viewer closes.
    #[arg(long, value_name = "JSON")]
    pub stats: Option<PathBuf>,
    /// Folder for screenshots (P: relief-view-NNN.png) and camera paths (R:
    /// relief-path-NNN.json) [default: the current folder].
    #[arg(long, value_name = "DIR")]
    pub output_dir: Option<PathBuf>,
    /// Time a frame may take while the camera moves, in milliseconds: the viewer renders at
    /// the largest reduced size that fits (5 to 1000; 50 is 20 frames/s).
    #[arg(long, value_name = "MS", default_value = "50", value_parser = frame_budget, allow_hyphen_values = true)]
    pub frame_budget: u64,
}

/// `--mode`: how an MLHM scene's columns are rendered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MlhmRenderMode {
    /// Every column as a box over its cell (Nilles & Müller 2025, 4.1).
    Boxes,
    /// The smooth implicit surface of the boxes: where a cube of half-size `--sigma` around a
    /// point is half full of terrain (Nilles & Müller 2025, 3.3 and 4.3-4.6).
    Smooth,
    /// The terrain as material stacks meshed by dual contouring at the camera's levels of
    /// detail (Löffler et al. 2011) and rasterized; any input.
    Mesh,
}

fn parse_mlhm_render_mode(s: &str) -> Result<MlhmRenderMode, String> {
    match s {
        "boxes" => Ok(MlhmRenderMode::Boxes),
        "smooth" => Ok(MlhmRenderMode::Smooth),
        "mesh" => Ok(MlhmRenderMode::Mesh),
        _ => Err(format!("unknown mode '{s}' (expected boxes, smooth or mesh)")),
    }
}

/// Options of the safety tracer (Baboud et al. 2011).
#[derive(Debug, Args)]
pub struct SafetyArgs {
    /// Safety shapes: cyl_all or cyl_ext (cylinders for all rays, or for exterior rays only:
    /// cameras outside the terrain's box), optionally +cone_all (conservative cones), +cone_ext
    /// (exact cones for exterior rays) or +cone_exact (exact cones for all rays).
    /// [default: cyl_all+cone_all]
    #[arg(long)]
    pub safety: Option<SafetyOptions>,
    /// Build the shapes for rays at most this many degrees from horizontal (e.g. -45: views
    /// looking down at least 45 degrees); other views are refused.
    #[arg(long, value_parser = parse::phi_max, allow_hyphen_values = true)]
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
    /// Farthest step, in texels, a shape may allow (1 to 1024) [default: 128].
    #[arg(long, value_name = "TEXELS", value_parser = safety_reach, allow_hyphen_values = true)]
    pub safety_reach: Option<u16>,
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
    /// A material-stack terrain (Löffler et al. 2011): seeded fBm bedrock with overhangs,
    /// caves and arches, sand on gentle slopes and water below a sea level.
    Stacks(StacksGenArgs),
}

/// `relief generate stacks`.
#[derive(Debug, Args)]
pub struct StacksGenArgs {
    /// Stacks along x (1 to 65536; the paper's benchmark terrain is 2048 x 4096).
    #[arg(long, value_name = "N", value_parser = terrain_side, allow_hyphen_values = true)]
    pub width: usize,
    /// Stacks along y (1 to 65536).
    #[arg(long, value_name = "N", value_parser = terrain_side, allow_hyphen_values = true)]
    pub height: usize,
    /// Random seed.
    #[arg(long, default_value = "1", value_parser = seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Distance between neighbouring stacks in metres.
    #[arg(long, value_name = "M", default_value = "2", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub spacing: f64,
    /// Highest height of the terrain in metres (the paper's 512 voxels of 1.5 m).
    #[arg(long, value_name = "M", default_value = "768", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub max_height: f64,
    /// Memory generation may take, e.g. 512M, 8G (default: half the machine's or cgroup's memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// Output: a .stacks file (relief's own material-stack file).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `relief generate mlhm`.
#[derive(Debug, Args)]
pub struct MlhmArgs {
    /// Scene: rivers-rain (fBm hills on a slope, one column per cell), or a carved scene with
    /// overhangs: arches, cave, chasm, overhangs, combined. Every scene is 256 m square.
    #[arg(long, value_name = "NAME")]
    pub scene: String,
    /// Cells per side, 1 to 65536 (the cell size is 256 m / N; not image pixels).
    #[arg(long, value_name = "N", value_parser = terrain_side, allow_hyphen_values = true)]
    pub size: usize,
    /// Seed of rivers-rain's noise (the carved scenes are fixed shapes and take none)
    /// [default: the reference simulator's].
    #[arg(long, value_parser = seed, allow_hyphen_values = true)]
    pub seed: Option<u64>,
    /// Column slots per cell, 1 to 127 (carved scenes need up to 4; fewer fills their
    /// thinnest air gaps).
    #[arg(long, default_value = "4", value_name = "L", value_parser = max_layers, allow_hyphen_values = true)]
    pub max_layers: usize,
    /// Store the values as f16 (rounded conservatively) instead of f32.
    #[arg(long)]
    pub half: bool,
    /// Memory generation may take, e.g. 512M, 8G (default: half the machine's or cgroup's memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// Output: scene.mlhm (relief's own file, an NPZ archive) or scene.json (the reference
    /// simulator's scene, its .dat written beside it with the same name).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `relief generate fbm`.
#[derive(Debug, Args)]
pub struct FbmArgs {
    /// Terrain samples per side, width and height (1 to 65536; not image pixels).
    #[arg(long, value_name = "N", default_value = "1024", value_parser = terrain_side, allow_hyphen_values = true)]
    pub size: usize,
    /// Random seed.
    #[arg(long, default_value = "1", value_parser = seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Output height file, in the format its extension names: .npy (float32), .tif/.tiff
    /// (float32 GeoTIFF), .asc, .png (16-bit grey: heights rounded to whole units 0..65535)
    /// or .hgt (1201 or 3601 samples only).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `relief shade`.
#[derive(Debug, Args)]
pub struct ShadeArgs {
    /// The DEM: .tif/.tiff (GeoTIFF), .hgt, .asc, .png, .npy or .npz.
    pub input: PathBuf,
    /// How to read it (voids are filled for tracing, and are nodata in every layer).
    #[command(flatten)]
    pub read: ReadArgs,
    /// The file to write: .tif (a float32 GeoTIFF, one band per layer, each described by its
    /// layer's name) or .png (one layer, 16-bit grey, with a .pgw world file).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The layers, comma-separated, in the order of the bands: shadow, sky, hillshade,
    /// combined. Each is 0 (dark, or closed to the sky) to 1 (lit, or open).
    #[arg(long, value_delimiter = ',', default_values = ["combined"])]
    pub layers: Vec<ShadeLayer>,
    /// A sun, AZIMUTH,ELEVATION in degrees (azimuth clockwise from north, elevation above the
    /// horizon, above 0); give it again for more suns (`--sun 315,45 --sun 45,30`), which are
    /// averaged [default: 315,45].
    #[arg(long, value_parser = parse::sun, allow_hyphen_values = true,
          action = clap::ArgAction::Append, value_name = "AZ,EL")]
    pub sun: Vec<(f64, f64)>,
    /// Angular radius of each sun's disc in degrees, for soft shadows (the real sun's is 0.27)
    /// [default: 0, a point].
    #[arg(long, value_name = "DEG", value_parser = sun_radius, allow_hyphen_values = true)]
    pub sun_radius: Option<f64>,
    /// Rays over each sun's disc, with --sun-radius (1 to 4096) [default: 16].
    #[arg(long, value_name = "N", value_parser = shade_rays, allow_hyphen_values = true)]
    pub sun_rays: Option<u32>,
    /// Directions over the sky for the sky-view factor, for the sky and combined layers (1 to
    /// 4096) [default: 64].
    #[arg(long, value_name = "N", value_parser = shade_rays, allow_hyphen_values = true)]
    pub sky_rays: Option<u32>,
    /// The surface the rays meet: triangles (through the samples) or boxes (a flat-topped
    /// column per sample).
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

/// A sun's angular radius: 0 to 45 degrees.
fn sun_radius(s: &str) -> Result<f64, String> {
    parse::number_in(s, "sun radius", &(0.0..=relief_shade::shade_map::MAX_SUN_RADIUS_DEG))
        .map_err(|e| format!("{e} degrees"))
}

/// Rays per sample of a shade map: 1 to 4096.
fn shade_rays(s: &str) -> Result<u32, String> {
    let max = u64::from(relief_shade::shade_map::MAX_RAYS_PER_SAMPLE);
    parse::whole_in(s, 1..=max, "ray count").map(|n| n as u32)
}

/// `relief info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Height file, or an MLHM scene (.json or .mlhm).
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
    /// Terrain samples per side of the fBm terrain (1 to 65536; not image pixels: see
    /// --res) [default: 4096].
    #[arg(long, value_name = "N", value_parser = terrain_side, allow_hyphen_values = true)]
    pub size: Option<usize>,
    /// Image size WxH in pixels.
    #[arg(long, value_parser = parse::image_size, default_value = "1920x1080")]
    pub res: (u32, u32),
    /// Seed of the fBm terrain [default: 1].
    #[arg(long, value_parser = seed, allow_hyphen_values = true)]
    pub seed: Option<u64>,
    /// Tracers to measure (comma-separated): naive, mipmap, safety, safety variants by name
    /// (cyl_all, cyl_all+cone_all, cyl_ext, ...), or hybrid (the hybrid renderer, with the
    /// options below; its shadow rays are the mipmap tracer's). Safety shapes are always
    /// precomputed afresh here, and their build time reported.
    #[arg(long, value_delimiter = ',', default_values = ["naive", "mipmap"])]
    pub tracers: Vec<TracerChoice>,
    /// Safety-shape options (for every safety tracer measured).
    #[command(flatten)]
    pub safety: SafetyArgs,
    /// Surfaces to measure (comma-separated) [default: boxes,triangles; with --dynamic:
    /// triangles].
    #[arg(long, value_delimiter = ',')]
    pub surfaces: Vec<Surface>,
    /// Views to measure (comma-separated): three-quarter, flight, top-down, cover (the terrain
    /// fills the image, seen from 60 degrees up: every ray looks down at least 45 degrees)
    /// [default: three-quarter,flight,top-down; with --dynamic: flight].
    #[arg(long, value_delimiter = ',')]
    pub views: Vec<String>,
    /// Measure this height file (spacing 1, z scale 1) instead of generating the fBm terrain
    /// (then --size and --seed do not apply).
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
    #[arg(long, default_value = "3", value_parser = repeat, allow_hyphen_values = true)]
    pub repeat: u32,
    /// Instructions of the mipmap tracer's packet tests: auto (the fastest this processor
    /// has, the default), avx2 or portable.
    #[arg(long)]
    pub simd: Option<Simd>,
    /// Trace one ray at a time instead of in batches (the mipmap tracer's single-ray
    /// traversal instead of its packets), for comparison.
    #[arg(long)]
    pub single_rays: bool,
    /// Decide the shadow rays the sun's shadow sweep proves lit or occluded without tracing
    /// them (relief_trace::SunShadows; exact) and trace the others, and report the sweep's
    /// build time and the share of rays it decided: the default, for the triangles surface of
    /// a field without holes (on the 4096^2 fBm views, 1.3-1.5x as fast in the three-quarter
    /// and top-down views, as fast in the flight view; elsewhere the sweep does not pay and is
    /// not built).
    #[arg(long, overrides_with = "no_shadow_sweep")]
    pub shadow_sweep: bool,
    /// Trace every shadow ray, without the sun's shadow sweep.
    #[arg(long, overrides_with = "shadow_sweep")]
    pub no_shadow_sweep: bool,
    /// Options of the hybrid renderer (with `--tracers hybrid`, or `--dynamic`).
    #[command(flatten)]
    pub hybrid: HybridArgs,
    /// Instead of the tracers: the hybrid renderer drawing a terrain that changes every
    /// frame, on the flight view (or the first of --views) and the triangles surface (or the
    /// first of --surfaces): stamp (a brush raising and lowering the ground along a circle),
    /// waves (the ocean wave simulation rewriting the whole field) or erosion (the
    /// height-field erosion rewriting it). Prints, per frame, the update's and the render's
    /// milliseconds (the render shaded with shadows, as shown).
    #[arg(long, value_name = "stamp|waves|erosion")]
    pub dynamic: Option<DynamicKind>,
    /// With --dynamic: shade without shadow rays.
    #[arg(long, requires = "dynamic")]
    pub no_shadows: bool,
    /// With --dynamic: frames to draw (1 to 100000).
    #[arg(long, default_value = "20", value_parser = frames, allow_hyphen_values = true)]
    pub frames: u32,
}

impl BenchArgs {
    /// The views to measure: those given, or the default ones.
    pub fn views(&self) -> Vec<String> {
        match (self.views.is_empty(), self.dynamic.is_some()) {
            (false, _) => self.views.clone(),
            (true, true) => vec!["flight".into()],
            (true, false) => ["three-quarter", "flight", "top-down"].map(String::from).to_vec(),
        }
    }

    /// The surfaces to measure: those given, or the default ones.
    pub fn surfaces(&self) -> Vec<Surface> {
        match (self.surfaces.is_empty(), self.dynamic.is_some()) {
            (false, _) => self.surfaces.clone(),
            (true, true) => vec![Surface::Triangles],
            (true, false) => Surface::ALL.to_vec(),
        }
    }
}

/// What changes the terrain in `relief bench --dynamic`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum DynamicKind {
    /// A brush raising and lowering the ground.
    Stamp,
    /// The ocean wave simulation.
    Waves,
    /// The height-field erosion.
    Erosion,
}

/// A terrain's samples (or an MLHM's cells) per side: 1 to 65536.
fn terrain_side(s: &str) -> Result<usize, String> {
    parse::whole_in(s, 1..=65536, "size").map(|v| v as usize)
}

/// A seed: any whole number from 0 to 2^64 - 1.
fn seed(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 0..=u64::MAX, "seed")
}

/// `--safety-reach`: 1 to 1024 texels (the precomputation's time grows with it).
fn safety_reach(s: &str) -> Result<u16, String> {
    parse::whole_in(s, 1..=1024, "--safety-reach").map(|v| v as u16)
}

/// `--max-layers`: 1 to 127, what the scene format's int8 layer counts hold.
fn max_layers(s: &str) -> Result<usize, String> {
    parse::whole_in(s, 1..=127, "--max-layers").map(|v| v as usize)
}

/// `--frames`: 1 to 100000 frames.
fn frames(s: &str) -> Result<u32, String> {
    parse::whole_in(s, 1..=100_000, "--frames").map(|v| v as u32)
}

/// `--frame-budget`: 5 to 1000 milliseconds.
fn frame_budget(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 5..=1000, "--frame-budget")
}

/// `--repeat`: 1 to 1000 runs of every view.
fn repeat(s: &str) -> Result<u32, String> {
    parse::whole_in(s, 1..=1000, "--repeat").map(|v| v as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn render_modes_parse() {
        assert_eq!(parse_mlhm_render_mode("boxes"), Ok(MlhmRenderMode::Boxes));
        assert_eq!(parse_mlhm_render_mode("smooth"), Ok(MlhmRenderMode::Smooth));
        assert!(parse_mlhm_render_mode("spheres").is_err());
    }

    #[test]
    fn whole_numbers_are_held_to_their_ranges() {
        assert_eq!(terrain_side("65536"), Ok(65536));
        assert!(terrain_side("0").is_err() && terrain_side("-4").is_err());
        assert_eq!(seed("18446744073709551615"), Ok(u64::MAX));
        assert!(safety_reach("1025").is_err() && max_layers("128").is_err());
    }
}

/// `relief simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// MLHM scene to simulate: the reference simulator's .json (with its .dat) or a .mlhm.
    pub input: PathBuf,
    /// Steps to simulate (1 to 10000000).
    #[arg(long, value_parser = simulation_steps, allow_hyphen_values = true)]
    pub steps: u64,
    /// Scene to write: .json (with a .dat beside it, simulation state included) or .mlhm (the
    /// terrain only).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Seed of the rain's random numbers.
    #[arg(long, default_value = "1")]
    pub seed: u64,
    /// Rain in metres of water per second (0 to 100) [default: the scene's, else 0.07].
    #[arg(long, value_name = "M_PER_S", value_parser = water_rate, allow_hyphen_values = true)]
    pub rain: Option<f32>,
    /// Evaporation in metres of water per second (0 to 100) [default: the scene's, else 0.09].
    #[arg(long, value_name = "M_PER_S", value_parser = water_rate, allow_hyphen_values = true)]
    pub evaporation: Option<f32>,
    /// Time step in seconds (0.001 to 10) [default: the scene's, else 0.15].
    #[arg(long, value_name = "S", value_parser = time_step, allow_hyphen_values = true)]
    pub dt: Option<f32>,
    /// Write the step count, the median step time and the volumes added and removed by
    /// design to this .json file (with --frames, also the median and per-frame rebuild and
    /// render times).
    #[arg(long, value_name = "F.json")]
    pub stats: Option<PathBuf>,
    /// Memory the scene may take, e.g. 512M, 8G (default: half the machine's or cgroup's
    /// memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// With --frames: every K steps, rebuild the MLHM hierarchy and render a frame (1 to
    /// 10000000).
    #[arg(long, value_name = "K", value_parser = render_every, allow_hyphen_values = true)]
    pub render_every: Option<u64>,
    /// With --render-every: the folder the frames are written to as frame-00000.png,
    /// frame-00001.png, ... as flythrough numbers them (created if missing), each stage's
    /// time printed per frame.
    #[arg(long, value_name = "DIR")]
    pub frames: Option<PathBuf>,
    /// With --frames: the frames' quality preset, as in render: low, mid, high or max
    /// [default: low].
    #[arg(long)]
    pub preset: Option<MlhmPreset>,
    /// With --frames: frame size WxH in pixels [default: 1280x720].
    #[arg(long, value_parser = parse::image_size)]
    pub size: Option<(u32, u32)>,
    /// With --frames: the camera looking towards compass AZ degrees from EL degrees above the
    /// horizon, at DISTANCE metres from the terrain's centre, as in render [default: render's
    /// framing, 45,30], fixed over the run.
    #[arg(long, value_name = "AZ,EL[,DISTANCE]", value_parser = parse::view, allow_hyphen_values = true)]
    pub view: Option<parse::ViewAngles>,
    /// Every K steps, write the state so far as OUTPUT.step-N.json (or .mlhm) beside the
    /// output, atomically, removing the previous one (1 to 10000000): a killed run keeps its
    /// work. The final output replaces the last.
    #[arg(long, value_name = "K", value_parser = checkpoint_every, allow_hyphen_values = true)]
    pub checkpoint: Option<u64>,
    /// Diagnostic: check the terrain's invariants after every stage of every step (not only
    /// after every step), so an error names the stage that broke them; a few times slower.
    #[arg(long)]
    pub check_stages: bool,
    /// For the tests of the error path: step N (counted as the scene counts its steps)
    /// reports a broken terrain.
    #[arg(long, value_name = "N", hide = true)]
    pub test_fail_at_step: Option<u64>,
}

/// `--checkpoint`: 1 to 10^7 steps.
fn checkpoint_every(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 1..=10_000_000, "--checkpoint")
}

/// `--render-every`: 1 to 10^7 steps.
fn render_every(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 1..=10_000_000, "--render-every")
}

/// Simulation steps: 1 to 10^7.
fn simulation_steps(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 1..=10_000_000, "step count")
}

/// A rate of rain or evaporation: 0 to 100 m/s.
fn water_rate(s: &str) -> Result<f32, String> {
    parse::number_in(s, "water rate", &(0.0..=100.0))
        .map(|v| v as f32)
        .map_err(|e| format!("{e} m/s"))
}

/// A time step: 0.001 to 10 s.
fn time_step(s: &str) -> Result<f32, String> {
    parse::number_in(s, "time step", &(0.001..=10.0))
        .map(|v| v as f32)
        .map_err(|e| format!("{e} s"))
}
