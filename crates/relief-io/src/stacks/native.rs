//! relief's own material-stacks file, `.stacks`: a little-endian binary of the grid, the
//! palette and the compressed-row layers of a [`MaterialStacks`] (see `docs/stacks.md`).
//!
//! | field | type |
//! |---|---|
//! | magic | `b"RELIEFSTK\0"` (10 bytes) |
//! | version | u16, [`STACKS_VERSION`] |
//! | width, height | u32, u32 |
//! | spacing x, spacing y, origin x, origin y | f64 each |
//! | material count `M` | u16 |
//! | `M` materials | u8 kind (0 solid, 1 liquid), u8 r, g, b, u16 name length, name (UTF-8) |
//! | layer count `L` | u64 |
//! | offsets | `width * height + 1` u32 |
//! | `L` layers | f32 start, f32 end, u8 material |

use crate::atomic_write::write_atomically;
use crate::format_error::FormatError;
use crate::input_file::open_input;
use crate::IoError;
use relief_core::{DVec2, MaterialKind, MaterialStacks, StackLayer, StackMaterial};
use std::io::{Read, Write};
use std::path::Path;

/// The first ten bytes of every `.stacks` file.
pub const STACKS_MAGIC: &[u8; 10] = b"RELIEFSTK\0";

/// The version of the `.stacks` format this relief writes and reads. A reader refuses any
/// other.
pub const STACKS_VERSION: u16 = 1;

/// The file extension of relief's stacks files, without the dot.
pub const STACKS_EXTENSION: &str = "stacks";

/// Bytes of the fixed header: magic, version, width, height, spacing, origin, material count.
const HEADER_BYTES: usize = 10 + 2 + 4 + 4 + 4 * 8 + 2;

/// Bytes of one stored layer: f32 start, f32 end, u8 material.
const LAYER_BYTES: u64 = 9;

/// Whether `path` names a `.stacks` file, by its extension (any case).
pub fn is_stacks_path(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case(STACKS_EXTENSION))
}

/// Whether `bytes` begin with the `.stacks` magic ([`STACKS_MAGIC`]).
pub fn has_stacks_magic(bytes: &[u8]) -> bool {
    bytes.starts_with(STACKS_MAGIC)
}

/// Reads the `.stacks` file at `path` (see the module documentation and `docs/stacks.md`).
///
/// Errors: [`IoError::Io`] when the file cannot be read; [`IoError::Format`] for a wrong
/// magic, a truncated file, sizes in the header that disagree with the file's length (checked
/// before anything is allocated), trailing bytes, a material name that is not UTF-8 or an
/// unknown material kind; [`IoError::Unsupported`] for another format version;
/// [`IoError::InvalidData`], naming the stack and the layer, for stacks that break an
/// invariant of [`MaterialStacks::validate`] (and for an empty grid, a spacing that is not
/// finite and positive, an empty palette or one of more than 256 materials).
pub fn read_stacks(path: &Path) -> Result<MaterialStacks, IoError> {
    let (file, len) = open_input(path)?;
    read_stacks_from(file, len).map_err(|e| e.at(path))
}

/// [`read_stacks`] from `file` holding the `len` bytes of a `.stacks` file, before the file
/// is named.
fn read_stacks_from(file: impl Read, len: u64) -> Result<MaterialStacks, FormatError> {
    let len = usize::try_from(len)
        .map_err(|_| FormatError::Format(format!("{len} bytes do not fit in memory")))?;
    let mut bytes = Vec::with_capacity(len);
    file.take(len as u64).read_to_end(&mut bytes).map_err(FormatError::Io)?;
    decode_stacks(&bytes)
}

/// Writes `stacks` as a `.stacks` file at `path`, atomically: into a temporary file beside it,
/// renamed into place only once complete.
///
/// Errors: [`IoError::Io`] when the file cannot be written; [`IoError::InvalidData`] when the
/// stacks do not fit the format (a dimension over `u32::MAX`, a material name over 65535
/// bytes), in which case no file is written.
pub fn write_stacks(path: &Path, stacks: &MaterialStacks) -> Result<(), IoError> {
    let bytes = stacks_to_bytes(stacks, path)?;
    write_atomically(path, |out| out.write_all(&bytes).map_err(|e| IoError::io(path, e)))
}

/// The bytes of `stacks` as a `.stacks` file; `path` names it in errors.
///
/// Errors: [`IoError::InvalidData`] as for [`write_stacks`].
pub fn stacks_to_bytes(stacks: &MaterialStacks, path: &Path) -> Result<Vec<u8>, IoError> {
    let too_big = |what: &str| IoError::invalid_data(path, format!("{what} exceeds the format"));
    let width = u32::try_from(stacks.width()).map_err(|_| too_big("the width"))?;
    let height = u32::try_from(stacks.height()).map_err(|_| too_big("the height"))?;
    let materials = stacks.materials();
    let count = u16::try_from(materials.len()).map_err(|_| too_big("the material count"))?;
    let names: usize = materials.iter().map(|m| 6 + m.name.len()).sum();
    let size = HEADER_BYTES
        + names
        + 8
        + stacks.offsets().len() * 4
        + stacks.layers().len() * LAYER_BYTES as usize;
    let mut out = Vec::with_capacity(size);
    out.extend_from_slice(STACKS_MAGIC);
    out.extend_from_slice(&STACKS_VERSION.to_le_bytes());
    out.extend_from_slice(&width.to_le_bytes());
    out.extend_from_slice(&height.to_le_bytes());
    for v in [stacks.spacing().x, stacks.spacing().y, stacks.origin().x, stacks.origin().y] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&count.to_le_bytes());
    for material in materials {
        let name = material.name.as_bytes();
        let name_len = u16::try_from(name.len()).map_err(|_| {
            IoError::invalid_data(
                path,
                format!("material {:?}: a name over 65535 bytes exceeds the format", material.name),
            )
        })?;
        let kind = match material.kind {
            MaterialKind::Solid => 0u8,
            MaterialKind::Liquid => 1u8,
        };
        out.push(kind);
        out.extend_from_slice(&material.color);
        out.extend_from_slice(&name_len.to_le_bytes());
        out.extend_from_slice(name);
    }
    out.extend_from_slice(&(stacks.layers().len() as u64).to_le_bytes());
    for offset in stacks.offsets() {
        out.extend_from_slice(&offset.to_le_bytes());
    }
    for layer in stacks.layers() {
        out.extend_from_slice(&layer.start.to_le_bytes());
        out.extend_from_slice(&layer.end.to_le_bytes());
        out.push(layer.material);
    }
    debug_assert_eq!(out.len(), size);
    Ok(out)
}

/// Reads the `.stacks` file held in `bytes` as [`read_stacks`] does; `path` names it in
/// errors. Used by tests and fuzzing.
pub fn stacks_from_bytes(bytes: &[u8], path: &Path) -> Result<MaterialStacks, IoError> {
    decode_stacks(bytes).map_err(|e| e.at(path))
}

/// The stacks of the `.stacks` file held in `bytes`, before the file is named.
fn decode_stacks(bytes: &[u8]) -> Result<MaterialStacks, FormatError> {
    let mut r = ByteReader { bytes, at: 0 };
    if !has_stacks_magic(bytes) {
        return Err(FormatError::Format("not a relief .stacks file (wrong magic)".into()));
    }
    r.take(STACKS_MAGIC.len(), "the magic")?;
    let version = r.u16("the version")?;
    if version != STACKS_VERSION {
        return Err(FormatError::Unsupported(format!(
            ".stacks format version {version} (this relief reads version {STACKS_VERSION})"
        )));
    }
    let width = r.u32("the width")?;
    let height = r.u32("the height")?;
    let spacing = DVec2::new(r.f64("the spacing")?, r.f64("the spacing")?);
    let origin = DVec2::new(r.f64("the origin")?, r.f64("the origin")?);
    let count = r.u16("the material count")?;
    let mut materials = Vec::new();
    for index in 0..count {
        let kind = match r.u8("a material's kind")? {
            0 => MaterialKind::Solid,
            1 => MaterialKind::Liquid,
            other => {
                return Err(FormatError::Format(format!(
                    "material {index}: kind {other}, expected 0 (solid) or 1 (liquid)"
                )))
            }
        };
        let color = r.take(3, "a material's colour")?;
        let color = [color[0], color[1], color[2]];
        let name_len = r.u16("a material's name length")?;
        let name = r.take(usize::from(name_len), "a material's name")?;
        let name = std::str::from_utf8(name).map_err(|e| {
            FormatError::Format(format!("material {index}: the name is not UTF-8 ({e})"))
        })?;
        materials.push(StackMaterial::new(name, color, kind));
    }
    let layer_count = r.u64("the layer count")?;

    // Every size checked against the bytes left before anything is allocated.
    let stacks = u64::from(width) * u64::from(height);
    let needed = (stacks + 1)
        .checked_mul(4)
        .and_then(|offsets| layer_count.checked_mul(LAYER_BYTES)?.checked_add(offsets));
    let left = (bytes.len() - r.at) as u64;
    match needed {
        Some(needed) if needed == left => {}
        Some(needed) if needed < left => {
            return Err(FormatError::Format(format!(
                "{} bytes after the layers of the {width}x{height} stacks",
                left - needed
            )))
        }
        _ => {
            return Err(FormatError::Format(format!(
                "{width}x{height} stacks of {layer_count} layers need more than the {left} \
                     bytes left (truncated, or a corrupt header)"
            )))
        }
    }
    // Both fit in the bytes held, so in usize.
    let offsets: Vec<u32> = r
        .take((stacks as usize + 1) * 4, "the offsets")?
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let layers: Vec<StackLayer> = r
        .take(layer_count as usize * LAYER_BYTES as usize, "the layers")?
        .chunks_exact(LAYER_BYTES as usize)
        .map(|b| {
            let start = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            let end = f32::from_le_bytes([b[4], b[5], b[6], b[7]]);
            StackLayer::new(start, end, b[8])
        })
        .collect();
    MaterialStacks::from_parts(
        width as usize,
        height as usize,
        spacing,
        origin,
        materials,
        offsets,
        layers,
    )
    .map_err(|e| FormatError::InvalidData(e.to_string()))
}

/// A little-endian reader over a byte slice whose every read checks the bytes left.
struct ByteReader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> ByteReader<'a> {
    /// The next `n` bytes, or a truncation error naming `what` was being read.
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], FormatError> {
        let end =
            self.at.checked_add(n).filter(|&end| end <= self.bytes.len()).ok_or_else(|| {
                FormatError::Format(format!(
                    "truncated in {what} ({n} bytes at offset {} of {})",
                    self.at,
                    self.bytes.len()
                ))
            })?;
        let taken = &self.bytes[self.at..end];
        self.at = end;
        Ok(taken)
    }

    /// The next `N` bytes as an array.
    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], FormatError> {
        let mut array = [0u8; N];
        array.copy_from_slice(self.take(N, what)?);
        Ok(array)
    }

    fn u8(&mut self, what: &str) -> Result<u8, FormatError> {
        Ok(self.array::<1>(what)?[0])
    }

    fn u16(&mut self, what: &str) -> Result<u16, FormatError> {
        Ok(u16::from_le_bytes(self.array(what)?))
    }

    fn u32(&mut self, what: &str) -> Result<u32, FormatError> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    fn u64(&mut self, what: &str) -> Result<u64, FormatError> {
        Ok(u64::from_le_bytes(self.array(what)?))
    }

    fn f64(&mut self, what: &str) -> Result<f64, FormatError> {
        Ok(f64::from_le_bytes(self.array(what)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_corruption::corrupted_copies;
    use crate::test_dir::TestDir;
    use proptest::prelude::*;

    fn name() -> &'static Path {
        Path::new("test.stacks")
    }

    /// Two stacks: plain ground, and ground under a water layer and a rock arch.
    fn small() -> MaterialStacks {
        MaterialStacks::from_stacks(
            2,
            1,
            DVec2::new(1.5, 2.0),
            DVec2::new(-3.0, 4.0),
            StackMaterial::defaults(),
            &[
                vec![StackLayer::new(0.0, 2.0, 0)],
                vec![
                    StackLayer::new(0.0, 1.0, 0),
                    StackLayer::new(1.0, 1.5, 2),
                    StackLayer::new(5.0, 6.0, 1),
                ],
            ],
        )
        .unwrap()
    }

    /// `bytes` with the `u32`/`u64` at `offset` replaced.
    fn patched(bytes: &[u8], offset: usize, value: &[u8]) -> Vec<u8> {
        let mut bad = bytes.to_vec();
        bad[offset..offset + value.len()].copy_from_slice(value);
        bad
    }

    #[test]
    fn a_file_round_trips_through_disk_and_is_recognised() {
        let dir = TestDir::new("stacks-round-trip");
        let path = dir.path().join("terrain.stacks");
        write_stacks(&path, &small()).unwrap();
        assert_eq!(read_stacks(&path).unwrap(), small());
        assert!(is_stacks_path(&path) && is_stacks_path(Path::new("A.STACKS")));
        assert!(!is_stacks_path(Path::new("a.mlhm")));
        assert!(has_stacks_magic(&std::fs::read(&path).unwrap()));
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "no temporary left");
    }

    #[test]
    fn the_layout_is_as_documented() {
        let bytes = stacks_to_bytes(&small(), name()).unwrap();
        assert_eq!(&bytes[..10], b"RELIEFSTK\0");
        assert_eq!(&bytes[10..12], &1u16.to_le_bytes());
        assert_eq!(&bytes[12..16], &2u32.to_le_bytes());
        assert_eq!(&bytes[16..20], &1u32.to_le_bytes());
        assert_eq!(&bytes[20..28], &1.5f64.to_le_bytes());
        assert_eq!(&bytes[44..52], &4.0f64.to_le_bytes());
        assert_eq!(&bytes[52..54], &3u16.to_le_bytes());
        // bedrock: solid, its colour, 7 bytes of name.
        assert_eq!(&bytes[54..67], b"\0\x80\x76\x6c\x07\0bedrock");
        let materials: usize = StackMaterial::defaults().iter().map(|m| 6 + m.name.len()).sum();
        let at = 54 + materials;
        assert_eq!(&bytes[at..at + 8], &4u64.to_le_bytes());
        assert_eq!(bytes.len(), at + 8 + 3 * 4 + 4 * 9);
        assert_eq!(&bytes[bytes.len() - 9..], b"\0\0\xa0\x40\0\0\xc0\x40\x01");
    }

    #[test]
    fn every_truncation_is_an_error() {
        let bytes = stacks_to_bytes(&small(), name()).unwrap();
        for len in 0..bytes.len() {
            let err = stacks_from_bytes(&bytes[..len], name()).unwrap_err();
            assert!(matches!(err, IoError::Format { .. }), "{len} bytes: {err}");
        }
        let mut longer = bytes.clone();
        longer.push(0);
        let err = stacks_from_bytes(&longer, name()).unwrap_err().to_string();
        assert!(err.contains("1 bytes after the layers"), "{err}");
    }

    #[test]
    fn a_hostile_header_is_refused_before_allocating() {
        let bytes = stacks_to_bytes(&small(), name()).unwrap();
        let layer_count_at = bytes.len() - 8 - 3 * 4 - 4 * 9;
        let huge = u32::MAX.to_le_bytes();
        for bad in [
            patched(&patched(&bytes, 12, &huge), 16, &huge),
            patched(&bytes, 12, &huge),
            patched(&bytes, layer_count_at, &u64::MAX.to_le_bytes()),
            patched(&bytes, layer_count_at, &(u64::MAX / 9).to_le_bytes()),
            patched(&bytes, layer_count_at, &(1u64 << 40).to_le_bytes()),
        ] {
            let err = stacks_from_bytes(&bad, name()).unwrap_err();
            assert!(matches!(err, IoError::Format { .. }), "{err}");
            assert!(err.to_string().contains("need more than"), "{err}");
        }
    }

    #[test]
    fn bad_magic_version_utf8_and_kind_are_refused_by_cause() {
        let bytes = stacks_to_bytes(&small(), name()).unwrap();
        let err = stacks_from_bytes(&patched(&bytes, 0, b"X"), name()).unwrap_err();
        assert!(matches!(err, IoError::Format { .. }) && err.to_string().contains("magic"));
        let err = stacks_from_bytes(&patched(&bytes, 10, &2u16.to_le_bytes()), name()).unwrap_err();
        assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
        let err = stacks_from_bytes(&patched(&bytes, 60, &[0xff]), name()).unwrap_err();
        assert!(err.to_string().contains("not UTF-8"), "{err}");
        let err = stacks_from_bytes(&patched(&bytes, 54, &[7]), name()).unwrap_err();
        assert!(matches!(err, IoError::Format { .. }) && err.to_string().contains("kind 7"));
    }

    #[test]
    fn invalid_stacks_are_invalid_data_naming_the_stack() {
        let bytes = stacks_to_bytes(&small(), name()).unwrap();
        // The arch's first layer (stack 1, layer 0) made to end below its start.
        let layer = bytes.len() - 3 * 9;
        let err = stacks_from_bytes(&patched(&bytes, layer + 4, &(-1.0f32).to_le_bytes()), name())
            .unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        assert!(err.to_string().contains("stack (1, 0), layer 0"), "{err}");
        // A material index past the palette.
        let err = stacks_from_bytes(&patched(&bytes, bytes.len() - 1, &[9]), name()).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        // An empty grid.
        let empty = patched(&bytes, 12, &0u32.to_le_bytes());
        let empty =
            [&empty[..bytes.len() - 8 - 3 * 4 - 4 * 9], &0u64.to_le_bytes(), &[0; 4]].concat();
        let err = stacks_from_bytes(&empty, name()).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
    }

    #[test]
    fn corrupted_files_give_errors_or_valid_stacks_never_panics() {
        let bytes = stacks_to_bytes(&small(), name()).unwrap();
        for bad in corrupted_copies(&bytes, 2000, 3) {
            if let Ok(stacks) = stacks_from_bytes(&bad, name()) {
                assert!(stacks.validate().is_ok());
            }
        }
    }

    #[test]
    fn a_name_too_long_for_the_format_writes_nothing() {
        let dir = TestDir::new("stacks-long-name");
        let path = dir.path().join("bad.stacks");
        let long = "x".repeat(70_000);
        let stacks = MaterialStacks::from_stacks(
            1,
            1,
            DVec2::ONE,
            DVec2::ZERO,
            vec![StackMaterial::new(&long, [0; 3], MaterialKind::Solid)],
            &[vec![]],
        )
        .unwrap();
        let err = write_stacks(&path, &stacks).unwrap_err();
        assert!(matches!(err, IoError::InvalidData { .. }), "{err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    /// Random stacks: a palette of 1 to 5 materials with any names, up to 3 layers a stack.
    fn random_stacks() -> impl Strategy<Value = MaterialStacks> {
        let material =
            ("\\PC{0,12}", any::<[u8; 3]>(), any::<bool>()).prop_map(|(n, c, liquid)| {
                let kind = if liquid { MaterialKind::Liquid } else { MaterialKind::Solid };
                StackMaterial::new(&n, c, kind)
            });
        (1usize..5, 1usize..5, prop::collection::vec(material, 1..5)).prop_flat_map(
            |(w, h, materials)| {
                let m = materials.len() as u8;
                let stack = prop::collection::vec((0.0f32..3.0, 0.01f32..3.0, 0..m), 0..3)
                    .prop_map(|parts| {
                        let mut z = -1.0f32;
                        parts
                            .into_iter()
                            .map(|(gap, thickness, material)| {
                                let start = z + gap;
                                z = start + thickness;
                                StackLayer::new(start, z, material)
                            })
                            .collect::<Vec<_>>()
                    });
                let grid = (0.1f64..10.0, 0.1f64..10.0, -1e6f64..1e6, -1e6f64..1e6);
                (prop::collection::vec(stack, w * h), grid).prop_map(
                    move |(columns, (sx, sy, ox, oy))| {
                        MaterialStacks::from_stacks(
                            w,
                            h,
                            DVec2::new(sx, sy),
                            DVec2::new(ox, oy),
                            materials.clone(),
                            &columns,
                        )
                        .unwrap()
                    },
                )
            },
        )
    }

    proptest! {
        #[test]
        fn random_stacks_round_trip_bit_for_bit(stacks in random_stacks()) {
            let bytes = stacks_to_bytes(&stacks, name()).unwrap();
            let back = stacks_from_bytes(&bytes, name()).unwrap();
            prop_assert_eq!(&back, &stacks);
            prop_assert_eq!(stacks_to_bytes(&back, name()).unwrap(), bytes);
        }
    }
}
