//! `relief bench`.

use crate::args::values::*;
use crate::args::*;
use crate::parse;
use clap::Args;
use relief_core::Surface;
use relief_render::TracerChoice;
use relief_trace::Simd;
use std::path::PathBuf;

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
