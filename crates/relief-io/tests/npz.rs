//! NumPy `.npz` archives: members stored or deflated chosen by name, members claiming huge
//! sizes refused before decompressing, truncated and changed archives.

mod common;
#[path = "common/reading.rs"]
mod reading;

use common::TestDir;
use reading::{
    assert_format, check_truncations_and_flips, options, read_bytes, same_samples, Accepted,
};

use relief_core::GridGeometry;
use relief_io::npy::{read_npz, write_npy_f32};
use relief_io::{Format, IoError, ReadOptions};
use std::io::{Cursor, Write};

/// The bytes of a little-endian f32 `.npy` file of `shape` holding `data`.
fn npy_bytes(dir: &TestDir, shape: &[usize], data: &[f32]) -> Vec<u8> {
    let path = dir.join("member.npy");
    write_npy_f32(&path, shape, data).unwrap();
    std::fs::read(&path).unwrap()
}

/// A zip archive of `(name, bytes, deflated)` members, in that order.
fn zip_archive(members: &[(&str, &[u8], bool)]) -> Vec<u8> {
    let mut writer = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for &(name, bytes, deflated) in members {
        let method = if deflated {
            zip::CompressionMethod::Deflated
        } else {
            zip::CompressionMethod::Stored
        };
        let options = zip::write::SimpleFileOptions::default().compression_method(method);
        writer.start_file(name, options).unwrap();
        writer.write_all(bytes).unwrap();
    }
    writer.finish().unwrap().into_inner()
}

#[test]
fn npz_members_stored_or_deflated_are_selected_by_name() {
    let dir = TestDir::new("npz-select");
    let path = dir.join("arrays.npz");
    let a = npy_bytes(&dir, &[2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    let b_values: Vec<f32> = (0..40 * 30).map(|i| (i % 17) as f32 * 0.25).collect();
    let b = npy_bytes(&dir, &[40, 30], &b_values);
    for (a_deflated, b_deflated) in [(false, true), (true, false), (true, true), (false, false)] {
        let archive = zip_archive(&[("a.npy", &a, a_deflated), ("b.npy", &b, b_deflated)]);
        std::fs::write(&path, &archive).unwrap();
        // The first member by default; no flip, no georeference.
        let raster = read_npz(&path, &options()).unwrap();
        assert_eq!((raster.width, raster.height), (3, 2));
        assert_eq!(raster.samples, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(raster.info.format, Format::Npz);
        assert_eq!(raster.info.sample_type, "float32");
        assert!(!raster.info.georeferenced);
        assert_eq!(raster.geometry, GridGeometry::unit());
        for name in ["b", "b.npy"] {
            let options = ReadOptions { array: Some(name.into()), ..options() };
            let raster = read_npz(&path, &options).unwrap();
            assert_eq!((raster.width, raster.height), (30, 40));
            assert_eq!(raster.samples, b_values);
        }
        let options = ReadOptions { array: Some("c".into()), ..options() };
        assert_format(
            read_npz(&path, &options),
            "no array named 'c' in the archive; it holds a.npy, b.npy",
        );
    }
    // The memory budget applies to the member.
    let archive = zip_archive(&[("b.npy", &b, true)]);
    std::fs::write(&path, &archive).unwrap();
    let small = ReadOptions { max_memory: 1000, ..options() };
    let err = read_npz(&path, &small).unwrap_err();
    assert!(matches!(err, IoError::Limits { width: 30, height: 40, .. }), "{err}");
    // An archive of nothing.
    std::fs::write(&path, zip_archive(&[])).unwrap();
    assert_format(read_npz(&path, &options()), "no arrays");
}

#[test]
fn npz_member_claiming_a_huge_size_is_refused_before_decompressing() {
    let dir = TestDir::new("npz-bomb");
    let path = dir.join("arrays.npz");
    let a = npy_bytes(&dir, &[2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    for deflated in [false, true] {
        let mut archive = zip_archive(&[("a.npy", &a, deflated)]);
        // Declare 4 GB uncompressed in the local and the central header.
        patch_sizes(&mut archive, 0xffff_fff0);
        assert_format(read_bytes(read_npz, &path, &archive, &options()), "member 'a.npy'");
    }
    // A member whose array header claims more than the member holds.
    let mut lying = a.clone();
    let at = lying.windows(6).position(|w| w == b"(2, 3)").unwrap();
    lying[at..at + 6].copy_from_slice(b"(9, 9)");
    let archive = zip_archive(&[("a.npy", &lying, true)]);
    assert_format(read_bytes(read_npz, &path, &archive, &options()), "needs 324 data bytes");
}

/// Sets the uncompressed size of every member, in the local and the central headers.
fn patch_sizes(archive: &mut [u8], size: u32) {
    for at in 0..archive.len().saturating_sub(4) {
        let offset = match archive[at..at + 4] {
            [0x50, 0x4b, 0x03, 0x04] => 22,
            [0x50, 0x4b, 0x01, 0x02] => 24,
            _ => continue,
        };
        archive[at + offset..at + offset + 4].copy_from_slice(&size.to_le_bytes());
    }
}

#[test]
fn npz_truncations_are_refused_and_changed_bytes_never_change_the_array() {
    let dir = TestDir::new("npz-fuzz");
    let path = dir.join("arrays.npz");
    let a = npy_bytes(&dir, &[2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    let b = npy_bytes(&dir, &[1, 2], &[7.0, 8.0]);
    for deflated in [false, true] {
        let archive = zip_archive(&[("a.npy", &a, deflated), ("b.npy", &b, !deflated)]);
        let options = ReadOptions { array: Some("b".into()), ..options() };
        let (intact, accepted) =
            check_truncations_and_flips(read_npz, &path, &archive, &options, |_| false);
        // Many bytes go unread or unchecked (member a, local header signatures, timestamps),
        // so many changed copies read; but the CRC-32 of member b guards every byte read
        // from it, so each reads exactly as the intact archive.
        assert!(!accepted.is_empty() && accepted.len() < 5 * archive.len());
        for Accepted { at, raster } in &accepted {
            assert!(same_samples(raster, &intact), "byte {at}: {:?}", raster.samples);
        }
    }
}
