//! Raw little-endian files the benchmark scripts exchange with the programs they time (the
//! premade rays and hits of bench/native_anchor.py): no header, the values one after another.

use anyhow::{bail, Context, Result};
use std::path::Path;

/// The float32 values of the raw file at `path`.
pub fn read_f32s(path: &Path) -> Result<Vec<f32>> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    if bytes.len() % 4 != 0 {
        bail!("{}: {} bytes is not a whole number of float32 values", path.display(), bytes.len());
    }
    Ok(bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect())
}

/// Writes `values` to `path` as raw float32.
#[allow(dead_code)] // trace_rays writes, shade_hits only reads
pub fn write_f32s(path: &Path, values: &[f32]) -> Result<()> {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(path, bytes).with_context(|| format!("writing {}", path.display()))
}
