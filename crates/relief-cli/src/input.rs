//! The command line's reading options turned into the scene layer's, and the readers the
//! commands share (relief_render::input, with the options as the command line gives them).

use crate::applies;
use crate::args::{InputArgs, PngHeights, ReadArgs, Voids};
use anyhow::Result;
use relief_core::HeightField;
use relief_io::{PngEncoding, ReadOptions, VoidPolicy};
use relief_render::{ReadSettings, TerrainSettings};
use std::path::Path;

pub use relief_render::input::{
    fbm, is_mlhm_scene, is_native_mlhm, is_reference_scene, is_stacks_file, is_tile_store, place,
};

/// A height file read to be mapped sample for sample: the field placed, which samples were
/// voids before they were filled (or kept as holes), how many, and the raster's georeference,
/// CRS and nodata for the output.
pub struct MappedField {
    /// The height field, placed by the file's georeference or `--spacing` and `--z-scale`.
    pub field: HeightField,
    /// Per sample, whether it was a void.
    pub void: Vec<bool>,
    /// How many samples were voids.
    pub voids: usize,
    /// What the file said of its grid.
    pub info: relief_io::RasterInfo,
}

/// `raster`, read from `path` with `read`, as a [`MappedField`] placed by `spacing` and
/// `z_scale`.
pub fn mapped_field(
    raster: relief_io::Raster,
    path: &Path,
    read: &ReadArgs,
    spacing: Option<(f64, f64)>,
    z_scale: f64,
) -> Result<MappedField> {
    let void: Vec<bool> = raster.samples.iter().map(|v| v.is_nan()).collect();
    let voids = void.iter().filter(|&&v| v).count();
    let info = raster.info.clone();
    let policy = void_policy(read.voids.unwrap_or(Voids::Fill));
    let field = place(raster.into_height_field(path, policy)?, spacing, z_scale)?;
    Ok(MappedField { field, void, voids, info })
}

/// The reading settings `args` give.
pub fn read_settings(args: &ReadArgs) -> ReadSettings {
    ReadSettings {
        voids: args.voids.map(void_policy),
        max_memory: args.max_memory,
        png_encoding: match args.png_encoding.unwrap_or(PngHeights::Grey) {
            PngHeights::Grey => PngEncoding::Grey,
            PngHeights::TerrainRgb => PngEncoding::TerrainRgb,
            PngHeights::Terrarium => PngEncoding::Terrarium,
        },
        array: args.array.clone(),
        z_unit: args.z_unit,
    }
}

/// The terrain settings `args` give: how the file is read and placed, or the fBm terrain's.
pub fn terrain_settings(args: &InputArgs) -> TerrainSettings {
    TerrainSettings {
        read: read_settings(&args.read),
        spacing: args.spacing,
        north_up: args.north_up,
        z_scale: args.z_scale,
        fbm_size: args.fbm_size,
        seed: args.seed,
    }
}

/// What `--voids` names.
pub fn void_policy(voids: Voids) -> VoidPolicy {
    match voids {
        Voids::Fill => VoidPolicy::Fill,
        Voids::Hole => VoidPolicy::Hole,
    }
}

/// The reader options the command line asks for.
pub fn read_options(args: &ReadArgs) -> ReadOptions {
    read_settings(args).read_options()
}

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
    let settings = read_settings(args);
    Ok(relief_render::input::read(path, &settings, void_policy(default_voids))?)
}

/// Reads the MLHM at `path` within `--max-memory`: a `.mlhm` file as a scene with no
/// simulation state or settings, else a reference scene (its JSON and the `.dat` it names).
pub fn load_mlhm(path: &Path, args: &ReadArgs) -> Result<relief_io::MlhmScene> {
    Ok(relief_render::input::load_mlhm(path, &read_settings(args))?)
}
