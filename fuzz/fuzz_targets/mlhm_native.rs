//! Fuzzes the native `.mlhm` reader: any bytes give a valid map or an error, never a panic or
//! a hang.
#![no_main]

use libfuzzer_sys::fuzz_target;
use relief_io::{read_mlhm_native_from_bytes, ReadOptions};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let options = ReadOptions { max_memory: 64 << 20, ..ReadOptions::default() };
    if let Ok(map) = read_mlhm_native_from_bytes(data, Path::new("fuzz.mlhm"), &options) {
        assert!(map.validate().is_ok());
    }
});
