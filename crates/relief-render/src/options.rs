//! What a scene is opened with: how its input is read and placed, the tracer and renderer,
//! the light, and the options of each kind of input. Plain values, as a front end (the
//! command line, the Python module) fills them in; `None` where the default applies.

use crate::colours::ColourSettings;
use crate::error::RenderError;
use crate::tracer_spec::{SafetySettings, TracerChoice};
use relief_core::{Precision, Surface};
use relief_io::{LengthUnit, PngEncoding, ReadOptions, VoidPolicy};
use relief_shade::hybrid::HybridParams;
use relief_shade::mlhm::MlhmPreset;
use relief_shade::{FarField, NormalStyle, TextureFilter};
use relief_trace::MlhmBacktrack;
use std::path::PathBuf;

/// How a height file is read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReadSettings {
    /// What becomes of voids (nodata) [default: filled].
    pub voids: Option<VoidPolicy>,
    /// Memory the input may take, bytes [default: half the machine's or cgroup's memory].
    pub max_memory: Option<u64>,
    /// How a PNG encodes heights.
    pub png_encoding: PngEncoding,
    /// The array to read from an .npz archive [default: the first].
    pub array: Option<String>,
    /// The unit of the file's heights [default: the file's, else metres].
    pub z_unit: Option<LengthUnit>,
}

impl ReadSettings {
    /// The reader options these settings ask for.
    pub fn read_options(&self) -> ReadOptions {
        let defaults = ReadOptions::default();
        ReadOptions {
            max_memory: self.max_memory.unwrap_or(defaults.max_memory),
            array: self.array.clone(),
            png_encoding: self.png_encoding,
            z_unit: self.z_unit,
        }
    }
}

/// How a height field is read (or generated) and placed in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainSettings {
    /// How the file is read.
    pub read: ReadSettings,
    /// Texel spacing (dx, dy) in world units [default: the file's georeference, else 1].
    pub spacing: Option<(f64, f64)>,
    /// The array's row 0 is its north edge: flip the rows.
    pub north_up: bool,
    /// Multiplies heights (after their unit is turned into metres).
    pub z_scale: f64,
    /// Samples a side of the default fBm terrain [default: 1024].
    pub fbm_size: Option<usize>,
    /// Seed of the default fBm terrain [default: 1].
    pub seed: Option<u64>,
}

impl Default for TerrainSettings {
    fn default() -> Self {
        TerrainSettings {
            read: ReadSettings::default(),
            spacing: None,
            north_up: false,
            z_scale: 1.0,
            fbm_size: None,
            seed: None,
        }
    }
}

/// How an MLHM scene's columns (or any input's material stacks) are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderMode {
    /// Every column as a box over its cell (Nilles & Müller 2025, 4.1).
    Boxes,
    /// The smooth implicit surface of the boxes (Nilles & Müller 2025, 3.3 and 4.3-4.6).
    Smooth,
    /// The terrain as material stacks meshed by dual contouring at the camera's levels of
    /// detail (Löffler et al. 2011) and rasterized; any input.
    Mesh,
}

/// The options of an MLHM scene.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MlhmSettings {
    /// The quality preset [default: mid].
    pub preset: Option<MlhmPreset>,
    /// Precision of the hierarchy tracer's bounds [default: f32].
    pub hierarchy_bounds: Option<Precision>,
    /// How the hierarchy tracer climbs back up [default: stack].
    pub backtrack: Option<MlhmBacktrack>,
    /// Leave the preset's ambient occlusion out.
    pub no_ao: bool,
}

/// The options of material-stack meshes (`RenderMode::Mesh`, `.stacks` files).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshSettings {
    /// The largest screen-space size of a mesh cell, pixels [default: 10].
    pub tau_px: Option<f64>,
    /// The height of a density voxel at the finest level, metres [default: the spacing].
    pub voxel_height: Option<f64>,
    /// Node meshes a frame makes at most beyond those nothing drawn before stands in for
    /// (see [`relief_mesh::StacksMesher::set_node_budget`]); `None`: every node a frame wants.
    /// A still picture is the same either way: nothing stands in for a first frame.
    pub node_budget: Option<usize>,
}

/// The largest screen-space size of a stacks mesh cell where none is given, pixels.
pub const DEFAULT_TAU_PX: f64 = 10.0;

/// The node meshes a frame of a stacks terrain makes at most where no budget is given (past
/// those nothing drawn before stands in for).
pub const DEFAULT_NODE_BUDGET: usize = 40;

/// The options of a tile store.
#[derive(Debug, Clone, PartialEq)]
pub struct StoreSettings {
    /// The largest screen-space error, pixels.
    pub max_error_px: f64,
    /// Bytes of tiles held in memory.
    pub cache_bytes: u64,
    /// How the store's photo is filtered.
    pub texture_filter: TextureFilter,
    /// Bytes of texture tiles held in memory.
    pub texture_cache_bytes: u64,
}

/// Tile stores: the screen-space error where none is given (Dick et al. 2009).
pub const DEFAULT_MAX_ERROR_PX: f64 = 2.0 / 3.0;
/// Tile stores: megabytes of tiles in memory where none are given.
pub const DEFAULT_CACHE_MB: u64 = 512;
/// Textured tile stores: megabytes of texture tiles in memory where none are given.
pub const DEFAULT_TEXTURE_CACHE_MB: u64 = 256;

impl Default for StoreSettings {
    fn default() -> Self {
        StoreSettings {
            max_error_px: DEFAULT_MAX_ERROR_PX,
            cache_bytes: DEFAULT_CACHE_MB << 20,
            texture_filter: TextureFilter::Anisotropic {
                max_anisotropy: relief_shade::DEFAULT_MAX_ANISOTROPY,
            },
            texture_cache_bytes: DEFAULT_TEXTURE_CACHE_MB << 20,
        }
    }
}

/// The options of the hybrid renderer (Ammann et al. 2010).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HybridSettings {
    /// The heuristic's parameters.
    pub params: HybridParams,
    /// How the cells it does not rasterize are ray cast [default: exact].
    pub far: Option<FarField>,
    /// Colour each pixel by what drew it (the paper's Figure 1).
    pub show_lop: bool,
}

/// The light and the colours.
#[derive(Debug, Clone, PartialEq)]
pub struct LightSettings {
    /// The sun's azimuth (clockwise from north) and elevation, degrees.
    pub sun: (f64, f64),
    /// Do not trace shadow rays.
    pub no_shadows: bool,
    /// Exposure applied before tone mapping.
    pub exposure: f64,
    /// A colour texture (PNG) draped over the terrain's footprint, top row north.
    pub texture: Option<PathBuf>,
    /// How heights are coloured where no texture is draped.
    pub colours: ColourSettings,
    /// The normals that light a height field's `triangles` surface [default: smooth for
    /// triangles; `boxes` are always faceted, and refuse smooth given explicitly].
    pub shading_normals: Option<NormalStyle>,
}

impl Default for LightSettings {
    fn default() -> Self {
        LightSettings {
            sun: (315.0, 35.0),
            no_shadows: false,
            exposure: 1.0,
            texture: None,
            colours: ColourSettings::default(),
            shading_normals: None,
        }
    }
}

/// Everything a scene is opened with.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneOptions {
    /// How the height field is read or generated, and placed.
    pub terrain: TerrainSettings,
    /// The surface drawn [default: triangles; an MLHM scene's is its mode].
    pub surface: Option<Surface>,
    /// The tracer or renderer [default: mipmap; hierarchy for an MLHM scene].
    pub tracer: Option<TracerChoice>,
    /// The safety tracer's options.
    pub safety: SafetySettings,
    /// How the terrain is drawn [default: boxes for an MLHM scene; mesh for a .stacks file].
    pub mode: Option<RenderMode>,
    /// MLHM smooth mode: the smoothing radius; mesh mode: the Gaussian's standard deviation;
    /// metres [default: one cell].
    pub sigma: Option<f64>,
    /// MLHM scenes' options.
    pub mlhm: MlhmSettings,
    /// Stacks meshes' options.
    pub mesh: MeshSettings,
    /// Tile stores' options.
    pub store: StoreSettings,
    /// The hybrid renderer's options.
    pub hybrid: HybridSettings,
    /// The light and colours.
    pub light: LightSettings,
}

/// Refuses shading normals asked for a scene that shades its own surface (`what`: "MLHM
/// scenes", ...): they apply to height fields and tile stores.
pub fn refuse_shading_normals(light: &LightSettings, what: &str) -> Result<(), RenderError> {
    match light.shading_normals {
        Some(style) => Err(RenderError::Unsupported(format!(
            "shading normals ({style}) apply to height fields and tile stores, not to {what}"
        ))),
        None => Ok(()),
    }
}
