//! `relief info STORE`: what a tile store holds, and whether its build finished.

use super::args::InfoArgs;
use crate::applies;
use anyhow::Result;
use relief_tiles::{precision_name, TileStore};
use std::io::Write;

/// Runs `relief info` on a tile store.
pub fn run(args: &InfoArgs) -> Result<()> {
    if let Some(option) =
        [(args.read.voids.is_some(), "--voids"), (args.read.max_memory.is_some(), "--max-memory")]
            .into_iter()
            .find_map(|(given, name)| given.then_some(name))
    {
        return Err(applies::refuse(option, "height files", "a tile store"));
    }
    let store = TileStore::open_any(&args.input)?;
    let header = store.header();
    let layout = store.layout();
    let (done, total) = store.progress();
    let g = store.geometry();
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "store:       {} (relief tile store, version {})",
        args.input.display(),
        header.version
    )?;
    if header.complete && done == total {
        writeln!(out, "state:       complete ({total} tiles)")?;
    } else {
        writeln!(
            out,
            "state:       INCOMPLETE: {done} of {total} tiles built; run the same `relief tile` \
             command again to resume it"
        )?;
    }
    writeln!(out, "size:        {} x {} samples", header.width, header.height)?;
    writeln!(out, "spacing:     {} x {}", g.dx, g.dy)?;
    writeln!(out, "origin:      {}, {} (south-west corner)", g.origin.x, g.origin.y)?;
    if done == total {
        writeln!(out, "values:      {} .. {}", store.floor(), store.top())?;
    }
    writeln!(
        out,
        "tiles:       {}^2 samples (and a ring of one), {} levels, {} precision",
        header.tile,
        header.levels,
        precision_name(header.precision)
    )?;
    for level in 0..layout.level_count() {
        let (tx, ty) = layout.tiles_of(level);
        let (w, h) = layout.level_size(level);
        writeln!(out, "  level {level:>2}:  {w} x {h} samples in {tx} x {ty} tiles")?;
    }
    for source in &header.sources {
        writeln!(out, "input:       {} ({} bytes)", source.path, source.bytes)?;
    }
    if let Some(texture) = &header.texture {
        let [col, row, _, _] = texture.window;
        writeln!(
            out,
            "texture:     {} x {} texels of {} x {} (8-bit sRGB), tiles of {}^2, {} levels, from \
             {} ({} bytes; its pixels from column {col}, row {row})",
            texture.width,
            texture.height,
            texture.texel[0],
            texture.texel[1],
            texture.tile,
            texture.levels,
            texture.source.path,
            texture.source.bytes
        )?;
    }
    Ok(())
}
