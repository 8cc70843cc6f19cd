//! Every height reader of a single-file format alike: empty files, directories and missing
//! files refused by cause; a `.npy` grid read as a raster.

mod common;
#[path = "common/reading.rs"]
mod reading;

use common::TestDir;
use reading::{
    check_truncations_and_flips, options, png_options, read_bytes, same_samples, Accepted, Reader,
};

use relief_io::asc::read_asc;
use relief_io::hgt::read_hgt;
use relief_io::npy::{read_npy, read_npz, write_npy_f32};
use relief_io::png::read_png_height;
use relief_io::{IoError, PngEncoding, ReadOptions};
use std::io::ErrorKind;

/// Every reader refuses an empty file with a format error and a directory with an I/O error.
#[test]
fn empty_files_and_directories_are_refused_by_every_reader() {
    let dir = TestDir::new("empty");
    let readers: [(&str, Reader, ReadOptions); 7] = [
        ("N36W085.hgt", read_hgt, options()),
        ("grid.asc", read_asc, options()),
        ("grey.png", read_png_height, options()),
        ("rgb.png", read_png_height, png_options(PngEncoding::TerrainRgb)),
        ("rgb.png", read_png_height, png_options(PngEncoding::Terrarium)),
        ("arrays.npz", read_npz, options()),
        ("grid.npy", read_npy, options()),
    ];
    for (name, read, options) in readers {
        let path = dir.join(name);
        let err = read_bytes(read, &path, b"", &options).unwrap_err();
        assert!(matches!(err, IoError::Format { .. }), "{name}: {err}");
        assert!(err.to_string().contains(name), "{err}");
        let sub = dir.join(&format!("{name}.d"));
        std::fs::create_dir_all(&sub).unwrap();
        let err = read(&sub, &options).unwrap_err();
        assert!(
            matches!(&err, IoError::Io { source, .. } if source.kind() == ErrorKind::IsADirectory),
            "{name}: {err}"
        );
        let err = read(&dir.join("absent"), &options).unwrap_err();
        assert!(
            matches!(&err, IoError::Io { source, .. } if source.kind() == ErrorKind::NotFound),
            "{name}: {err}"
        );
    }
}

#[test]
fn npy_raster_keeps_array_rows_and_refuses_non_finite_samples() {
    let dir = TestDir::new("npy-raster");
    let path = dir.join("grid.npy");
    write_npy_f32(&path, &[3, 1], &[1.0, 2.0, 3.0]).unwrap();
    assert_eq!(read_npy(&path, &options()).unwrap().samples, [1.0, 2.0, 3.0]);
    write_npy_f32(&path, &[3, 1], &[1.0, f32::NAN, 3.0]).unwrap();
    let err = read_npy(&path, &options()).unwrap_err();
    assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    let mut good = std::fs::read(&path).unwrap();
    let nan_at = good.len() - 8;
    good[nan_at..nan_at + 4].copy_from_slice(&2f32.to_le_bytes());
    let (intact, accepted) =
        check_truncations_and_flips(read_npy, &path, &good, &options(), |_| false);
    // No checksum: a changed data byte reads as another height (or is refused as NaN or
    // infinite). The header is text that must parse with a shape matching the data, so a
    // changed header byte is refused unless it does not matter (the minor version, '<' made
    // '=' on a little-endian machine): whatever reads is 1 x 3, and a header change keeps
    // the samples.
    let data_at = good.len() - 12;
    assert!(accepted.iter().filter(|a| a.at < data_at).count() <= 8, "header changes read");
    for Accepted { at, raster } in &accepted {
        assert_eq!((raster.width, raster.height), (intact.width, intact.height), "byte {at}");
        assert!(*at >= data_at || same_samples(raster, &intact), "byte {at}");
    }
}
