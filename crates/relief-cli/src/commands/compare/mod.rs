//! `relief compare REF.npy TEST.npy`: the hybrid-rendering paper's error metrics (Ammann et
//! al. 2010, section 4.1) of one depth image against a reference (relief_shade::depth_metrics).

pub mod args;

use crate::args::{ReadArgs, Voids};
use crate::parse::readable;
use crate::{applies, input};
use anyhow::{bail, Result};
use args::CompareArgs;
use relief_core::Surface;
use relief_io::ReadOptions;
use relief_shade::{depth_metrics, DepthImage, DepthMetrics, DepthScale};
use serde_json::{json, Value};
use std::path::Path;

/// A depth image read from a `.npy` file: rows, columns and values.
struct DepthFile {
    rows: usize,
    cols: usize,
    depth: Vec<f32>,
}

impl DepthFile {
    fn image(&self) -> DepthImage<'_> {
        DepthImage { width: self.cols, height: self.rows, depth: &self.depth }
    }
}

/// Where R and the cell size came from.
#[derive(Debug, Clone, Copy)]
enum ScaleSource {
    /// `--diagonal` / `--cell`.
    Given,
    /// The `--terrain`.
    Terrain,
    /// The defaults: the largest finite reference depth, a cell of 1.
    Default,
}

impl ScaleSource {
    fn name(self) -> &'static str {
        match self {
            ScaleSource::Given => "given",
            ScaleSource::Terrain => "terrain",
            ScaleSource::Default => "default",
        }
    }
}

/// Runs `relief compare`.
pub fn run(args: &CompareArgs) -> Result<()> {
    let options = read_options(args);
    let reference = read_depth(&args.reference, &options)?;
    let test = read_depth(&args.test, &options)?;
    if (reference.rows, reference.cols) != (test.rows, test.cols) {
        bail!(
            "{} is {} x {} pixels but {} is {} x {}: depth images of different shapes",
            args.reference.display(),
            reference.cols,
            reference.rows,
            args.test.display(),
            test.cols,
            test.rows
        );
    }
    let terrain = match &args.terrain {
        Some(path) => Some(terrain_scale(path, args)?),
        None => None,
    };
    let largest = reference.depth.iter().copied().filter(|d| d.is_finite()).fold(0.0, f32::max);
    let (diagonal, diagonal_from) = match (args.diagonal, terrain) {
        (Some(r), _) => (r, ScaleSource::Given),
        (None, Some((r, _))) => (r, ScaleSource::Terrain),
        (None, None) if largest > 0.0 => (f64::from(largest), ScaleSource::Default),
        (None, None) => (1.0, ScaleSource::Default),
    };
    let (cell, cell_from) = match (args.cell, terrain) {
        (Some(c), _) => (c, ScaleSource::Given),
        (None, Some((_, c))) => (c, ScaleSource::Terrain),
        (None, None) => (1.0, ScaleSource::Default),
    };
    let scale = DepthScale { diagonal, cell };
    let metrics = depth_metrics(&reference.image(), &test.image(), scale)?;
    if args.json {
        let mut value = metrics_json(&metrics, scale);
        if let Some(map) = value.as_object_mut() {
            map.insert("width".into(), json!(reference.cols));
            map.insert("height".into(), json!(reference.rows));
            map.insert("diagonal_from".into(), json!(diagonal_from.name()));
            map.insert("cell_from".into(), json!(cell_from.name()));
        }
        println!("{value}");
    } else {
        print!("{}", report(&metrics, scale, (diagonal_from, cell_from)));
    }
    Ok(())
}

/// The reader options: `--max-memory` where given.
fn read_options(args: &CompareArgs) -> ReadOptions {
    let defaults = ReadOptions::default();
    ReadOptions { max_memory: args.max_memory.unwrap_or(defaults.max_memory), ..defaults }
}

/// Reads the depth image at `path`.
fn read_depth(path: &Path, options: &ReadOptions) -> Result<DepthFile> {
    let (rows, cols, depth) = relief_io::read_npy_f32_array(path, options)?;
    Ok(DepthFile { rows, cols, depth })
}

/// The bounding-box diagonal of the solid of the terrain at `path` and its grid spacing.
fn terrain_scale(path: &Path, args: &CompareArgs) -> Result<(f64, f64)> {
    let read = ReadArgs { max_memory: args.max_memory, ..ReadArgs::default() };
    if input::is_mlhm_scene(path) {
        let here = applies::input_kind(Some(path));
        if args.spacing.is_some() {
            return Err(applies::refuse("--spacing", "height files", &here));
        }
        if args.z_scale.is_some() {
            return Err(applies::refuse("--z-scale", "height files", &here));
        }
        let map = input::load_mlhm(path, &read)?.mlhm;
        let s = map.cell_size();
        let heights = map.heights();
        // The solid is clipped at its lowest bedrock top; water is visible.
        let size = [map.width() as f64 * s, map.height() as f64 * s];
        let depth = heights.water_max.max(heights.solid_max) - heights.bedrock_min;
        let diagonal = (size[0].powi(2) + size[1].powi(2) + depth.powi(2)).sqrt();
        if !diagonal.is_finite() || diagonal <= 0.0 {
            bail!("{}: the scene has no finite bounding box", path.display());
        }
        return Ok((diagonal, s));
    }
    let (_, field, _) = input::read(path, &read, Voids::Fill)?;
    let field = input::place(field, args.spacing, args.z_scale.unwrap_or(1.0))?;
    let bounds = field.world_bounds(Surface::Boxes);
    let diagonal = (bounds.max - bounds.min).length();
    let g = field.geometry();
    // A flat terrain of one texel still has a box of one cell's width.
    Ok((diagonal.max(g.dx.max(g.dy)), g.dx.max(g.dy)))
}

/// A number for JSON: `null` for a value JSON cannot hold (the PSNR of identical images).
fn number(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

/// The metrics as the JSON object `--json` prints.
fn metrics_json(m: &DepthMetrics, scale: DepthScale) -> Value {
    json!({
        "psnr_db": number(m.psnr_db),
        "wrong_pixel_fraction": m.wrong_pixel_fraction,
        "max_rel_error": m.max_rel_error,
        "max_abs_error": m.max_abs_error,
        "rms_error": m.rms_error,
        "pixels": m.pixels,
        "rendered": m.rendered,
        "wrong": m.wrong,
        "reference_only": m.reference_only,
        "test_only": m.test_only,
        "off_by_more_than_a_cell": m.off_by_more_than_a_cell,
        "diagonal": scale.diagonal,
        "cell": scale.cell,
    })
}

/// The metrics in words.
fn report(m: &DepthMetrics, scale: DepthScale, from: (ScaleSource, ScaleSource)) -> String {
    let psnr = if m.psnr_db.is_finite() {
        format!("{:.2} dB", m.psnr_db)
    } else {
        "infinite (no error on any pixel both hit)".to_string()
    };
    let percent = |n: usize| 100.0 * n as f64 / m.pixels.max(1) as f64;
    format!(
        "PSNR {psnr} (R = {} from {}), over {} pixels both images hit ({:.2} %)\n\
         wrong pixels {} of {} ({:.4} %): {} terrain in the reference only, {} in the test \
         only, {} more than a cell ({} from {}) off\n\
         largest error {} (relative {:.3e}), RMS {}\n",
        readable(scale.diagonal),
        from.0.name(),
        m.rendered,
        percent(m.rendered),
        m.wrong,
        m.pixels,
        100.0 * m.wrong_pixel_fraction,
        m.reference_only,
        m.test_only,
        m.off_by_more_than_a_cell,
        readable(scale.cell),
        from.1.name(),
        readable(m.max_abs_error),
        m.max_rel_error,
        readable(m.rms_error)
    )
}
