//! How fast `open_rows` reads: MB/s of f32 samples delivered from an uncompressed float32
//! GeoTIFF in strips, a `.npy` array and a Deflate-compressed tiled GeoTIFF, each N x N,
//! read in bands of 513 rows from the south as the tile builder reads them.
//!
//! `cargo bench -p relief-bench --bench rows_throughput -- [N] [DIR] [FILE.tif ...]`
//! (N 8192, DIR the system's temporary folder); files given after DIR are timed too. The
//! files are written first and stay in the page cache: the figures are those of a warm cache.

use relief_io::npy::write_npy_f32;
use relief_io::{open_rows, ReadOptions};
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tiff::encoder::colortype::Gray32Float;
use tiff::encoder::compression::{CompressionAlgorithm, Deflate, DeflateLevel};
use tiff::encoder::TiffEncoder;
use tiff::tags::Tag;

#[path = "common/args.rs"]
mod args;

/// Rows per request: a tile of 512 and its border, as relief-tiles reads.
const BAND: usize = 513;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = args::program_args();
    let n: usize = args.first().map_or(Ok(8192), |a| a.parse())?;
    let dir = args.get(1).map_or_else(std::env::temp_dir, PathBuf::from);
    let samples: Vec<f32> =
        (0..n * n).map(|i| ((i % n) as f32 * 0.01).sin() * 300.0 + (i / n) as f32 * 0.05).collect();
    let mut files = Vec::new();

    let strips = dir.join(format!("rows-{n}-strips.tif"));
    let mut bytes = Cursor::new(Vec::new());
    TiffEncoder::new(&mut bytes)?.write_image::<Gray32Float>(n as u32, n as u32, &samples)?;
    std::fs::write(&strips, bytes.into_inner())?;
    files.push(("uncompressed f32 GeoTIFF, strips", strips));

    let npy = dir.join(format!("rows-{n}.npy"));
    write_npy_f32(&npy, &[n, n], &samples)?;
    files.push(("f32 .npy", npy));

    let tiled = dir.join(format!("rows-{n}-deflate-tiles.tif"));
    std::fs::write(&tiled, deflate_tiles(&samples, n, 512)?)?;
    files.push(("Deflate GeoTIFF, 512^2 tiles", tiled));
    drop(samples);

    for extra in args.iter().skip(2) {
        files.push(("given", PathBuf::from(extra)));
    }
    for (what, path) in &files {
        let (mb, seconds) = read_all(path)?;
        let size = std::fs::metadata(path)?.len() as f64 / 1e6;
        println!(
            "{what:34} {:>9.0} MB of samples in {seconds:6.2} s: {:7.0} MB/s  ({size:.0} MB file, {})",
            mb,
            mb / seconds,
            path.display()
        );
    }
    for (what, path) in &files {
        if *what != "given" {
            std::fs::remove_file(path)?;
        }
    }
    Ok(())
}

/// Reads every row of `path` in bands of [`BAND`] rows, south first; returns the MB of f32
/// samples delivered and the seconds taken.
fn read_all(path: &Path) -> Result<(f64, f64), Box<dyn std::error::Error>> {
    let started = Instant::now();
    let mut rows = open_rows(path, &ReadOptions::default())?;
    let (w, h) = (rows.width(), rows.height());
    let mut band = vec![0f32; BAND * w];
    let (mut checksum, mut delivered) = (0f64, 0usize);
    for first in (0..h).step_by(BAND - 1) {
        let count = BAND.min(h - first);
        rows.read_rows(first, &mut band[..count * w])?;
        checksum += f64::from(band[0]);
        delivered += count * w;
    }
    let seconds = started.elapsed().as_secs_f64();
    std::hint::black_box(checksum);
    Ok((delivered as f64 * 4.0 / 1e6, seconds))
}

/// A tiled float32 GeoTIFF of `n x n` samples in `tile x tile` tiles, Deflate-compressed.
fn deflate_tiles(
    samples: &[f32],
    n: usize,
    tile: usize,
) -> Result<Vec<u8>, Box<dyn std::error::Error>> {
    let mut file = Cursor::new(Vec::new());
    let mut tiff = TiffEncoder::new(&mut file)?;
    let mut dir = tiff.image_directory()?;
    let (mut offsets, mut counts) = (Vec::<u32>::new(), Vec::<u32>::new());
    let mut raw = vec![0u8; tile * tile * 4];
    for ty in 0..n.div_ceil(tile) {
        for tx in 0..n.div_ceil(tile) {
            raw.fill(0);
            for r in 0..tile.min(n - ty * tile) {
                for c in 0..tile.min(n - tx * tile) {
                    let v = samples[(ty * tile + r) * n + tx * tile + c];
                    raw[(r * tile + c) * 4..][..4].copy_from_slice(&v.to_ne_bytes());
                }
            }
            let mut packed = Vec::new();
            Deflate::with_level(DeflateLevel::Fast).write_to(&mut packed, &raw)?;
            offsets.push(u32::try_from(dir.write_data(&packed[..])?)?);
            counts.push(u32::try_from(packed.len())?);
        }
    }
    dir.write_tag(Tag::ImageWidth, n as u32)?;
    dir.write_tag(Tag::ImageLength, n as u32)?;
    dir.write_tag(Tag::BitsPerSample, 32u16)?;
    dir.write_tag(Tag::Compression, 8u16)?;
    dir.write_tag(Tag::PhotometricInterpretation, 1u16)?;
    dir.write_tag(Tag::SamplesPerPixel, 1u16)?;
    dir.write_tag(Tag::TileWidth, tile as u32)?;
    dir.write_tag(Tag::TileLength, tile as u32)?;
    dir.write_tag(Tag::TileOffsets, &offsets[..])?;
    dir.write_tag(Tag::TileByteCounts, &counts[..])?;
    dir.write_tag(Tag::SampleFormat, 3u16)?;
    dir.finish()?;
    Ok(file.into_inner())
}
