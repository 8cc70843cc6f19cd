//! Fuzzes the PNG height reader in its three encodings (the first byte picks one).
#![no_main]

use libfuzzer_sys::fuzz_target;
use relief_io::{read_raster_from_bytes, Format, ReadOptions, VoidPolicy};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Some((&pick, bytes)) = data.split_first() else { return };
    let format = [Format::Png16, Format::TerrainRgb, Format::Terrarium][pick as usize % 3];
    let options = ReadOptions { max_memory: 64 << 20, ..ReadOptions::default() };
    let path = Path::new("fuzz.png");
    if let Ok(raster) = read_raster_from_bytes(bytes, format, path, &options) {
        let _ = raster.into_height_field(path, VoidPolicy::Fill);
    }
});
