//! Fuzzes the Asc reader: any bytes give a raster or an error, never a panic or a hang.
#![no_main]

use libfuzzer_sys::fuzz_target;
use relief_io::{read_raster_from_bytes, Format, ReadOptions, VoidPolicy};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let options = ReadOptions { max_memory: 64 << 20, ..ReadOptions::default() };
    let path = Path::new("fuzz.asc");
    if let Ok(raster) = read_raster_from_bytes(data, Format::Asc, path, &options) {
        let _ = raster.clone().into_height_field(path, VoidPolicy::Fill);
        let _ = raster.into_height_field(path, VoidPolicy::Hole);
    }
});
