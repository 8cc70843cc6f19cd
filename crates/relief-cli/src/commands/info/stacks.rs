//! `relief info` of a `.stacks` file: its grid, layers and materials, and the memory of its
//! LOD mipmap against the voxel grid it stands for (Löffler et al. 2011, section 4).

use super::args::InfoArgs;
use anyhow::Result;
use relief_core::StacksMipmap;
use std::io::Write;

/// Runs `relief info` on a stacks file.
pub fn run(args: &InfoArgs) -> Result<()> {
    crate::applies::check_read_args(&args.read, Some(&args.input))?;
    let stacks = relief_io::read_stacks(&args.input)?;
    let mut out = std::io::stdout().lock();
    let (w, h) = (stacks.width(), stacks.height());
    let s = stacks.spacing();
    writeln!(out, "file:        {}", args.input.display())?;
    writeln!(out, "format:      relief stacks (docs/stacks.md)")?;
    writeln!(
        out,
        "size:        {w} x {h} stacks of {} x {} m ({:.0} x {:.0} m)",
        s.x,
        s.y,
        s.x * w as f64,
        s.y * h as f64
    )?;
    let layers = stacks.layers().len();
    let multi = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| stacks.stack(x, y).len() > 1)
        .count();
    writeln!(
        out,
        "layers:      {layers} ({:.2} a stack; {multi} stacks with 2 or more)",
        layers as f64 / (w * h) as f64
    )?;
    let (low, high) = stacks.height_range().unwrap_or((0.0, 0.0));
    writeln!(out, "heights:     {low} .. {high} m")?;
    for (k, m) in stacks.materials().iter().enumerate() {
        let volume = stacks.volume(|x| x == m);
        let kind = if m.is_liquid() { "liquid" } else { "solid" };
        writeln!(
            out,
            "material {k}:  {} ({kind}, colour #{:02x}{:02x}{:02x}), {volume:.1} m³",
            m.name, m.color[0], m.color[1], m.color[2]
        )?;
    }
    let mipmap = StacksMipmap::new(stacks)?;
    let voxels = (high as f64 - low as f64) / s.x;
    // A voxel grid of the same resolution holds at least a float density a voxel.
    let voxel_bytes = 4.0 * w as f64 * h as f64 * voxels.ceil().max(1.0);
    writeln!(
        out,
        "mipmap:      {} levels, {:.1} MiB (the voxel grid of {w} x {h} x {:.0} voxels of {} m: \
         {:.1} MiB at a float a voxel)",
        mipmap.level_count(),
        mipmap.memory_bytes() as f64 / 1048576.0,
        voxels.ceil(),
        s.x,
        voxel_bytes / 1048576.0
    )?;
    Ok(())
}
