//! The overview pyramid of a cloud-optimised GeoTIFF, built from the spilled full-resolution
//! tiles: each level the 2 x 2 mean of the one before (voids ignored), a few tiles at a time,
//! its compressed tiles spilled in turn, so that no level is ever whole in memory.

use crate::geotiff::cog_spill::Spill;
use crate::geotiff::cog_tiles::{pack_tile, unpack_tile, LevelTiles, TileGrid};
use crate::IoError;
use rayon::prelude::*;
use std::path::Path;

/// Builds every overview level of `full` (see [`TileGrid::overviews`]) from the tiles in
/// `spill`, appending theirs; returns them, largest first. `void` is the value voids are
/// stored as (NaN is a void too); `path` names the output in errors.
pub(crate) fn build_overviews(
    path: &Path,
    spill: &mut Spill,
    full: &LevelTiles,
    void: f32,
) -> Result<Vec<LevelTiles>, IoError> {
    let mut levels: Vec<LevelTiles> = Vec::new();
    for grid in full.grid.overviews() {
        let source = levels.last().unwrap_or(full);
        let level = build_level(path, spill, source, grid, void)?;
        levels.push(level);
    }
    Ok(levels)
}

/// Output tiles computed in parallel at a time: one per thread, which bounds the memory held
/// (see [`overview_bytes_per_thread`]).
fn batch() -> usize {
    rayon::current_num_threads().max(1)
}

/// Bytes one thread holds building a tile of `raw` bytes of samples: the 2 x 2 source tiles
/// stored and decoded, the decoding buffer, the output tile, its predicted bytes and its
/// stored bytes (each at most a tile's bytes and Deflate's overhead).
pub(crate) fn overview_bytes_per_thread(raw: u64) -> u64 {
    let stored = stored_bound(raw);
    4 * stored + 4 * raw + raw + raw + raw + stored
}

/// The most bytes Deflate stores `raw` bytes in (stored blocks at worst), and the zlib frame.
pub(crate) fn stored_bound(raw: u64) -> u64 {
    raw + raw / 1000 + 5 * (raw / 16384 + 1) + 64
}

/// Builds `grid`, the level after `source`, from `source`'s spilled tiles; appends its tiles
/// to `spill`.
fn build_level(
    path: &Path,
    spill: &mut Spill,
    source: &LevelTiles,
    grid: TileGrid,
    void: f32,
) -> Result<LevelTiles, IoError> {
    let mut level = LevelTiles::new(grid, source.bands);
    let jobs: Vec<(usize, usize, usize)> = (0..source.bands)
        .flat_map(|band| {
            (0..grid.down).flat_map(move |ty| (0..grid.across).map(move |tx| (band, tx, ty)))
        })
        .collect();
    for batch in jobs.chunks(batch()) {
        // The stored bytes of each output tile's (up to) 2 x 2 source tiles, read in turn.
        let mut inputs = Vec::with_capacity(batch.len());
        for &(band, tx, ty) in batch {
            let mut sources: [Option<Vec<u8>>; 4] = Default::default();
            for (k, slot) in sources.iter_mut().enumerate() {
                let (sx, sy) = (2 * tx + k % 2, 2 * ty + k / 2);
                if sx < source.grid.across && sy < source.grid.down {
                    let index = source.grid.index(band, sx, sy);
                    let (offset, count) = source.get(index).ok_or_else(|| {
                        IoError::invalid_data(path, format!("overview source tile {index} missing"))
                    })?;
                    let mut stored = Vec::new();
                    spill.read(offset, count, &mut stored)?;
                    *slot = Some(stored);
                }
            }
            inputs.push(sources);
        }
        let packed: Vec<Result<Vec<u8>, IoError>> = inputs
            .into_par_iter()
            .zip(batch)
            .map(|(sources, &(_, tx, ty))| {
                let samples = mean_tile(&source.grid, &grid, (tx, ty), &sources, void)
                    .map_err(|reason| IoError::format(path, format!("spilled tile: {reason}")))?;
                pack_tile(path, &samples, grid.tile)
            })
            .collect();
        for (packed, &(band, tx, ty)) in packed.into_iter().zip(batch) {
            let packed = packed?;
            let offset = spill.append(&packed)?;
            // A stored tile is never empty (zlib's frame alone has 6 bytes) and at most
            // stored_bound(4 MiB) long.
            level.set(grid.index(band, tx, ty), offset, packed.len() as u32);
        }
    }
    Ok(level)
}

/// Output tile (`tx`, `ty`) of level `grid`: each sample the mean of the 2 x 2 samples of
/// level `source` under it that are neither voids nor past its edge, the void value where
/// there are none or past `grid`'s edge. `sources` holds the stored 2 x 2 source tiles
/// (north-west, north-east, south-west, south-east; `None` past the source's edge).
fn mean_tile(
    source: &TileGrid,
    grid: &TileGrid,
    (tx, ty): (usize, usize),
    sources: &[Option<Vec<u8>>; 4],
    void: f32,
) -> Result<Vec<f32>, String> {
    let t = grid.tile;
    let half = t / 2;
    let is_void = |v: f32| v.is_nan() || v == void;
    let mut out = vec![void; t * t];
    let mut scratch = Vec::new();
    // Each source tile lies under one quarter of the output tile.
    for (k, stored) in sources.iter().enumerate() {
        let Some(stored) = stored else { continue };
        let tile = unpack_tile(stored, t, &mut scratch)?;
        let (kx, ky) = (k % 2, k / 2);
        // The source tile's samples within the source level.
        let (sx0, sy0) = ((2 * tx + kx) * t, (2 * ty + ky) * t);
        let cols = (source.width - sx0).min(t);
        let rows = (source.height - sy0).min(t);
        for r in 0..rows.div_ceil(2) {
            let out_row = &mut out[(ky * half + r) * t + kx * half..][..cols.div_ceil(2)];
            let north = &tile[2 * r * t..][..cols];
            let south = (2 * r + 1 < rows).then(|| &tile[(2 * r + 1) * t..][..cols]);
            for (c, sample) in out_row.iter_mut().enumerate() {
                let (mut sum, mut n) = (0f64, 0u32);
                let mut add = |v: f32| {
                    if !is_void(v) {
                        sum += f64::from(v);
                        n += 1;
                    }
                };
                let pair = &north[2 * c..cols.min(2 * c + 2)];
                pair.iter().for_each(|&v| add(v));
                if let Some(south) = south {
                    south[2 * c..cols.min(2 * c + 2)].iter().for_each(|&v| add(v));
                }
                if n > 0 {
                    *sample = (sum / f64::from(n)) as f32;
                }
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_dir::TestDir;

    /// Spills a `width x height` band of `value(x, y)` (file coordinates) in `tile` tiles.
    fn spilled(
        spill: &mut Spill,
        width: usize,
        height: usize,
        tile: usize,
        value: impl Fn(usize, usize) -> f32,
    ) -> LevelTiles {
        let grid = TileGrid::new(width, height, tile);
        let mut level = LevelTiles::new(grid, 1);
        for ty in 0..grid.down {
            for tx in 0..grid.across {
                let mut samples = vec![f32::NAN; tile * tile];
                for r in 0..tile {
                    for c in 0..tile {
                        let (x, y) = (tx * tile + c, ty * tile + r);
                        if x < width && y < height {
                            samples[r * tile + c] = value(x, y);
                        }
                    }
                }
                let stored = pack_tile(Path::new("t"), &samples, tile).unwrap();
                let offset = spill.append(&stored).unwrap();
                level.set(grid.index(0, tx, ty), offset, stored.len() as u32);
            }
        }
        level
    }

    /// The samples of a level, row-major.
    fn samples(spill: &mut Spill, level: &LevelTiles) -> Vec<f32> {
        let g = level.grid;
        let mut out = vec![0f32; g.width * g.height];
        for ty in 0..g.down {
            for tx in 0..g.across {
                let (offset, count) = level.get(g.index(0, tx, ty)).unwrap();
                let mut stored = Vec::new();
                spill.read(offset, count, &mut stored).unwrap();
                let tile = unpack_tile(&stored, g.tile, &mut Vec::new()).unwrap();
                for r in 0..g.tile {
                    for c in 0..g.tile {
                        let (x, y) = (tx * g.tile + c, ty * g.tile + r);
                        if x < g.width && y < g.height {
                            out[y * g.width + x] = tile[r * g.tile + c];
                        }
                    }
                }
            }
        }
        out
    }

    #[test]
    fn each_level_is_the_mean_of_the_non_void_samples_under_it() {
        let dir = TestDir::new("cog-overviews");
        let mut spill = Spill::create(&dir.path().join("spill")).unwrap();
        let (width, height) = (301, 259);
        // Voids: a 3 x 3 patch (so that some 2 x 2 groups are all void) and scattered ones.
        let value = |x: usize, y: usize| {
            if (10..13).contains(&x) && (20..23).contains(&y) || (x * 7 + y * 3).is_multiple_of(11)
            {
                -5.0
            } else {
                (x as f32 * 0.37).sin() * 100.0 + y as f32
            }
        };
        let full = spilled(&mut spill, width, height, 128, value);
        let levels = build_overviews(Path::new("t"), &mut spill, &full, -5.0).unwrap();
        let sizes: Vec<_> = levels.iter().map(|l| (l.grid.width, l.grid.height)).collect();
        assert_eq!(sizes, [(151, 130), (76, 65)]);
        let first = samples(&mut spill, &levels[0]);
        for oy in 0..130 {
            for ox in 0..151 {
                let mut under = Vec::new();
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let (x, y) = (2 * ox + dx, 2 * oy + dy);
                    if x < width && y < height && value(x, y) != -5.0 {
                        under.push(f64::from(value(x, y)));
                    }
                }
                let expected = if under.is_empty() {
                    -5.0
                } else {
                    (under.iter().sum::<f64>() / under.len() as f64) as f32
                };
                assert_eq!(first[oy * 151 + ox], expected, "({ox}, {oy})");
            }
        }
        // The 3 x 3 void patch covers the group of (10..12, 20..22) whole.
        assert_eq!(first[10 * 151 + 5], -5.0);
        let second = samples(&mut spill, &levels[1]);
        let mean = |k: [f32; 4]| {
            let valid: Vec<f64> = k.iter().filter(|&&v| v != -5.0).map(|&v| f64::from(v)).collect();
            (valid.iter().sum::<f64>() / valid.len() as f64) as f32
        };
        let at = |x: usize, y: usize| first[y * 151 + x];
        assert_eq!(second[0], mean([at(0, 0), at(1, 0), at(0, 1), at(1, 1)]));
        // The last column of the second level lies over the first's last column alone.
        assert_eq!(second[75], mean([at(150, 0), -5.0, at(150, 1), -5.0]));
    }
}
