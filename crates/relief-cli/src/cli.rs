//! The command line: the subcommands, each with its arguments (in the subcommand's folder).

use crate::commands::bench::args::BenchArgs;
use crate::commands::compare::args::CompareArgs;
use crate::commands::convert::args::ConvertArgs;
use crate::commands::flythrough::args::FlythroughArgs;
use crate::commands::generate::args::GenerateCommand;
use crate::commands::info::args::InfoArgs;
use crate::commands::mesh::args::MeshArgs;
use crate::commands::render::args::RenderArgs;
use crate::commands::shade::args::ShadeArgs;
use crate::commands::simulate::args::SimulateArgs;
use crate::commands::tile::args::TileArgs;
use crate::commands::view::args::ViewArgs;
use crate::commands::viewshed::args::ViewshedArgs;
use clap::{Parser, Subcommand};

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
    /// Which samples of a DEM an observer sees (1 or 0), or how many of several observers
    /// see each one, exact for the DEM's surface, written on its grid (its georeference, CRS
    /// and nodata).
    Viewshed(Box<ViewshedArgs>),
}
