//! How long readers take to refuse files that lie about their size: an ESRI grid whose header
//! claims 100000 x 100000 samples but holds three, and `.npz` archives (stored and deflated)
//! whose member claims 4 GB uncompressed. Both must be refused up front, from the header,
//! without reading or decompressing what the header claims; the figures show it.
//!
//! `cargo bench -p relief-bench --bench refusal_times -- [REPEATS] [DIR]`
//! (REPEATS 100, DIR the system's temporary folder).

#[path = "common/args.rs"]
mod args;

use relief_io::asc::read_asc;
use relief_io::npy::{read_npz, write_npy_f32};
use relief_io::ReadOptions;
use std::io::{Cursor, Write};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = args::program_args();
    let repeats: u32 = args.first().map_or(Ok(100), |a| a.parse())?;
    let dir = args.get(1).map_or_else(std::env::temp_dir, std::path::PathBuf::from);
    let dir = dir.join(format!("relief-io-refusal-times-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;

    let asc = dir.join("lying.asc");
    let huge = "ncols 100000\nnrows 100000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n";
    std::fs::write(&asc, huge)?;
    let unbounded = ReadOptions { max_memory: u64::MAX, ..ReadOptions::default() };
    for (what, options) in
        [("within the default budget", ReadOptions::default()), ("without a budget", unbounded)]
    {
        time(&format!(".asc claiming 10^10 samples, {what}"), repeats, || {
            read_asc(&asc, &options).is_err()
        });
    }

    let member = dir.join("member.npy");
    write_npy_f32(&member, &[2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0])?;
    let member = std::fs::read(&member)?;
    let npz = dir.join("bomb.npz");
    for deflated in [false, true] {
        std::fs::write(&npz, claiming_4_gb(&member, deflated)?)?;
        let how = if deflated { "deflated" } else { "stored" };
        time(&format!(".npz {how} member claiming 4 GB"), repeats, || {
            read_npz(&npz, &ReadOptions::default()).is_err()
        });
    }
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

/// Runs `refuse` `repeats` times and prints the mean time; every run must refuse.
fn time(what: &str, repeats: u32, refuse: impl Fn() -> bool) {
    let start = Instant::now();
    for _ in 0..repeats {
        assert!(refuse(), "{what}: read, not refused");
    }
    let mean = start.elapsed().as_secs_f64() / f64::from(repeats.max(1));
    println!("{what}: refused in {:.3} ms", mean * 1e3);
}

/// A zip archive of one member `a.npy` holding `npy`, whose local and central headers then
/// declare 4 GB uncompressed.
fn claiming_4_gb(npy: &[u8], deflated: bool) -> Result<Vec<u8>, Box<dyn std::error::Error>> {
    let mut writer = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let method =
        if deflated { zip::CompressionMethod::Deflated } else { zip::CompressionMethod::Stored };
    writer
        .start_file("a.npy", zip::write::SimpleFileOptions::default().compression_method(method))?;
    writer.write_all(npy)?;
    let mut archive = writer.finish()?.into_inner();
    for at in 0..archive.len().saturating_sub(4) {
        let offset = match archive[at..at + 4] {
            [0x50, 0x4b, 0x03, 0x04] => 22,
            [0x50, 0x4b, 0x01, 0x02] => 24,
            _ => continue,
        };
        archive[at + offset..at + offset + 4].copy_from_slice(&0xffff_fff0u32.to_le_bytes());
    }
    Ok(archive)
}
