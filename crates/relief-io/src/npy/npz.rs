//! NumPy `.npz` archives: zip files of `.npy` members, stored or deflated.

use crate::input_file::open_input;
use crate::npy::raster::npy_raster;
use crate::npy::read::read_npy_array_from;
use crate::raster::{Format, Raster, ReadOptions};
use crate::IoError;
use std::io::{BufReader, ErrorKind, Read, Seek};
use std::path::Path;
use zip::read::ZipFile;
use zip::result::ZipError;
use zip::{CompressionMethod, ZipArchive};

/// The largest inflation deflate allows (about 1032:1).
const MAX_INFLATION: u64 = 1032;

/// Names listed at most in the message for an unknown array name.
const LISTED_NAMES: usize = 20;

/// Reads one 2D array of the `.npz` archive at `path` as a raster.
///
/// `options.array` names the member, as `NAME` or `NAME.npy` (the names `numpy.savez` gives
/// its keyword arguments); without it the first member in archive order is read. The member
/// is decoded as by [`read_npy`](crate::npy::read_npy): no georeference, array row `r` is grid
/// row `r`, NaN and infinities refused. Members may be stored or deflated; they are
/// decompressed as a stream, and never past their declared size, whose consistency with the
/// member's compressed size and its `.npy` header is checked before anything is allocated.
///
/// Errors: [`IoError::Io`] when the file cannot be read (or is a directory),
/// [`IoError::Format`] for a malformed or truncated archive or member, an unknown array name
/// (listing the names there are) or an empty archive, [`IoError::Unsupported`] for encrypted
/// members, other compression methods, dtypes or numbers of dimensions, [`IoError::Limits`]
/// for an array over the memory budget, [`IoError::InvalidData`] for a non-finite sample.
pub fn read_npz(path: &Path, options: &ReadOptions) -> Result<Raster, IoError> {
    let (file, len) = open_input(path)?;
    read_npz_from(BufReader::new(file), len, path, options)
}

/// [`read_npz`] from `reader` holding the `len` bytes of an archive; `path` names the file in
/// errors.
pub(crate) fn read_npz_from<R: Read + Seek>(
    reader: R,
    len: u64,
    path: &Path,
    options: &ReadOptions,
) -> Result<Raster, IoError> {
    let mut archive = ZipArchive::new(reader).map_err(|e| zip_error(path, e))?;
    let index = select_member(&archive, path, options.array.as_deref())?;
    let name = archive.name_for_index(index).unwrap_or_default().to_owned();
    let tag = |e: IoError| in_member(e, &name);
    let mut member = archive.by_index(index).map_err(|e| tag(zip_error(path, e)))?;
    let size = checked_member_size(&member, path, len).map_err(tag)?;
    let array = read_npy_array_from(&mut member, size, options).map_err(|e| tag(e.at(path)))?;
    check_member_end(&mut member, path).map_err(tag)?;
    npy_raster(array, Format::Npz).map_err(|e| tag(e.at(path)))
}

/// The size `member` of an archive of `len` bytes declares, once checked against its
/// compressed size: [`IoError::Unsupported`] for a member neither stored nor deflated,
/// [`IoError::Format`] for a size its compressed bytes cannot hold.
pub(crate) fn checked_member_size<R: Read>(
    member: &ZipFile<'_, R>,
    path: &Path,
    len: u64,
) -> Result<u64, IoError> {
    let (size, packed) = (member.size(), member.compressed_size());
    let plausible = match member.compression() {
        CompressionMethod::Stored => size == packed,
        CompressionMethod::Deflated => size <= packed.saturating_mul(MAX_INFLATION),
        other => {
            return Err(IoError::unsupported(
                path,
                format!("compression method {other} (only stored and deflated members)"),
            ))
        }
    };
    if !plausible || packed > len {
        return Err(IoError::format(
            path,
            format!("declares {size} bytes from {packed} compressed bytes in a {len}-byte file"),
        ));
    }
    Ok(size)
}

/// Checks, once its declared size has been read, that `member` holds no more; reading on to
/// the end also makes the zip reader verify the member's CRC.
pub(crate) fn check_member_end(member: &mut impl Read, path: &Path) -> Result<(), IoError> {
    let mut extra = [0u8; 1];
    match member.read(&mut extra) {
        Ok(0) => Ok(()),
        Ok(_) => Err(IoError::format(path, "holds more data than its declared size")),
        Err(e) => Err(IoError::io(path, e)),
    }
}

/// The index of the member `wanted` names (`NAME` or `NAME.npy`), or of the first file.
fn select_member<R: Read + Seek>(
    archive: &ZipArchive<R>,
    path: &Path,
    wanted: Option<&str>,
) -> Result<usize, IoError> {
    let names = || (0..archive.len()).filter_map(|i| Some((i, archive.name_for_index(i)?)));
    let found = match wanted {
        None => names().find(|(_, n)| !n.ends_with('/')),
        Some(w) => names()
            .find(|&(_, n)| n == w)
            .or_else(|| names().find(|&(_, n)| n.strip_suffix(".npy") == Some(w))),
    };
    if let Some((index, _)) = found {
        return Ok(index);
    }
    let listed: Vec<&str> = names().map(|(_, n)| n).take(LISTED_NAMES).collect();
    let more = archive.len().saturating_sub(LISTED_NAMES);
    Err(IoError::format(
        path,
        match wanted {
            _ if listed.is_empty() => "the archive holds no arrays".to_owned(),
            None => "the archive holds only directories".to_owned(),
            Some(w) => format!(
                "no array named '{w}' in the archive; it holds {}{}",
                listed.join(", "),
                if more > 0 { format!(" and {more} more") } else { String::new() }
            ),
        },
    ))
}

/// An [`IoError`] for a zip-level error.
pub(crate) fn zip_error(path: &Path, e: ZipError) -> IoError {
    match e {
        ZipError::Io(e) if e.kind() == ErrorKind::UnexpectedEof => {
            IoError::format(path, "truncated zip archive")
        }
        ZipError::Io(e) => IoError::io(path, e),
        ZipError::InvalidArchive(why) => {
            IoError::format(path, format!("not a valid .npz (zip) archive: {why}"))
        }
        ZipError::UnsupportedArchive(what) => {
            IoError::unsupported(path, format!("zip archive: {what}"))
        }
        other => IoError::format(path, other.to_string()),
    }
}

/// Names the member in `e`'s message; turns the decompressor's complaints about the data
/// (reported as I/O errors) into format errors.
pub(crate) fn in_member(e: IoError, name: &str) -> IoError {
    let corrupt = [ErrorKind::UnexpectedEof, ErrorKind::InvalidData, ErrorKind::InvalidInput];
    match e {
        IoError::Io { path, source } if corrupt.contains(&source.kind()) => {
            IoError::Format { path, reason: format!("member '{name}': {source}") }
        }
        IoError::Format { path, reason } => {
            IoError::Format { path, reason: format!("member '{name}': {reason}") }
        }
        IoError::Unsupported { path, what } => {
            IoError::Unsupported { path, what: format!("{what} in member '{name}'") }
        }
        IoError::InvalidData { path, reason } => {
            IoError::InvalidData { path, reason: format!("member '{name}': {reason}") }
        }
        other => other,
    }
}
