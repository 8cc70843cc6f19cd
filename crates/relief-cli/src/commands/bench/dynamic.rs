//! `relief bench --dynamic`: the hybrid renderer drawing a height field that changes every
//! frame, measured by relief-bench's [`DynamicBench`]; here the table or the JSON lines it
//! prints.

use super::args::{BenchArgs, DynamicKind};
use anyhow::{Context, Result};
use relief_bench::{benchmark_views, ChangeKind, DynamicBench, FrameTimes};
use relief_core::{HeightField, Surface};
use std::io::Write;
use std::sync::Arc;

/// Runs `relief bench --dynamic KIND` on `field` (described by `source`).
pub fn run(
    args: &BenchArgs,
    kind: DynamicKind,
    field: Arc<HeightField>,
    source: &str,
    views: &[String],
    surfaces: &[Surface],
) -> Result<()> {
    let (w, h) = args.res;
    let (view, camera) = benchmark_views(&field, w, h)?
        .into_iter()
        .find(|(name, _)| views.first().is_some_and(|v| v == name))
        .context("the view to draw")?;
    let surface = surfaces[0];
    let change = match kind {
        DynamicKind::Stamp => ChangeKind::Stamp,
        DynamicKind::Waves => ChangeKind::Waves,
        DynamicKind::Erosion => ChangeKind::Erosion,
    };
    let far = args.hybrid.far.unwrap_or_default();
    let hybrid = (args.hybrid.params(), far);
    let mut bench = DynamicBench::new(change, field, surface, camera, hybrid, !args.no_shadows)?;
    let mut out = std::io::stdout().lock();
    let kind_name = format!("{kind:?}").to_lowercase();
    if !args.json {
        writeln!(
            out,
            "relief bench --dynamic {kind_name}: {source}, {view} view, {surface}, {w}x{h}, \
             hybrid renderer (far field {far}), shadows {}, {} threads",
            if bench.shadows() { "on" } else { "off" },
            rayon::current_num_threads()
        )?;
        writeln!(
            out,
            "{:>5} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
            "frame", "samples", "change ms", "update ms", "render ms", "shade ms", "frame ms"
        )?;
    }
    let mut frames = Vec::new();
    for frame in 0..args.frames {
        let times = bench.frame(frame)?;
        let FrameTimes { samples, change_ms, update_ms, render_ms, shade_ms, frame_ms } = times;
        if args.json {
            writeln!(
                out,
                "{{\"dynamic\": \"{kind_name}\", \"frame\": {frame}, \"samples\": {samples}, \"change_ms\": {change_ms}, \"update_ms\": {update_ms}, \"render_ms\": {render_ms}, \"shade_ms\": {shade_ms}, \"frame_ms\": {frame_ms}}}"
            )?;
        } else {
            writeln!(
                out,
                "{frame:>5} {samples:>10} {change_ms:>10.1} {update_ms:>10.1} {render_ms:>10.1} {shade_ms:>10.1} {frame_ms:>10.1}"
            )?;
        }
        frames.push(times);
    }
    let medians = FrameTimes::median(&frames);
    let (update, render, shade, frame, changed) = (
        medians.update_ms,
        medians.render_ms,
        medians.shade_ms,
        medians.frame_ms,
        medians.change_ms,
    );
    if args.json {
        writeln!(
            out,
            "{{\"dynamic\": \"{kind_name}\", \"view\": \"{view}\", \"surface\": \"{surface}\", \"width\": {w}, \"height\": {h}, \"far\": \"{far}\", \"shadows\": {}, \"frames\": {}, \"median_change_ms\": {changed}, \"median_update_ms\": {update}, \"median_render_ms\": {render}, \"median_shade_ms\": {shade}, \"median_frame_ms\": {frame}, \"frames_per_s\": {}}}",
            bench.shadows(),
            frames.len(),
            1e3 / frame
        )?;
    } else {
        writeln!(
            out,
            "median: update {update:.1} ms (the change {changed:.1} ms), render {render:.1} ms, shade {shade:.1} ms, frame {frame:.1} ms ({:.1} frames/s)",
            1e3 / frame
        )?;
    }
    Ok(())
}
