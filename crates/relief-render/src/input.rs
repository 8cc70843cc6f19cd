//! Reading the terrain a scene draws: a height file placed in the world, the seeded fBm
//! terrain, or an MLHM scene; and what kind of input a path names.

use crate::error::RenderError;
use crate::memory::{self, Budget};
use crate::options::{ReadSettings, TerrainSettings};
use crate::warnings;
use relief_core::{GridGeometry, HeightField};
use relief_io::{Raster, RasterInfo, VoidPolicy};
use relief_sim::{fbm_terrain, FbmParams};
use std::path::Path;

/// Samples per side of the default fBm terrain.
pub const DEFAULT_FBM_SIZE: usize = 1024;

/// The kinds of input a scene opens.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputKind {
    /// A height file (.tif, .tiff, .hgt, .asc, .png, .npy, .npz), or the default fBm terrain.
    HeightFile,
    /// A multi-layered height map: a reference scene (.json with its .dat) or a .mlhm file.
    Mlhm,
    /// relief's material-stacks file (.stacks).
    Stacks,
    /// A tile store made by `relief tile`: a folder with an index.json.
    TileStore,
}

impl InputKind {
    /// The kind of input at `path` (`None`: the default fBm terrain), by its extension or,
    /// for a folder, its index.
    pub fn of(path: Option<&Path>) -> InputKind {
        match path {
            None => InputKind::HeightFile,
            Some(p) if is_tile_store(p) => InputKind::TileStore,
            Some(p) if is_mlhm_scene(p) => InputKind::Mlhm,
            Some(p) if is_stacks_file(p) => InputKind::Stacks,
            Some(_) => InputKind::HeightFile,
        }
    }
}

/// A height field read from a file or generated, placed in the world, with what reading it
/// found.
pub struct LoadedField {
    /// The terrain.
    pub field: HeightField,
    /// The warning of a DEM read at the default spacing whose heights dwarf its grid, if any.
    pub warning: Option<String>,
}

/// Reads the height file at `path` (or generates the default terrain) and places it as
/// `settings` say: rows flipped for north-up, spacing and z scale applied. A DEM read at the
/// default spacing whose heights dwarf its grid is warned of.
pub fn load(path: Option<&Path>, settings: &TerrainSettings) -> Result<LoadedField, RenderError> {
    let (field, defaulted_spacing) = match path {
        Some(path) => {
            let (info, field, _) = read(path, &settings.read, VoidPolicy::Fill)?;
            (field, settings.spacing.is_none() && !info.georeferenced)
        }
        None => (
            fbm(
                settings.fbm_size.unwrap_or(DEFAULT_FBM_SIZE),
                settings.seed.unwrap_or(1),
                &memory::budget(settings.read.max_memory),
            )?,
            false,
        ),
    };
    let field = if settings.north_up { field.flip_rows() } else { field };
    let field = place(field, settings.spacing, settings.z_scale)?;
    let warning = defaulted_spacing.then(|| warnings::defaulted_spacing(&field)).flatten();
    Ok(LoadedField { field, warning })
}

/// Applies `spacing` (where given; else the file's) and `z_scale` to `field`. The z scale
/// multiplies the field's own, which turns the file's height unit into metres (0.3048 for a
/// DEM in feet).
pub fn place(
    field: HeightField,
    spacing: Option<(f64, f64)>,
    z_scale: f64,
) -> Result<HeightField, RenderError> {
    let (dx, dy) = spacing.unwrap_or((field.geometry().dx, field.geometry().dy));
    let z_scale = z_scale * field.geometry().z_scale;
    let geometry = GridGeometry { dx, dy, z_scale, ..*field.geometry() };
    field.with_geometry(geometry).map_err(RenderError::Placement)
}

/// Reads the height file at `path` as a raster and as a height field with its voids resolved
/// as `settings` say, or by `default_voids` where they say nothing. Also returns the void
/// count.
pub fn read(
    path: &Path,
    settings: &ReadSettings,
    default_voids: VoidPolicy,
) -> Result<(RasterInfo, HeightField, usize), RenderError> {
    let raster: Raster = relief_io::read_raster(path, &settings.read_options())?;
    let (info, voids) = (raster.info.clone(), raster.void_count());
    let policy = settings.voids.unwrap_or(default_voids);
    Ok((info, raster.into_height_field(path, policy)?, voids))
}

/// The seeded fBm terrain of `size` x `size` samples, refused when it and the pyramid a
/// render builds over it would not fit `budget`.
pub fn fbm(size: usize, seed: u64, budget: &Budget) -> Result<HeightField, RenderError> {
    if size == 0 || size > 65536 {
        return Err(RenderError::TerrainSize(size));
    }
    let needed = (size as u64).pow(2) * 16 / 3;
    if needed > budget.bytes {
        return Err(RenderError::TerrainOverBudget { size, needed, budget: budget.clone() });
    }
    fbm_terrain(size, size, seed, &FbmParams::for_size(size, size)).map_err(RenderError::Fbm)
}

/// Whether `path` names a multi-layered height map: a reference scene (`.json`) or relief's
/// own `.mlhm` file, by its extension.
pub fn is_mlhm_scene(path: &Path) -> bool {
    is_reference_scene(path) || is_native_mlhm(path)
}

/// Whether `path` is a tile store made by `relief tile`: a folder with an `index.json`.
pub fn is_tile_store(path: &Path) -> bool {
    path.is_dir() && path.join("index.json").is_file()
}

/// Whether `path` names a reference simulator scene (its JSON), by the extension `.json`.
pub fn is_reference_scene(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Whether `path` names relief's own MLHM file, by the extension `.mlhm`.
pub fn is_native_mlhm(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("mlhm"))
}

/// Whether `path` names relief's stacks file, by the extension `.stacks`.
pub fn is_stacks_file(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("stacks"))
}

/// Reads the MLHM at `path` as `settings` say: a `.mlhm` file as a scene with no simulation
/// state or settings (in its map's precision), else a reference scene (its JSON and the
/// `.dat` it names).
pub fn load_mlhm(
    path: &Path,
    settings: &ReadSettings,
) -> Result<relief_io::MlhmScene, RenderError> {
    let options = settings.read_options();
    if is_native_mlhm(path) {
        let map = relief_io::read_mlhm_native(path, &options)?;
        let precision = map.precision();
        return Ok(relief_io::MlhmScene { precision, ..relief_io::MlhmScene::new(map) });
    }
    Ok(relief_io::read_mlhm_scene(path, &options)?)
}
