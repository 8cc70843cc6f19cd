//! Fuzzes the `.stacks` reader: any bytes give valid stacks or an error, never a panic, a hang
//! or an allocation the file's length does not justify.
#![no_main]

use libfuzzer_sys::fuzz_target;
use relief_io::stacks_from_bytes;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(stacks) = stacks_from_bytes(data, Path::new("fuzz.stacks")) {
        assert!(stacks.validate().is_ok());
    }
});
