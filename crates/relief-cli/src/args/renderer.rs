//! The renderers' options that `relief render`, `view`, `flythrough` and `bench` share: the
//! hybrid renderer's and tile stores'.

use super::values::*;
use clap::{Args, ValueEnum};

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
