//! TIFF and BigTIFF image file directories encoded by hand, with their out-of-line values, for
//! a writer that must place the directories before the image data (the cloud-optimised
//! layout), which the `tiff` crate's encoder does not: the header, a ghost area after it, the
//! directories one after the other, each followed by its values, then the values held back for
//! after every directory (the tile offsets and byte counts). Little-endian throughout.

/// The values of one tag.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum TagValue {
    /// SHORT (16-bit) values.
    Short(Vec<u16>),
    /// LONG (32-bit) values.
    Long(Vec<u32>),
    /// LONG8 (64-bit, BigTIFF only) values.
    Long8(Vec<u64>),
    /// DOUBLE values.
    Double(Vec<f64>),
    /// ASCII bytes, the terminating NUL included.
    Ascii(Vec<u8>),
}

impl TagValue {
    /// The ASCII value of `bytes`, adding the terminating NUL when they lack one.
    pub(crate) fn ascii(bytes: &[u8]) -> TagValue {
        let mut data = bytes.to_vec();
        if data.last() != Some(&0) {
            data.push(0);
        }
        TagValue::Ascii(data)
    }

    /// TIFF's code of the field type.
    fn type_code(&self) -> u16 {
        match self {
            TagValue::Ascii(_) => 2,
            TagValue::Short(_) => 3,
            TagValue::Long(_) => 4,
            TagValue::Double(_) => 12,
            TagValue::Long8(_) => 16,
        }
    }

    /// Number of values.
    fn count(&self) -> usize {
        match self {
            TagValue::Short(v) => v.len(),
            TagValue::Long(v) => v.len(),
            TagValue::Long8(v) => v.len(),
            TagValue::Double(v) => v.len(),
            TagValue::Ascii(v) => v.len(),
        }
    }

    /// Bytes of the values.
    fn len(&self) -> u64 {
        let size = match self {
            TagValue::Ascii(_) => 1,
            TagValue::Short(_) => 2,
            TagValue::Long(_) => 4,
            TagValue::Double(_) | TagValue::Long8(_) => 8,
        };
        self.count() as u64 * size
    }

    /// Appends the values, little-endian.
    fn write(&self, out: &mut Vec<u8>) {
        match self {
            TagValue::Short(v) => v.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            TagValue::Long(v) => v.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            TagValue::Long8(v) => v.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            TagValue::Double(v) => v.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            TagValue::Ascii(v) => out.extend_from_slice(v),
        }
    }
}

/// One tag of a directory.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Entry {
    /// The tag's number.
    pub(crate) tag: u16,
    /// Its values.
    pub(crate) value: TagValue,
    /// Whether its values, when they do not fit in the entry, are written after every
    /// directory rather than right after their own.
    pub(crate) deferred: bool,
}

impl Entry {
    /// A tag whose values follow its directory.
    pub(crate) fn new(tag: u16, value: TagValue) -> Entry {
        Entry { tag, value, deferred: false }
    }

    /// A tag whose values come after every directory.
    pub(crate) fn deferred(tag: u16, value: TagValue) -> Entry {
        Entry { tag, value, deferred: true }
    }
}

/// The TIFF flavour: classic (32-bit offsets) or BigTIFF (64-bit).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TiffFlavour {
    /// BigTIFF when true.
    pub(crate) big: bool,
}

impl TiffFlavour {
    /// Bytes of the header.
    fn header_len(self) -> u64 {
        if self.big {
            16
        } else {
            8
        }
    }

    /// Bytes of an offset (and of the value field of an entry).
    fn offset_len(self) -> u64 {
        if self.big {
            8
        } else {
            4
        }
    }

    /// Bytes of a directory of `entries` tags: its count, the entries, the next offset.
    fn directory_len(self, entries: usize) -> u64 {
        let (count, entry) = if self.big { (8, 20) } else { (2, 12) };
        count + entries as u64 * entry + self.offset_len()
    }

    /// Appends `value` as an offset (or count) of this flavour.
    fn write_offset(self, out: &mut Vec<u8>, value: u64) {
        if self.big {
            out.extend_from_slice(&value.to_le_bytes());
        } else {
            // encode() checked that every offset fits.
            out.extend_from_slice(&(value as u32).to_le_bytes());
        }
    }
}

/// Where the header ends and the image data may start: the encoded header, ghost area and
/// directories with all their values.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct EncodedDirectories {
    /// The bytes, from the start of the file.
    pub(crate) bytes: Vec<u8>,
    /// The offset of each directory.
    pub(crate) directory_offsets: Vec<u64>,
}

/// Encodes a little-endian TIFF (or BigTIFF) header, `ghost` right after it, then the chain
/// of `directories` (their tags sorted by number), each followed by its values that do not
/// fit in their entries except the deferred ones, which come after the last directory in
/// directory order. Directories and values start on even offsets. Fails, saying why, on a
/// repeated tag or, in a classic TIFF, an offset or count past 2^32 - 1.
pub(crate) fn encode(
    flavour: TiffFlavour,
    ghost: &[u8],
    directories: &[Vec<Entry>],
) -> Result<EncodedDirectories, String> {
    let mut sorted: Vec<Vec<&Entry>> = Vec::with_capacity(directories.len());
    for directory in directories {
        let mut entries: Vec<&Entry> = directory.iter().collect();
        entries.sort_by_key(|e| e.tag);
        if let Some(pair) = entries.windows(2).find(|p| p[0].tag == p[1].tag) {
            return Err(format!("tag {} given twice in one directory", pair[0].tag));
        }
        sorted.push(entries);
    }
    let inline = |entry: &Entry| entry.value.len() <= flavour.offset_len();
    // Where everything goes: directories with their own values, then the deferred values.
    let even = |n: u64| n + n % 2;
    let mut at = even(flavour.header_len() + ghost.len() as u64);
    let mut directory_offsets = Vec::with_capacity(sorted.len());
    let mut value_offsets: Vec<Vec<u64>> = Vec::with_capacity(sorted.len());
    for entries in &sorted {
        directory_offsets.push(at);
        at += flavour.directory_len(entries.len());
        let mut offsets = vec![0; entries.len()];
        for (slot, entry) in offsets.iter_mut().zip(entries) {
            if !inline(entry) && !entry.deferred {
                *slot = at;
                at = even(at + entry.value.len());
            }
        }
        value_offsets.push(offsets);
    }
    for (entries, offsets) in sorted.iter().zip(&mut value_offsets) {
        for (slot, entry) in offsets.iter_mut().zip(entries) {
            if !inline(entry) && entry.deferred {
                *slot = at;
                at = even(at + entry.value.len());
            }
        }
    }
    let too_large = sorted.iter().flatten().any(|e| e.value.count() as u64 > u32::MAX as u64);
    if !flavour.big && (at > u32::MAX as u64 || too_large) {
        return Err(format!("{at} bytes of directories do not fit a classic TIFF"));
    }
    let mut out = Vec::with_capacity(at as usize);
    if flavour.big {
        out.extend_from_slice(b"II\x2b\x00\x08\x00\x00\x00");
    } else {
        out.extend_from_slice(b"II\x2a\x00");
    }
    flavour.write_offset(&mut out, directory_offsets.first().copied().unwrap_or(0));
    out.extend_from_slice(ghost);
    let pad = |out: &mut Vec<u8>| {
        if out.len() % 2 == 1 {
            out.push(0);
        }
    };
    pad(&mut out);
    for (d, (entries, offsets)) in sorted.iter().zip(&value_offsets).enumerate() {
        debug_assert_eq!(out.len() as u64, directory_offsets[d]);
        // The number of entries: a SHORT in a classic TIFF, a LONG8 in a BigTIFF (the few
        // tags written here fit either).
        if flavour.big {
            out.extend_from_slice(&(entries.len() as u64).to_le_bytes());
        } else {
            out.extend_from_slice(&(entries.len() as u16).to_le_bytes());
        }
        for (entry, &offset) in entries.iter().zip(offsets) {
            out.extend_from_slice(&entry.tag.to_le_bytes());
            out.extend_from_slice(&entry.value.type_code().to_le_bytes());
            flavour.write_offset(&mut out, entry.value.count() as u64);
            if inline(entry) {
                let start = out.len();
                entry.value.write(&mut out);
                out.resize(start + flavour.offset_len() as usize, 0);
            } else {
                flavour.write_offset(&mut out, offset);
            }
        }
        flavour.write_offset(&mut out, directory_offsets.get(d + 1).copied().unwrap_or(0));
        for (entry, &offset) in entries.iter().zip(offsets) {
            if !inline(entry) && !entry.deferred {
                debug_assert_eq!(out.len() as u64, offset);
                entry.value.write(&mut out);
                pad(&mut out);
            }
        }
    }
    for (entries, offsets) in sorted.iter().zip(&value_offsets) {
        for (entry, &offset) in entries.iter().zip(offsets) {
            if !inline(entry) && entry.deferred {
                debug_assert_eq!(out.len() as u64, offset);
                entry.value.write(&mut out);
                pad(&mut out);
            }
        }
    }
    debug_assert_eq!(out.len() as u64, at);
    Ok(EncodedDirectories { bytes: out, directory_offsets })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;
    use tiff::decoder::Decoder;
    use tiff::tags::Tag;

    /// Two directories of a 3 x 2 float32 image, one uncompressed strip each, after the
    /// directories.
    fn two_images(flavour: TiffFlavour) -> Vec<u8> {
        let directory = |offset: u64, subfile: u32| {
            let offset = if flavour.big {
                TagValue::Long8(vec![offset])
            } else {
                TagValue::Long(vec![offset as u32])
            };
            vec![
                Entry::new(339, TagValue::Short(vec![3])),
                Entry::new(256, TagValue::Long(vec![3])),
                Entry::new(257, TagValue::Long(vec![2])),
                Entry::new(254, TagValue::Long(vec![subfile])),
                Entry::new(258, TagValue::Short(vec![32])),
                Entry::new(259, TagValue::Short(vec![1])),
                Entry::new(262, TagValue::Short(vec![1])),
                Entry::new(277, TagValue::Short(vec![1])),
                Entry::new(278, TagValue::Long(vec![2])),
                Entry::deferred(273, offset),
                Entry::deferred(279, TagValue::Long(vec![24])),
                Entry::new(33550, TagValue::Double(vec![30.0, 20.0, 0.0])),
                Entry::new(42113, TagValue::ascii(b"nan")),
            ]
        };
        let ghost = b"GHOST";
        let probe = encode(flavour, ghost, &[directory(0, 0), directory(0, 1)]).unwrap();
        let data = probe.bytes.len() as u64;
        let mut bytes =
            encode(flavour, ghost, &[directory(data, 0), directory(data + 24, 1)]).unwrap().bytes;
        assert_eq!(bytes.len() as u64, data);
        assert_eq!(&bytes[flavour.header_len() as usize..][..5], ghost);
        for image in 0..2 {
            for k in 0..6 {
                bytes.extend_from_slice(&(k as f32 + 10.0 * image as f32).to_le_bytes());
            }
        }
        bytes
    }

    #[test]
    fn directories_read_back_with_the_tiff_crate() {
        for big in [false, true] {
            let bytes = two_images(TiffFlavour { big });
            assert_eq!(&bytes[..4], if big { b"II+\0" } else { b"II*\0" });
            let mut decoder = Decoder::new(Cursor::new(bytes)).unwrap();
            assert_eq!(decoder.dimensions().unwrap(), (3, 2));
            let scale = decoder.get_tag_f64_vec(Tag::ModelPixelScaleTag).unwrap();
            assert_eq!(scale, [30.0, 20.0, 0.0]);
            assert_eq!(decoder.get_tag_ascii_string(Tag::GdalNodata).unwrap(), "nan");
            let first = decoder.read_image().unwrap();
            assert!(matches!(first, tiff::decoder::DecodingResult::F32(v) if v[5] == 5.0));
            assert!(decoder.more_images());
            decoder.next_image().unwrap();
            assert_eq!(decoder.get_tag_u32(Tag::NewSubfileType).unwrap(), 1);
            let second = decoder.read_image().unwrap();
            assert!(matches!(second, tiff::decoder::DecodingResult::F32(v) if v[5] == 15.0));
            assert!(!decoder.more_images());
        }
    }

    #[test]
    fn repeated_tags_and_classic_overflow_are_refused() {
        let twice = vec![
            Entry::new(256, TagValue::Long(vec![1])),
            Entry::new(256, TagValue::Long(vec![2])),
        ];
        let flavour = TiffFlavour { big: false };
        assert!(encode(flavour, b"", &[twice]).unwrap_err().contains("tag 256 given twice"));
        let offset = Entry::new(273, TagValue::Long8(vec![1 << 33]));
        // A LONG8 of one value fits a BigTIFF entry.
        let big = encode(TiffFlavour { big: true }, b"", &[vec![offset]]).unwrap();
        assert_eq!(big.directory_offsets, [16]);
        assert_eq!(big.bytes.len(), 16 + 8 + 20 + 8);
    }
}
