//! NumPy `.npz` archives: zip files of `.npy` members, stored or deflated.

use crate::format_error::FormatError;
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
    read_npz_from(BufReader::new(file), len, options).map_err(|e| e.at(path))
}

/// [`read_npz`] from `reader` holding the `len` bytes of an archive, before the file is named.
pub(crate) fn read_npz_from<R: Read + Seek>(
    reader: R,
    len: u64,
    options: &ReadOptions,
) -> Result<Raster, FormatError> {
    let mut archive = ZipArchive::new(reader).map_err(zip_error)?;
    let index = select_member(&archive, options.array.as_deref())?;
    let name = archive.name_for_index(index).unwrap_or_default().to_owned();
    let tag = |e: FormatError| in_member(e, &name);
    let mut member = archive.by_index(index).map_err(|e| tag(zip_error(e)))?;
    let size = checked_member_size(&member, len).map_err(tag)?;
    let array = read_npy_array_from(&mut member, size, options).map_err(tag)?;
    check_member_end(&mut member).map_err(tag)?;
    npy_raster(array, Format::Npz).map_err(tag)
}

/// The size `member` of an archive of `len` bytes declares, once checked against its
/// compressed size: [`FormatError::Unsupported`] for a member neither stored nor deflated,
/// [`FormatError::Format`] for a size its compressed bytes cannot hold.
pub(crate) fn checked_member_size<R: Read>(
    member: &ZipFile<'_, R>,
    len: u64,
) -> Result<u64, FormatError> {
    let (size, packed) = (member.size(), member.compressed_size());
    let plausible = match member.compression() {
        CompressionMethod::Stored => size == packed,
        CompressionMethod::Deflated => size <= packed.saturating_mul(MAX_INFLATION),
        other => {
            return Err(FormatError::Unsupported(format!(
                "compression method {other} (only stored and deflated members)"
            )))
        }
    };
    if !plausible || packed > len {
        return Err(FormatError::Format(format!(
            "declares {size} bytes from {packed} compressed bytes in a {len}-byte file"
        )));
    }
    Ok(size)
}

/// Checks, once its declared size has been read, that `member` holds no more; reading on to
/// the end also makes the zip reader verify the member's CRC.
pub(crate) fn check_member_end(member: &mut impl Read) -> Result<(), FormatError> {
    let mut extra = [0u8; 1];
    match member.read(&mut extra) {
        Ok(0) => Ok(()),
        Ok(_) => Err(FormatError::Format("holds more data than its declared size".into())),
        Err(e) => Err(FormatError::Io(e)),
    }
}

/// The index of the member `wanted` names (`NAME` or `NAME.npy`), or of the first file.
fn select_member<R: Read + Seek>(
    archive: &ZipArchive<R>,
    wanted: Option<&str>,
) -> Result<usize, FormatError> {
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
    Err(FormatError::Format(match wanted {
        _ if listed.is_empty() => "the archive holds no arrays".to_owned(),
        None => "the archive holds only directories".to_owned(),
        Some(w) => format!(
            "no array named '{w}' in the archive; it holds {}{}",
            listed.join(", "),
            if more > 0 { format!(" and {more} more") } else { String::new() }
        ),
    }))
}

/// A [`FormatError`] for a zip-level error.
pub(crate) fn zip_error(e: ZipError) -> FormatError {
    match e {
        ZipError::Io(e) if e.kind() == ErrorKind::UnexpectedEof => {
            FormatError::Format("truncated zip archive".into())
        }
        ZipError::Io(e) => FormatError::Io(e),
        ZipError::InvalidArchive(why) => {
            FormatError::Format(format!("not a valid .npz (zip) archive: {why}"))
        }
        ZipError::UnsupportedArchive(what) => {
            FormatError::Unsupported(format!("zip archive: {what}"))
        }
        other => FormatError::Format(other.to_string()),
    }
}

/// Names the member in `e`'s message; turns the decompressor's complaints about the data
/// (reported as I/O errors) into format errors.
pub(crate) fn in_member(e: FormatError, name: &str) -> FormatError {
    let corrupt = [ErrorKind::UnexpectedEof, ErrorKind::InvalidData, ErrorKind::InvalidInput];
    match e {
        FormatError::Io(source) if corrupt.contains(&source.kind()) => {
            FormatError::Format(format!("member '{name}': {source}"))
        }
        FormatError::Format(reason) => FormatError::Format(format!("member '{name}': {reason}")),
        FormatError::Unsupported(what) => {
            FormatError::Unsupported(format!("{what} in member '{name}'"))
        }
        FormatError::InvalidData(reason) => {
            FormatError::InvalidData(format!("member '{name}': {reason}"))
        }
        other => other,
    }
}
