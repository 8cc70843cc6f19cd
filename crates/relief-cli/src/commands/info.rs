//! `relief info`: what a height-field file holds and what rendering it costs.

use crate::args::InfoArgs;
use anyhow::Result;

/// Runs `relief info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    let field = relief_io::read_npy_height_field(&args.input)?;
    let g = field.geometry();
    let samples_bytes = std::mem::size_of_val(field.samples());
    // The max mipmap adds a third of the samples (1/4 + 1/16 + ...).
    let mipmap_bytes = samples_bytes / 3;
    println!("file:      {}", args.input.display());
    println!("format:    NumPy .npy");
    println!("size:      {} x {} samples", field.width(), field.height());
    println!("spacing:   {} x {} (grid units; set with --spacing)", g.dx, g.dy);
    println!("values:    {} .. {}", field.min_sample(), field.max_sample());
    println!(
        "memory:    {:.1} MiB samples + {:.1} MiB max mipmap to render",
        samples_bytes as f64 / 1048576.0,
        mipmap_bytes as f64 / 1048576.0
    );
    Ok(())
}
