//! Reading test files through a reader: bytes written then read, every truncation and
//! changed byte of a good file tried, format errors matched by their words.
#![allow(dead_code)]

use relief_io::{IoError, PngEncoding, Raster, ReadOptions};
use std::path::Path;

pub type Reader = fn(&Path, &ReadOptions) -> Result<Raster, IoError>;

pub fn options() -> ReadOptions {
    ReadOptions::default()
}

pub fn png_options(png_encoding: PngEncoding) -> ReadOptions {
    ReadOptions { png_encoding, ..ReadOptions::default() }
}

/// Reads `bytes` written to `path` with `read`.
pub fn read_bytes(
    read: Reader,
    path: &Path,
    bytes: &[u8],
    options: &ReadOptions,
) -> Result<Raster, IoError> {
    std::fs::write(path, bytes).unwrap();
    read(path, options)
}

/// A changed copy of a file that a reader accepted.
pub struct Accepted {
    /// The offset of the changed byte.
    pub at: usize,
    /// The raster read.
    pub raster: Raster,
}

/// Every proper prefix of `good` (but those `valid_prefix` accepts) is refused, and no single
/// byte changed in any of five ways (5 x `good.len()` copies) makes the reader panic. Returns
/// the changed copies that were still read, and the raster of `good`, for the caller to judge
/// against what the format can detect.
pub fn check_truncations_and_flips(
    read: Reader,
    path: &Path,
    good: &[u8],
    options: &ReadOptions,
    valid_prefix: impl Fn(usize) -> bool,
) -> (Raster, Vec<Accepted>) {
    let intact = read_bytes(read, path, good, options).expect("the intact file reads");
    for len in 0..good.len() {
        if valid_prefix(len) {
            continue;
        }
        let result = read_bytes(read, path, &good[..len], options);
        assert!(result.is_err(), "prefix of {len} of {} bytes accepted", good.len());
    }
    let mut accepted = Vec::new();
    for at in 0..good.len() {
        let changes: [fn(u8) -> u8; 5] = [|b| b ^ 0x01, |b| b ^ 0x80, |_| 0xff, |_| 0, |_| b'9'];
        for change in changes {
            let mut bad = good.to_vec();
            bad[at] = change(bad[at]);
            if bad[at] == good[at] {
                continue;
            }
            if let Ok(raster) = read_bytes(read, path, &bad, options) {
                // Whatever reads must be a raster consistent with itself.
                assert_eq!(raster.samples.len(), raster.width * raster.height, "byte {at}");
                accepted.push(Accepted { at, raster });
            }
        }
    }
    (intact, accepted)
}

/// Fails naming the changed bytes of the copies in `accepted`, if any.
pub fn assert_none_read(accepted: &[Accepted]) {
    let at: Vec<usize> = accepted.iter().map(|a| a.at).collect();
    assert!(at.is_empty(), "copies with these bytes changed read: {at:?}");
}

/// Whether `a` and `b` have the same size and the same samples, bit for bit (voids too).
pub fn same_samples(a: &Raster, b: &Raster) -> bool {
    (a.width, a.height) == (b.width, b.height)
        && a.samples.iter().zip(&b.samples).all(|(x, y)| x.to_bits() == y.to_bits())
}

pub fn assert_format(result: Result<Raster, IoError>, needle: &str) {
    match result {
        Err(err @ IoError::Format { .. }) => {
            assert!(err.to_string().contains(needle), "'{err}' does not say '{needle}'")
        }
        other => panic!("expected a format error saying '{needle}', got {other:?}"),
    }
}
