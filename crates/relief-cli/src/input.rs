//! Loading the height field a command works on: a file, or the seeded fBm terrain.

use crate::args::{InputArgs, PngHeights, ReadArgs, Voids};
use crate::{applies, memory, warnings};
use anyhow::{Context, Result};
use relief_core::{GridGeometry, HeightField};
use relief_io::{PngEncoding, Raster, ReadOptions, VoidPolicy};
use relief_sim::{fbm_terrain, FbmParams};
use std::path::Path;
use std::sync::Arc;

/// Reads `args.input` (or generates the default terrain) and applies spacing and z scale.
/// Options that do nothing for that input are refused; a DEM read at the default spacing
/// whose heights dwarf its grid is warned of.
pub fn load(args: &InputArgs) -> Result<Arc<HeightField>> {
    check_input_args(args)?;
    let (field, defaulted_spacing) = match &args.input {
        Some(path) => {
            let (info, field, _) = read(path, &args.read, Voids::Fill)?;
            (field, args.spacing.is_none() && !info.georeferenced)
        }
        None => (
            fbm(
                args.fbm_size.unwrap_or(DEFAULT_FBM_SIZE),
                args.seed.unwrap_or(1),
                &memory::budget(args.read.max_memory),
            )?,
            false,
        ),
    };
    let field = if args.north_up { field.flip_rows() } else { field };
    let field = place(field, args.spacing, args.z_scale)?;
    if let Some(warning) = defaulted_spacing.then(|| warnings::defaulted_spacing(&field)).flatten()
    {
        eprintln!("{warning}");
    }
    Ok(Arc::new(field))
}

/// Applies `--spacing` (where given; else the file's) and `--z-scale` to `field`. The z scale
/// multiplies the field's own, which turns the file's height unit into metres (0.3048 for a
/// DEM in feet).
pub fn place(field: HeightField, spacing: Option<(f64, f64)>, z_scale: f64) -> Result<HeightField> {
    let (dx, dy) = spacing.unwrap_or((field.geometry().dx, field.geometry().dy));
    let z_scale = z_scale * field.geometry().z_scale;
    let geometry = GridGeometry { dx, dy, z_scale, ..*field.geometry() };
    field.with_geometry(geometry).context("invalid placement")
}

/// Samples per side of the default fBm terrain.
pub const DEFAULT_FBM_SIZE: usize = 1024;

/// Refuses the options of `args` that do nothing for its input.
pub fn check_input_args(args: &InputArgs) -> Result<()> {
    applies::check_read_args(&args.read, args.input.as_deref())?;
    if args.input.is_some() {
        let here = applies::input_kind(args.input.as_deref());
        if args.fbm_size.is_some() {
            return Err(applies::refuse("--fbm-size", "the default fBm terrain", &here));
        }
        if args.seed.is_some() {
            return Err(applies::refuse("--seed", "the default fBm terrain", &here));
        }
    }
    Ok(())
}

/// Reads the height file at `path` as a raster and as a height field with its voids resolved
/// as `--voids` says, or by `default_voids` where it says nothing. Also returns the void count.
pub fn read(
    path: &Path,
    args: &ReadArgs,
    default_voids: Voids,
) -> Result<(relief_io::RasterInfo, HeightField, usize)> {
    let raster: Raster = relief_io::read_raster(path, &read_options(args))?;
    let (info, voids) = (raster.info.clone(), raster.void_count());
    let policy = match args.voids.unwrap_or(default_voids) {
        Voids::Fill => VoidPolicy::Fill,
        Voids::Hole => VoidPolicy::Hole,
    };
    Ok((info, raster.into_height_field(path, policy)?, voids))
}

/// The reader options the command line asks for.
pub fn read_options(args: &ReadArgs) -> ReadOptions {
    let defaults = ReadOptions::default();
    ReadOptions {
        max_memory: args.max_memory.unwrap_or(defaults.max_memory),
        array: args.array.clone(),
        png_encoding: match args.png_encoding.unwrap_or(PngHeights::Grey) {
            PngHeights::Grey => PngEncoding::Grey,
            PngHeights::TerrainRgb => PngEncoding::TerrainRgb,
            PngHeights::Terrarium => PngEncoding::Terrarium,
        },
        z_unit: args.z_unit,
    }
}

/// The seeded fBm terrain of `size` x `size` samples, refused when it and the pyramid a
/// render builds over it would not fit `budget`.
pub fn fbm(size: usize, seed: u64, budget: &memory::Budget) -> Result<HeightField> {
    if size == 0 || size > 65536 {
        anyhow::bail!("terrain size {size} must be between 1 and 65536");
    }
    let needed = (size as u64).pow(2) * 16 / 3;
    if needed > budget.bytes {
        anyhow::bail!(
            "a {size}x{size} terrain needs {}, over the {} memory limit ({})",
            memory::format_bytes(needed),
            memory::format_bytes(budget.bytes),
            budget.origin
        );
    }
    fbm_terrain(size, size, seed, &FbmParams::for_size(size, size))
        .context("generating fBm terrain")
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

/// Reads the MLHM at `path` within `--max-memory`: a `.mlhm` file as a scene with no
/// simulation state or settings (in its map's precision), else a reference scene (its JSON
/// and the `.dat` it names).
pub fn load_mlhm(path: &Path, args: &ReadArgs) -> Result<relief_io::MlhmScene> {
    let options = read_options(args);
    if is_native_mlhm(path) {
        let map = relief_io::read_mlhm_native(path, &options)?;
        let precision = map.precision();
        return Ok(relief_io::MlhmScene { precision, ..relief_io::MlhmScene::new(map) });
    }
    Ok(relief_io::read_mlhm_scene(path, &options)?)
}
