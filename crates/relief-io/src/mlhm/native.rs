//! relief's own multi-layered height map file, `.mlhm`: a NumPy `.npz` (zip) archive of four
//! arrays that `numpy.load` opens as it is (see `docs/mlhm-format.md`).
//!
//! - `relief_mlhm_version`: int32, shape `(1,)`, the format version ([`MLHM_NATIVE_VERSION`]);
//! - `cell_size`: float64, shape `()`, metres;
//! - `layer_counts`: uint8, shape `(H, W)`, the columns of cell `(x, y)` at `[y, x]`, 1 to L;
//! - `columns`: float32 (or float16 for a map of [`Precision::F16`]), shape `(L, H, W, 4)`:
//!   column `k` of cell `(x, y)` at `[k, y, x]` as (bedrock top, sand, water, ceiling), the
//!   topmost column's ceiling `+inf`; the slots above a cell's layer count are zeros.

use crate::atomic_write::write_atomically;
use crate::format_error::FormatError;
use crate::input_file::open_input;
use crate::npy::header::{header_bytes, read_header, Dtype, ScalarKind};
use crate::npy::npz::{check_member_end, checked_member_size, in_member, zip_error};
use crate::sample_type::SampleType;
use crate::{IoError, ReadOptions};
use half::f16;
use relief_core::{Mlhm, MlhmColumn, Precision};
use std::io::{BufReader, Cursor, Read, Seek, Write};
use std::path::Path;
use zip::result::ZipError;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipArchive, ZipWriter};

/// The version of the `.mlhm` format this relief writes and reads, stored in the
/// `relief_mlhm_version` array. A reader refuses a larger version.
pub const MLHM_NATIVE_VERSION: i32 = 1;

/// The array holding the format version; its presence marks a relief `.mlhm` archive.
const VERSION_ARRAY: &str = "relief_mlhm_version";
/// The array of the cell size in metres.
const CELL_SIZE_ARRAY: &str = "cell_size";
/// The array of the per-cell layer counts.
const LAYER_COUNTS_ARRAY: &str = "layer_counts";
/// The array of the columns' four values.
const COLUMNS_ARRAY: &str = "columns";

/// Largest member read for a scalar array (version, cell size): a `.npy` header and a value.
const SCALAR_MEMBER_BYTES: u64 = 64 << 10;

/// Bytes per column slot of a decoded map (four f32).
const DECODED_SLOT_BYTES: u64 = 16;

/// Largest layer count an [`Mlhm`] holds.
const MAX_LAYERS: u64 = 255;

/// Column slots written per chunk.
const WRITE_CHUNK_SLOTS: usize = 1 << 12;

/// Reads the `.mlhm` file at `path` (see the module documentation and
/// `docs/mlhm-format.md`) as a multi-layered height map.
///
/// Arrays may be stored or deflated, in either byte order and in C or Fortran order; other
/// arrays in the archive are ignored. `relief_mlhm_version` may be any integer type of shape
/// `()` or `(1,)`, `cell_size` float32 or float64 of shape `()` or `(1,)`. A map whose columns
/// are float16 has [`Precision::F16`]. The slots above a cell's layer count are ignored (read
/// as zeros). Sizes are checked against the archive and `options.max_memory` before anything
/// is allocated.
///
/// Errors: [`IoError::Io`] when the file cannot be read; [`IoError::Format`] for a corrupt or
/// truncated archive or member, a missing array or a shape that disagrees with the others or
/// with its data; [`IoError::Unsupported`] for a newer format version, another dtype, an
/// encrypted member or another compression method; [`IoError::Limits`] for a map over the
/// memory budget; [`IoError::InvalidData`] for a cell size that is not a finite number > 0,
/// and, naming the cell and the column, for a layer count outside `1..=L`, a NaN or any
/// other broken invariant of [`Mlhm::validate`].
pub fn read_mlhm_native(path: &Path, options: &ReadOptions) -> Result<Mlhm, IoError> {
    let (file, len) = open_input(path)?;
    read_from(BufReader::new(file), len, options).map_err(|e| e.at(path))
}

/// [`read_mlhm_native`] of the archive held in `bytes`; `path` names it in errors. Used by
/// tests and fuzzing.
pub fn read_mlhm_native_from_bytes(
    bytes: &[u8],
    path: &Path,
    options: &ReadOptions,
) -> Result<Mlhm, IoError> {
    read_from(Cursor::new(bytes), bytes.len() as u64, options).map_err(|e| e.at(path))
}

/// Writes `map` as a `.mlhm` file at `path`, atomically: columns in float16 when the map is
/// [`Precision::F16`], else float32; the slots above each cell's layer count as zeros; every
/// member deflated at the fastest level, with a fixed timestamp (the same map gives the same
/// bytes).
///
/// Errors: [`IoError::Io`] when the file cannot be written.
pub fn write_mlhm_native(path: &Path, map: &Mlhm) -> Result<(), IoError> {
    use ScalarKind::Sample;
    const I32: Dtype = Dtype::little_endian(Sample(SampleType::I32));
    const F64: Dtype = Dtype::little_endian(Sample(SampleType::F64));
    const U8: Dtype = Dtype::little_endian(Sample(SampleType::U8));
    let (width, height, layers) = (map.width(), map.height(), map.max_layers());
    let half = map.precision() == Precision::F16;
    let columns =
        Dtype::little_endian(if half { ScalarKind::F16 } else { Sample(SampleType::F32) });
    write_atomically(path, |out| {
        let mut zip = ZipWriter::new(out);
        let version = MLHM_NATIVE_VERSION.to_le_bytes();
        add_array(&mut zip, path, VERSION_ARRAY, I32, &[1], &mut |w| w.write_all(&version))?;
        let cell_size = map.cell_size().to_le_bytes();
        add_array(&mut zip, path, CELL_SIZE_ARRAY, F64, &[], &mut |w| w.write_all(&cell_size))?;
        let counts = map.layer_counts();
        add_array(&mut zip, path, LAYER_COUNTS_ARRAY, U8, &[height, width], &mut |w| {
            w.write_all(counts)
        })?;
        let shape = [layers, height, width, 4];
        add_array(&mut zip, path, COLUMNS_ARRAY, columns, &shape, &mut |w| {
            write_columns(w, map, half)
        })?;
        zip.finish().map_err(|e| IoError::io(path, std::io::Error::other(e)))?;
        Ok(())
    })
}

/// Adds the array `name` (`name.npy`) of `dtype` and `shape` to `zip`; `write_data` writes
/// its C-order data in `dtype`'s byte order.
fn add_array<W: Write + Seek>(
    zip: &mut ZipWriter<W>,
    path: &Path,
    name: &str,
    dtype: Dtype,
    shape: &[usize],
    write_data: &mut dyn FnMut(&mut ZipWriter<W>) -> std::io::Result<()>,
) -> Result<(), IoError> {
    let header = header_bytes(dtype, shape).ok_or_else(|| {
        IoError::invalid_data(path, format!("shape {shape:?} is too long for a .npy header"))
    })?;
    let elements = shape.iter().fold(1u64, |n, &d| n.saturating_mul(d as u64));
    let data_bytes = elements.saturating_mul(dtype.size() as u64);
    let bytes = (header.len() as u64).saturating_add(data_bytes);
    // Members of 4 GiB and more need zip64 records, which numpy reads too.
    let options = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .compression_level(Some(1))
        .large_file(bytes >= u64::from(u32::MAX) / 2);
    let zip_io = |e: ZipError| IoError::io(path, std::io::Error::other(e));
    zip.start_file(format!("{name}.npy"), options).map_err(zip_io)?;
    zip.write_all(&header).map_err(|e| IoError::io(path, e))?;
    write_data(zip).map_err(|e| IoError::io(path, e))
}

/// Writes the column slots of `map` to `w` as float16 (`half`) or float32, little-endian,
/// zeros above each cell's layer count.
fn write_columns(w: &mut impl Write, map: &Mlhm, half: bool) -> std::io::Result<()> {
    let counts = map.layer_counts();
    let cells = counts.len();
    let item = if half { 2 } else { 4 };
    let mut bytes = Vec::with_capacity(WRITE_CHUNK_SLOTS * 4 * item);
    for (chunk_index, chunk) in map.raw_columns().chunks(WRITE_CHUNK_SLOTS).enumerate() {
        bytes.clear();
        for (offset, column) in chunk.iter().enumerate() {
            let slot = chunk_index * WRITE_CHUNK_SLOTS + offset;
            let used = slot / cells < usize::from(counts[slot % cells]);
            let values = if used { column.to_array() } else { [0.0; 4] };
            for v in values {
                if half {
                    bytes.extend_from_slice(&f16::from_f32(v).to_le_bytes());
                } else {
                    bytes.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
        w.write_all(&bytes)?;
    }
    Ok(())
}

/// Reads the archive of `len` bytes from `reader`.
fn read_from<R: Read + Seek>(
    reader: R,
    len: u64,
    options: &ReadOptions,
) -> Result<Mlhm, FormatError> {
    let zip = ZipArchive::new(reader).map_err(zip_error)?;
    let mut archive = Archive { zip, len };

    let version = archive.read_array(VERSION_ARRAY, |head| {
        check_scalar(head, "an integer", ScalarKind::is_integer)?;
        Ok(SCALAR_MEMBER_BYTES)
    })?;
    let version = version.value(0);
    if version != f64::from(MLHM_NATIVE_VERSION) {
        return Err(FormatError::Unsupported(format!(
            ".mlhm format version {version} (this relief reads version {MLHM_NATIVE_VERSION})"
        )));
    }

    let cell_size = archive.read_array(CELL_SIZE_ARRAY, |head| {
        check_scalar(head, "float64 or float32", ScalarKind::is_float)?;
        Ok(SCALAR_MEMBER_BYTES)
    })?;
    let cell_size = cell_size.value(0);
    if !(cell_size.is_finite() && cell_size > 0.0) {
        return Err(FormatError::InvalidData(format!(
            "cell_size is {cell_size}, not a finite number of metres > 0"
        )));
    }

    let counts = archive.read_array(LAYER_COUNTS_ARRAY, |head| {
        check_dtype(head, "uint8", |kind| kind == ScalarKind::Sample(SampleType::U8))?;
        let &[height, width] = &head.shape[..] else {
            return Err(wrong_shape(head, "2 dimensions (H, W)"));
        };
        check_not_empty(head)?;
        budget(width, height, width.saturating_mul(height), options)
    })?;
    let (height, width) = (counts.shape[0], counts.shape[1]);

    let columns = archive.read_array(COLUMNS_ARRAY, |head| {
        check_dtype(head, "float32 or float16", |kind| {
            kind == ScalarKind::Sample(SampleType::F32) || kind == ScalarKind::F16
        })?;
        let &[layers, h, w, 4] = &head.shape[..] else {
            return Err(wrong_shape(head, "4 dimensions (L, H, W, 4)"));
        };
        check_not_empty(head)?;
        if (h, w) != (height, width) {
            let expected =
                format!("(L, {height}, {width}, 4) as layer_counts is ({height}, {width})");
            return Err(wrong_shape(head, &expected));
        }
        if layers > MAX_LAYERS {
            return Err(FormatError::Unsupported(format!(
                "{layers} layers in '{COLUMNS_ARRAY}' (at most {MAX_LAYERS})"
            )));
        }
        let slots = layers.saturating_mul(width).saturating_mul(height);
        let raw = slots.saturating_mul(4 * head.dtype.size() as u64);
        let needed = raw
            .saturating_add(slots.saturating_mul(DECODED_SLOT_BYTES))
            .saturating_add(counts.len());
        budget(width, height, needed, options)
    })?;
    let layers = columns.shape[0];
    let half = columns.dtype.kind == ScalarKind::F16;
    let precision = if half { Precision::F16 } else { Precision::F32 };

    // Bounded by the budgets checked above.
    let (width, height, layers) = (width as usize, height as usize, layers as usize);
    let cells = width * height;
    let layer_counts: Vec<u8> = (0..cells).map(|i| counts.value(i) as u8).collect();
    drop(counts);
    let slots = decode_columns(&columns, &layer_counts, layers);
    drop(columns);
    let invalid = |e: relief_core::CoreError| FormatError::InvalidData(e.to_string());
    let map =
        Mlhm::from_parts(width, height, layers, cell_size, layer_counts, slots).map_err(invalid)?;
    match precision {
        Precision::F32 => Ok(map),
        // Exact f16 values of a valid map: the rounding changes nothing but the precision.
        Precision::F16 => map.to_precision(Precision::F16).map_err(invalid),
    }
}

/// The column slots of the array `columns` (shape `(L, H, W, 4)`, float32 or float16) for
/// these layer counts: zeros above each cell's count, whatever the file holds there.
fn decode_columns(columns: &Array, layer_counts: &[u8], layers: usize) -> Vec<MlhmColumn> {
    let cells = layer_counts.len();
    let mut slots = Vec::with_capacity(cells * layers);
    for slot in 0..cells * layers {
        let used = slot / cells < usize::from(layer_counts[slot % cells]);
        let column = if used {
            // float32 and float16 values are exact as f64 and back.
            MlhmColumn::from_array(std::array::from_fn(|v| columns.value(slot * 4 + v) as f32))
        } else {
            MlhmColumn::default()
        };
        slots.push(column);
    }
    slots
}

/// An open archive: its reader and its length in bytes.
struct Archive<R> {
    zip: ZipArchive<R>,
    len: u64,
}

/// What a member's `.npy` header declares.
struct ArrayHead {
    /// The member's name in the archive.
    name: String,
    /// The element type and byte order.
    dtype: Dtype,
    /// Whether the data is in Fortran (column-major) order.
    fortran_order: bool,
    /// The dimensions, slowest first (C order).
    shape: Vec<u64>,
}

/// A member array with its data bytes.
struct Array {
    dtype: Dtype,
    /// The dimensions; their product is the element count, which fits in memory.
    shape: Vec<u64>,
    /// For Fortran-ordered data, each dimension's stride in elements; empty for C order.
    fortran_strides: Vec<usize>,
    data: Vec<u8>,
}

impl Array {
    /// Number of elements.
    fn len(&self) -> u64 {
        self.shape.iter().product()
    }

    /// Element `index` in C (row-major) order, as f64 (exact for every float and for integers
    /// up to 2^53).
    fn value(&self, index: usize) -> f64 {
        let size = self.dtype.size();
        let at = self.storage_index(index) * size;
        let bytes = &self.data[at..at + size];
        let big_endian = self.dtype.big_endian;
        macro_rules! decode {
            ($t:ty) => {{
                let raw = bytes.try_into().expect("element size");
                if big_endian {
                    <$t>::from_be_bytes(raw)
                } else {
                    <$t>::from_le_bytes(raw)
                }
            }};
        }
        match self.dtype.kind {
            ScalarKind::F16 => f64::from(f16::from_bits(decode!(u16)).to_f32()),
            ScalarKind::Sample(sample) => match sample {
                SampleType::I8 => decode!(i8) as f64,
                SampleType::U8 => decode!(u8) as f64,
                SampleType::I16 => decode!(i16) as f64,
                SampleType::U16 => decode!(u16) as f64,
                SampleType::I32 => decode!(i32) as f64,
                SampleType::U32 => decode!(u32) as f64,
                SampleType::I64 => decode!(i64) as f64,
                SampleType::U64 => decode!(u64) as f64,
                SampleType::F32 => decode!(f32) as f64,
                SampleType::F64 => decode!(f64),
            },
        }
    }

    /// Where element `index` (C order) is stored.
    fn storage_index(&self, index: usize) -> usize {
        if self.fortran_strides.is_empty() {
            return index;
        }
        let mut rest = index;
        let mut at = 0;
        for (&dim, &stride) in self.shape.iter().zip(&self.fortran_strides).rev() {
            let dim = dim as usize;
            at += (rest % dim) * stride;
            rest /= dim;
        }
        at
    }
}

impl<R: Read + Seek> Archive<R> {
    /// Reads the array `name` (the member `name.npy`, or `name`). Once its header is known to
    /// agree with the member's size, `check` sees the header and refuses a wrong type or shape,
    /// or returns the bytes reading it may take, which the data must not exceed. Every error
    /// names the member.
    fn read_array(
        &mut self,
        name: &str,
        check: impl FnOnce(&ArrayHead) -> Result<u64, FormatError>,
    ) -> Result<Array, FormatError> {
        let member_name = format!("{name}.npy");
        let Some(index) =
            self.zip.index_for_name(&member_name).or_else(|| self.zip.index_for_name(name))
        else {
            return Err(self.missing(name));
        };
        let tag = |e: FormatError| in_member(e, &member_name);
        let mut member = self.zip.by_index(index).map_err(|e| tag(zip_error(e)))?;
        let size = checked_member_size(&member, self.len).map_err(tag)?;
        let header = read_header(&mut member, size).map_err(tag)?;
        let head = ArrayHead {
            name: member_name.clone(),
            dtype: header.dtype,
            fortran_order: header.fortran_order,
            shape: header.shape,
        };
        let elements = head.shape.iter().try_fold(1u64, |n, &d| n.checked_mul(d));
        let data_len = elements.and_then(|n| n.checked_mul(head.dtype.size() as u64));
        let available = size.saturating_sub(header.data_offset);
        if data_len != Some(available) {
            return Err(tag(FormatError::Format(format!(
                "shape {:?} of {} needs {} data bytes, the member holds {available}",
                head.shape,
                head.dtype.kind.name(),
                data_len.map_or("more than 2^64".into(), |n| n.to_string())
            ))));
        }
        let allowed = check(&head).map_err(tag)?;
        if available > allowed || usize::try_from(available).is_err() {
            return Err(tag(FormatError::Format(format!(
                "{available} data bytes where at most {allowed} are expected"
            ))));
        }
        // Bounded by the budget `check` gave.
        let mut data = vec![0u8; available as usize];
        member.read_exact(&mut data).map_err(|e| tag(FormatError::Io(e)))?;
        check_member_end(&mut member).map_err(tag)?;
        let fortran_strides = if head.fortran_order && head.shape.len() > 1 {
            // Elements fit in memory, so these products do not overflow.
            let mut stride = 1;
            head.shape
                .iter()
                .map(|&d| {
                    let s = stride;
                    stride *= d as usize;
                    s
                })
                .collect()
        } else {
            Vec::new()
        };
        Ok(Array { dtype: head.dtype, shape: head.shape, fortran_strides, data })
    }

    /// The error for the missing array `name`.
    fn missing(&self, name: &str) -> FormatError {
        let reason = if name == VERSION_ARRAY {
            format!("not a relief .mlhm archive: it holds no '{VERSION_ARRAY}' array")
        } else {
            format!(
                "no array '{name}' in the archive; a .mlhm holds {VERSION_ARRAY}, \
                 {CELL_SIZE_ARRAY}, {LAYER_COUNTS_ARRAY} and {COLUMNS_ARRAY}"
            )
        };
        FormatError::Format(reason)
    }
}

/// Refuses a member whose element type `accept` refuses, naming the type `expected`.
fn check_dtype(
    head: &ArrayHead,
    expected: &str,
    accept: impl Fn(ScalarKind) -> bool,
) -> Result<(), FormatError> {
    if accept(head.dtype.kind) {
        return Ok(());
    }
    Err(FormatError::Unsupported(format!(
        "dtype {} for '{}' (expected {expected})",
        head.dtype.kind.name(),
        head.name
    )))
}

/// Refuses a scalar member (shape `()` or `(1,)`) of the wrong type or shape.
fn check_scalar(
    head: &ArrayHead,
    expected: &str,
    accept: impl Fn(ScalarKind) -> bool,
) -> Result<(), FormatError> {
    check_dtype(head, expected, accept)?;
    match head.shape[..] {
        [] | [1] => Ok(()),
        _ => Err(wrong_shape(head, "one value, shape () or (1,)")),
    }
}

/// Refuses an array with a dimension of 0.
fn check_not_empty(head: &ArrayHead) -> Result<(), FormatError> {
    if head.shape.contains(&0) {
        return Err(wrong_shape(head, "no dimension of 0"));
    }
    Ok(())
}

/// The error for a member whose shape is not `expected`.
fn wrong_shape(head: &ArrayHead, expected: &str) -> FormatError {
    FormatError::Format(format!("'{}' has shape {:?}, expected {expected}", head.name, head.shape))
}

/// Refuses `needed` bytes for a `width x height` map over the memory budget; else returns
/// them as the bytes a member may take.
fn budget(width: u64, height: u64, needed: u64, options: &ReadOptions) -> Result<u64, FormatError> {
    if needed > options.max_memory || usize::try_from(needed).is_err() {
        return Err(FormatError::Limits { width, height, needed, limit: options.max_memory });
    }
    Ok(needed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_corruption::corrupted_copies;
    use crate::test_dir::TestDir;

    const INF: f32 = f32::INFINITY;

    fn small_map() -> Mlhm {
        let mut map = Mlhm::new(3, 2, 3, 0.5).unwrap();
        map.set_cell(
            1,
            1,
            &[MlhmColumn::new(1.0, 0.5, 0.25, 2.0), MlhmColumn::new(3.0, 0.0, 0.0, INF)],
        )
        .unwrap();
        map.set_cell(2, 0, &[MlhmColumn::new(-1.5, 0.125, 2.0, INF)]).unwrap();
        map
    }

    #[test]
    fn corrupted_files_are_refused_or_read_as_the_map_written() {
        let dir = TestDir::new("mlhm-native");
        let path = dir.path().join("small.mlhm");
        write_mlhm_native(&path, &small_map()).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let options = ReadOptions::default();
        assert_eq!(read_mlhm_native_from_bytes(&bytes, &path, &options).unwrap(), small_map());
        // Every member carries a CRC-32 that the reader checks: a copy reads only where the
        // changes hit what no checksum covers and nothing reads (timestamps, unused header
        // fields), and then it is the map that was written.
        let mut refused = 0;
        for bad in corrupted_copies(&bytes, 500, 3) {
            match read_mlhm_native_from_bytes(&bad, &path, &options) {
                Err(_) => refused += 1,
                Ok(map) => assert_eq!(map, small_map(), "a corrupted file read as another map"),
            }
        }
        assert!(refused >= 450, "only {refused} of 500 corrupted files refused");
        for cut in 0..bytes.len() {
            assert!(read_mlhm_native_from_bytes(&bytes[..cut], &path, &options).is_err());
        }
    }
}
