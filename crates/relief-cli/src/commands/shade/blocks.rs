//! `relief shade` block by block: a tile store, or a raster larger than the memory budget
//! (tiled into a store beside the output first), shaded one block at a time within
//! `--max-memory` and written as a cloud-optimised GeoTIFF as the blocks come. A killed run
//! leaves no file under the output's name; the same command resumes it.

use super::args::ShadeArgs;
use super::when::{self, SunTimes};
use crate::{outputs, progress};
use anyhow::{bail, Context, Result};
use relief_io::geotiff::CogWriter;
use relief_render::block_shade::{shade_blocks, BlockPlan, ShadeSource};
use relief_render::Budget;
use relief_shade::ShadeMapParams;
use relief_tiles::{build_store, BuildOptions};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Side of the output's internal tiles, and the blocks' alignment.
const OUTPUT_TILE: usize = 512;

/// Side of the tiles of the store a raster is tiled into.
const STORE_TILE: u32 = 512;

/// Bytes of decoded store tiles kept for the windows and the far field: a tenth of the budget,
/// between 16 and 512 MiB.
fn tile_cache_bytes(budget: &Budget) -> u64 {
    (budget.bytes / 10).clamp(16 << 20, 512 << 20)
}

/// Where a raster too large for memory is tiled: a hidden store beside the output, kept until
/// the output is complete (so that an interrupted run resumes the tiling too).
pub fn temporary_store(output: &Path) -> PathBuf {
    let name =
        output.file_name().map_or_else(Default::default, |n| n.to_string_lossy().into_owned());
    output.with_file_name(format!(".{name}.store"))
}

/// Runs `relief shade` block by block on `args.input` (a store, or a raster tiled into
/// `tiled` first), with `params` (suns from `--date` still to place).
pub fn run(
    args: &ShadeArgs,
    format: super::ShadeOutput,
    params: ShadeMapParams,
    budget: &Budget,
    tiled: Option<&Path>,
) -> Result<()> {
    if format != super::ShadeOutput::GeoTiff {
        bail!(
            "-o {}: {} is shaded block by block, and a PNG is written whole: write a .tif",
            args.output.display(),
            args.input.display()
        );
    }
    let start = Instant::now();
    let cache = tile_cache_bytes(budget);
    let store = match tiled {
        Some(store) => {
            tile_raster(args, store, budget)?;
            store
        }
        None => args.input.as_path(),
    };
    let source = ShadeSource::open_store(store, cache)?.placed(args.spacing, args.z_scale)?;
    let (width, height) = (source.width(), source.height());
    let mut params = params;
    match when::sun_samples(&args.when, source.georeference(), width, height)? {
        SunTimes::NotAsked => {}
        SunTimes::Instant(sun) => params.suns = vec![sun],
        SunTimes::Period(suns) => params.insolation = suns,
    }
    params.validate()?;
    let names: Vec<String> = params.band_names().into_iter().map(|(_, name)| name).collect();
    // The source's bounds, the tile cache, the writer, and a direction's steps over the whole
    // raster while its far walks run (about 300 bytes a step).
    let stencil = 300 * width.max(height) as u64;
    let fixed = source.bytes()
        + cache
        + CogWriter::memory_bytes(width, height, names.len(), OUTPUT_TILE)
        + stencil;
    let plan = BlockPlan::new(
        width,
        height,
        source.span(),
        &source.geometry(),
        &params,
        OUTPUT_TILE,
        budget,
        fixed,
    )?;
    let read_ms = elapsed_ms(start);

    let fingerprint = fingerprint(args, &source, &params)?;
    let existed = CogWriter::interrupted_at(&args.output);
    let mut writer = CogWriter::create(
        &args.output,
        width,
        height,
        &names,
        source.georeference(),
        source.nodata(),
        OUTPUT_TILE,
        &fingerprint,
    )?;
    let done: Vec<_> = writer.done_blocks().to_vec();
    if writer.resumed() {
        eprintln!(
            "resuming {}: {} of {} blocks were written by an interrupted run",
            args.output.display(),
            plan.blocks.iter().filter(|b| done.contains(b)).count(),
            plan.blocks.len()
        );
    } else if existed {
        eprintln!(
            "starting {} over: an interrupted run of other options or input left its blocks",
            args.output.display()
        );
    }
    let start = Instant::now();
    let bar = progress::bar((width * height) as u64, "shading");
    let report = shade_blocks(
        &source,
        &params,
        args.surface,
        &plan,
        &|block| done.contains(block),
        &mut |block, map| {
            let bands: Vec<&[f32]> = map.bands.iter().map(|b| b.values.as_slice()).collect();
            writer.write_block(block.0.clone(), block.1.clone(), &bands)?;
            Ok(())
        },
        &|samples| bar.set_position(samples),
    )?;
    bar.finish_and_clear();
    let trace_ms = elapsed_ms(start);
    let start = Instant::now();
    writer.finish()?;
    if tiled.is_some() {
        std::fs::remove_dir_all(store)
            .with_context(|| format!("removing the temporary store {}", store.display()))?;
    }
    let write_ms = elapsed_ms(start);
    let window = plan.window_samples(width, height);
    eprintln!(
        "wrote {} ({width} x {height} samples, {}; {} blocks of {} with a halo of {}, {} from an \
         earlier run; {:.1} s)",
        args.output.display(),
        names.join(", "),
        plan.blocks.len(),
        plan.block,
        plan.halo,
        report.skipped,
        (read_ms + trace_ms + write_ms) / 1e3
    );
    if let Some(path) = &args.stats {
        let stats = serde_json::json!({
            "samples": (width * height) as u64,
            "layers": names,
            "rays": report.rays,
            "blocks": plan.blocks.len(),
            "blocks_resumed": report.skipped,
            "block": plan.block,
            "halo": plan.halo,
            "window_samples": window,
            "memory_estimate": fixed + plan.window_bytes,
            "read_ms": read_ms,
            "trace_ms": trace_ms,
            "write_ms": write_ms,
        });
        outputs::write_stats(path, &stats)?;
    }
    Ok(())
}

/// Tiles the raster `args.input` into `store` (or resumes that), with a progress bar.
fn tile_raster(args: &ShadeArgs, store: &Path, budget: &Budget) -> Result<()> {
    let read = crate::input::read_options(&args.read);
    let mut rows = relief_io::open_rows(&args.input, &read)?;
    let sources = vec![crate::commands::tile::source_file(&args.input)?];
    let options =
        BuildOptions { tile: STORE_TILE, max_memory: budget.bytes, ..BuildOptions::default() };
    let bar = progress::bar(0, "tiling");
    build_store(rows.as_mut(), sources, store, &options, &|done, total| {
        bar.set_length(total);
        bar.set_position(done);
    })
    .with_context(|| format!("tiling {} into {}", args.input.display(), store.display()))?;
    bar.finish_and_clear();
    Ok(())
}

/// What identifies a job for resuming: the input, its size and time, and every option.
fn fingerprint(args: &ShadeArgs, source: &ShadeSource, params: &ShadeMapParams) -> Result<String> {
    // A store's index changes with every build; a raster's size and time with the file.
    let file = if args.input.is_dir() { args.input.join("index.json") } else { args.input.clone() };
    let meta = std::fs::metadata(&file).with_context(|| format!("{}", file.display()))?;
    let modified = meta
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_nanos());
    // The input however it is named (relative or absolute, through links).
    let input = std::fs::canonicalize(&args.input).unwrap_or_else(|_| args.input.clone());
    Ok(format!(
        "{} {} {modified} {:?} {:?} {:?} {}x{}",
        input.display(),
        meta.len(),
        params,
        args.surface,
        source.geometry(),
        source.width(),
        source.height()
    ))
}

/// Milliseconds since `start`.
fn elapsed_ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}
