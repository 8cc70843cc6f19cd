//! Fuzzes the MLHM scene reader: the first two bytes give the JSON's length (little-endian),
//! the JSON follows, the rest is the .dat stream. Any bytes give a scene or an error, never a
//! panic or a hang.
#![no_main]

use libfuzzer_sys::fuzz_target;
use relief_io::{read_mlhm_scene_from_bytes, ReadOptions};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Some((head, rest)) = data.split_first_chunk::<2>() else { return };
    let json_len = (u16::from_le_bytes(*head) as usize).min(rest.len());
    let (json, dat) = rest.split_at(json_len);
    let options = ReadOptions { max_memory: 64 << 20, ..ReadOptions::default() };
    let _ = read_mlhm_scene_from_bytes(json, dat, Path::new("fuzz.json"), &options);
});
