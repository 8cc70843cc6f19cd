//! The NumPy `.npy` header: its preamble, its Python-literal dictionary and its dtypes.
//!
//! Format: the magic `\x93NUMPY`, a major and minor version byte, the header length (u16 LE
//! for version 1, u32 LE for versions 2 and 3), then a Python dict literal with the keys
//! `descr`, `fortran_order` and `shape`, padded with spaces and ended by a newline.

use crate::format_error::FormatError;
use crate::sample_type::SampleType;
use std::io::{ErrorKind, Read};

/// The bytes every `.npy` file starts with.
pub(crate) const MAGIC: &[u8; 6] = b"\x93NUMPY";

/// Headers longer than this are refused without being read (numpy itself refuses 10 000).
const MAX_HEADER_LEN: u64 = 1 << 20;

/// An element type relief reads from and writes to `.npy` files: a raster sample type, or
/// float16, which among relief's inputs only NumPy arrays hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ScalarKind {
    /// An integer of 8 to 64 bits, float32 or float64 (the sample types of rasters).
    Sample(SampleType),
    /// IEEE 754 half precision (NumPy's `float16`, type code `f2`).
    F16,
}

impl ScalarKind {
    /// Bytes per element.
    pub(crate) fn size(self) -> usize {
        match self {
            ScalarKind::Sample(sample) => sample.size(),
            ScalarKind::F16 => 2,
        }
    }

    /// The type's NumPy name (`int16`, `float16`).
    pub(crate) fn name(self) -> &'static str {
        match self {
            ScalarKind::Sample(sample) => sample.name(),
            ScalarKind::F16 => "float16",
        }
    }

    /// The type's code in a NumPy type string, without the byte order (`i2`, `f2`).
    pub(crate) fn numpy_code(self) -> &'static str {
        match self {
            ScalarKind::Sample(sample) => sample.numpy_code(),
            ScalarKind::F16 => "f2",
        }
    }

    /// Whether the type is a signed or unsigned integer.
    pub(crate) fn is_integer(self) -> bool {
        self.numpy_code().starts_with(['i', 'u'])
    }

    /// Whether the type is a float (float16, float32 or float64).
    pub(crate) fn is_float(self) -> bool {
        self.numpy_code().starts_with('f')
    }
}

/// An element type with its byte order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Dtype {
    /// The element type.
    pub kind: ScalarKind,
    /// Whether multi-byte elements are stored most significant byte first.
    pub big_endian: bool,
}

impl Dtype {
    /// The little-endian dtype of `kind`, as relief writes it.
    pub(crate) const fn little_endian(kind: ScalarKind) -> Dtype {
        Dtype { kind, big_endian: false }
    }

    /// Bytes per element.
    pub(crate) fn size(&self) -> usize {
        self.kind.size()
    }

    /// The NumPy type string: the byte order (`<`, `>`, or `|` for single bytes) and the code,
    /// such as `<f4`, `>i2` or `|u1`.
    pub(crate) fn descr(&self) -> String {
        let order = match (self.size(), self.big_endian) {
            (1, _) => '|',
            (_, true) => '>',
            (_, false) => '<',
        };
        format!("{order}{}", self.kind.numpy_code())
    }
}

/// What a `.npy` header declares, and where its data starts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct NpyHeader {
    /// Element type of the data.
    pub dtype: Dtype,
    /// Whether the data is stored in column-major (Fortran) order.
    pub fortran_order: bool,
    /// The array's dimensions, slowest-varying first (in C order).
    pub shape: Vec<u64>,
    /// Byte offset of the first data byte in the file.
    pub data_offset: u64,
}

/// Why a header's text was refused, before a path is attached.
#[derive(Debug, PartialEq)]
enum Problem {
    Malformed(String),
    Unsupported(String),
}

fn malformed<T>(msg: impl Into<String>) -> Result<T, Problem> {
    Err(Problem::Malformed(msg.into()))
}

/// Reads the preamble and header of a `.npy` file of `file_len` bytes from `reader`, leaving
/// `reader` at the first data byte.
pub(crate) fn read_header(reader: &mut impl Read, file_len: u64) -> Result<NpyHeader, FormatError> {
    let read = |reader: &mut dyn Read, buf: &mut [u8], what: &str| {
        reader.read_exact(buf).map_err(|e| match e.kind() {
            ErrorKind::UnexpectedEof => FormatError::Format(format!("truncated in the {what}")),
            _ => FormatError::Io(e),
        })
    };
    let mut start = [0u8; 8];
    read(reader, &mut start, "preamble")?;
    if &start[..6] != MAGIC {
        return Err(FormatError::Format("not a .npy file (wrong magic bytes)".into()));
    }
    let (header_len, preamble_len) = match start[6] {
        1 => {
            let mut len = [0u8; 2];
            read(reader, &mut len, "preamble")?;
            (u64::from(u16::from_le_bytes(len)), 10)
        }
        2 | 3 => {
            let mut len = [0u8; 4];
            read(reader, &mut len, "preamble")?;
            (u64::from(u32::from_le_bytes(len)), 12)
        }
        major => {
            return Err(FormatError::Unsupported(format!(
                ".npy format version {major}.{}",
                start[7]
            )))
        }
    };
    if header_len > file_len.saturating_sub(preamble_len) {
        return Err(FormatError::Format(format!(
            "header length {header_len} runs past the end of the {file_len}-byte file"
        )));
    }
    if header_len > MAX_HEADER_LEN {
        return Err(FormatError::Unsupported(format!(
            "header of {header_len} bytes (at most {MAX_HEADER_LEN})"
        )));
    }
    // Bounded by the checks above.
    let mut text = vec![0u8; header_len as usize];
    read(reader, &mut text, "header")?;
    let (dtype, fortran_order, shape) = parse_dict(&text).map_err(|p| match p {
        Problem::Malformed(reason) => FormatError::Format(format!("header: {reason}")),
        Problem::Unsupported(what) => FormatError::Unsupported(what),
    })?;
    Ok(NpyHeader { dtype, fortran_order, shape, data_offset: preamble_len + header_len })
}

/// The version 1.0 preamble and header of a C-order array of `dtype` and `shape`, padded with
/// spaces so that the data starts at a multiple of 64 bytes; `None` when the shape is too long
/// for a version 1.0 header.
pub(crate) fn header_bytes(dtype: Dtype, shape: &[usize]) -> Option<Vec<u8>> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let tuple = match dims.len() {
        1 => format!("({},)", dims[0]),
        _ => format!("({})", dims.join(", ")),
    };
    let descr = dtype.descr();
    let mut dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {tuple}, }}");
    let unpadded = MAGIC.len() + 4 + dict.len() + 1;
    dict.extend(std::iter::repeat_n(' ', unpadded.next_multiple_of(64) - unpadded));
    dict.push('\n');
    let len = u16::try_from(dict.len()).ok()?;
    let mut out = Vec::with_capacity(10 + dict.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&len.to_le_bytes());
    out.extend_from_slice(dict.as_bytes());
    Some(out)
}

/// Parses the header dictionary into (dtype, fortran_order, shape).
fn parse_dict(text: &[u8]) -> Result<(Dtype, bool, Vec<u64>), Problem> {
    let mut cur = Cursor { text, pos: 0 };
    let (mut descr, mut fortran, mut shape) = (None, None, None);
    cur.expect(b'{')?;
    loop {
        cur.skip_space();
        if cur.eat(b'}') {
            break;
        }
        let key = cur.string()?;
        cur.expect(b':')?;
        cur.skip_space();
        let duplicate = match key.as_str() {
            "descr" => descr.replace(cur.descr()?).is_some(),
            "fortran_order" => fortran.replace(cur.boolean()?).is_some(),
            "shape" => shape.replace(cur.tuple()?).is_some(),
            _ => return malformed(format!("unexpected key '{key}'")),
        };
        if duplicate {
            return malformed(format!("key '{key}' given twice"));
        }
        cur.skip_space();
        if !cur.eat(b',') {
            cur.expect(b'}')?;
            break;
        }
    }
    cur.skip_space();
    if cur.pos != text.len() {
        return malformed(format!("unexpected text after the dictionary at byte {}", cur.pos));
    }
    let missing = |key: &str| Problem::Malformed(format!("key '{key}' missing"));
    Ok((
        descr.ok_or_else(|| missing("descr"))?,
        fortran.ok_or_else(|| missing("fortran_order"))?,
        shape.ok_or_else(|| missing("shape"))?,
    ))
}

/// A position in the header text.
struct Cursor<'a> {
    text: &'a [u8],
    pos: usize,
}

impl Cursor<'_> {
    fn peek(&self) -> Option<u8> {
        self.text.get(self.pos).copied()
    }

    fn skip_space(&mut self) {
        while self.peek().is_some_and(|b| b.is_ascii_whitespace()) {
            self.pos += 1;
        }
    }

    fn eat(&mut self, byte: u8) -> bool {
        let found = self.peek() == Some(byte);
        if found {
            self.pos += 1;
        }
        found
    }

    fn expect(&mut self, byte: u8) -> Result<(), Problem> {
        self.skip_space();
        if self.eat(byte) {
            return Ok(());
        }
        match self.peek() {
            Some(b) => malformed(format!(
                "expected '{}' at byte {}, found '{}'",
                byte as char,
                self.pos,
                b.escape_ascii()
            )),
            None => malformed(format!("expected '{}', found the end of the header", byte as char)),
        }
    }

    /// A quoted Python string; a backslash takes the next byte literally.
    fn string(&mut self) -> Result<String, Problem> {
        let quote = match self.peek() {
            Some(q @ (b'\'' | b'"')) => q,
            _ => return malformed(format!("expected a quoted string at byte {}", self.pos)),
        };
        self.pos += 1;
        let mut out = Vec::new();
        loop {
            match self.peek() {
                None => return malformed("unterminated string"),
                Some(b) if b == quote => break,
                Some(b'\\') => {
                    self.pos += 1;
                    match self.peek() {
                        Some(b) => out.push(b),
                        None => return malformed("unterminated string"),
                    }
                }
                Some(b) => out.push(b),
            }
            self.pos += 1;
        }
        self.pos += 1;
        Ok(String::from_utf8_lossy(&out).into_owned())
    }

    fn boolean(&mut self) -> Result<bool, Problem> {
        for (word, value) in [(&b"True"[..], true), (&b"False"[..], false)] {
            if self.text[self.pos..].starts_with(word) {
                self.pos += word.len();
                return Ok(value);
            }
        }
        malformed(format!("expected True or False at byte {}", self.pos))
    }

    fn descr(&mut self) -> Result<Dtype, Problem> {
        if self.peek() == Some(b'[') {
            return Err(Problem::Unsupported("structured dtype (a list of fields)".into()));
        }
        let descr = self.string()?;
        parse_descr(&descr).ok_or(Problem::Unsupported(format!("dtype '{descr}'")))
    }

    /// A tuple of non-negative integers, such as `(3, 4)`, `(5,)` or `()`.
    fn tuple(&mut self) -> Result<Vec<u64>, Problem> {
        self.expect(b'(')?;
        let mut dims = Vec::new();
        loop {
            self.skip_space();
            if self.eat(b')') {
                return Ok(dims);
            }
            dims.push(self.integer()?);
            self.skip_space();
            if !self.eat(b',') {
                self.expect(b')')?;
                return Ok(dims);
            }
        }
    }

    /// A decimal integer, optionally with Python 2's `L` suffix.
    fn integer(&mut self) -> Result<u64, Problem> {
        let start = self.pos;
        let mut value: u64 = 0;
        while let Some(d @ b'0'..=b'9') = self.peek() {
            value = value
                .checked_mul(10)
                .and_then(|v| v.checked_add(u64::from(d - b'0')))
                .ok_or_else(|| Problem::Malformed("dimension too large".into()))?;
            self.pos += 1;
        }
        if self.pos == start {
            return malformed(format!("expected a dimension at byte {}", self.pos));
        }
        self.eat(b'L');
        Ok(value)
    }
}

/// Parses a type string such as `<f4`, `>i2`, `<f2` or `|u1`; `None` for types relief does not
/// read.
fn parse_descr(descr: &str) -> Option<Dtype> {
    use ScalarKind::*;
    let (order, code) = match descr.as_bytes().first()? {
        b'<' | b'>' | b'|' | b'=' => descr.split_at(1),
        _ => ("=", descr),
    };
    let big_endian = match order {
        ">" => true,
        "<" => false,
        _ => cfg!(target_endian = "big"),
    };
    let kind = match code {
        "b" => Sample(SampleType::I8),
        "B" => Sample(SampleType::U8),
        "f2" | "e" => F16,
        _ => Sample(SampleType::ALL.into_iter().find(|t| t.numpy_code() == code)?),
    };
    Some(Dtype { kind, big_endian })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample_type::SampleType::*;
    use crate::IoError;
    use std::path::Path;
    use ScalarKind::Sample;

    fn header(dict: &str) -> Result<NpyHeader, IoError> {
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&[1, 0]);
        bytes.extend_from_slice(&(dict.len() as u16).to_le_bytes());
        bytes.extend_from_slice(dict.as_bytes());
        read_header(&mut &bytes[..], bytes.len() as u64).map_err(|e| e.at(Path::new("t.npy")))
    }

    #[test]
    fn parses_numpy_written_headers() {
        let dict = "{'descr': '>i2', 'fortran_order': True, 'shape': (3, 4), }   \n";
        let h = header(dict).unwrap();
        assert_eq!(h.dtype, Dtype { kind: Sample(I16), big_endian: true });
        assert!(h.fortran_order);
        assert_eq!(h.shape, vec![3, 4]);
        assert_eq!(h.data_offset, 10 + dict.len() as u64);
        let h = header("{\"shape\":(7L,),\"descr\":\"|u1\",\"fortran_order\":False}").unwrap();
        assert_eq!((h.shape, h.dtype.kind), (vec![7], Sample(U8)));
    }

    #[test]
    fn parses_float16_in_either_byte_order() {
        for (descr, big_endian) in [("<f2", false), (">f2", true), ("<e", false)] {
            let h =
                header(&format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': (2,)}}"))
                    .unwrap();
            assert_eq!(h.dtype, Dtype { kind: ScalarKind::F16, big_endian }, "{descr}");
            assert_eq!((h.dtype.size(), h.dtype.kind.name()), (2, "float16"));
        }
    }

    #[test]
    fn refuses_malformed_and_unsupported_headers() {
        let format = |d: &str| matches!(header(d), Err(IoError::Format { .. }));
        let unsupported = |d: &str| matches!(header(d), Err(IoError::Unsupported { .. }));
        assert!(format("{'descr': '<f4', 'fortran_order': False}"));
        assert!(format("{'descr': '<f4', 'fortran_order': False, 'shape': (1, 2)"));
        assert!(format("{'descr': '<f4', 'fortran_order': 0, 'shape': (1, 2)}"));
        assert!(format("{'descr': '<f4', 'descr': '<f4', 'fortran_order': False, 'shape': ()}"));
        assert!(format(
            "{'descr': '<f4', 'fortran_order': False, 'shape': (99999999999999999999,)}"
        ));
        assert!(format("{'descr': '<f4', 'fortran_order': False, 'shape': ((1,),)}"));
        assert!(format("{'descr': '<f4', 'fortran_order': False, 'shape': (1,)} x"));
        assert!(format("{'descr': '<f4"));
        assert!(unsupported("{'descr': '<c8', 'fortran_order': False, 'shape': (1, 2)}"));
        assert!(unsupported("{'descr': [('a', '<f4')], 'fortran_order': False, 'shape': (1,)}"));
    }

    #[test]
    fn header_length_past_the_file_is_refused_before_reading() {
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&[2, 0, 0xff, 0xff, 0xff, 0xff]);
        let err =
            read_header(&mut &bytes[..], bytes.len() as u64).map_err(|e| e.at(Path::new("t.npy")));
        assert!(matches!(err, Err(IoError::Format { .. })));
    }

    #[test]
    fn written_header_is_padded_to_64_and_reads_back() {
        let f32 = Dtype::little_endian(Sample(F32));
        for shape in [&[3usize, 4][..], &[5], &[2, 3, 3], &[]] {
            let bytes = header_bytes(f32, shape).unwrap();
            assert_eq!(bytes.len() % 64, 0);
            assert_eq!(bytes.last(), Some(&b'\n'));
            let h = read_header(&mut &bytes[..], bytes.len() as u64)
                .map_err(|e| e.at(Path::new("t.npy")))
                .unwrap();
            assert_eq!(h.shape, shape.iter().map(|&d| d as u64).collect::<Vec<_>>());
            assert_eq!(h.dtype, f32);
            assert!(!h.fortran_order);
            assert_eq!(h.data_offset, bytes.len() as u64);
        }
        let long_shape = vec![usize::MAX; 4000];
        assert!(header_bytes(f32, &long_shape).is_none());
    }

    #[test]
    fn written_header_of_every_type_and_byte_order_reads_back() {
        let kinds = SampleType::ALL.into_iter().map(Sample).chain([ScalarKind::F16]);
        for kind in kinds {
            for big_endian in [false, true] {
                let dtype = Dtype { kind, big_endian };
                let bytes = header_bytes(dtype, &[2, 3]).unwrap();
                let text = String::from_utf8_lossy(&bytes);
                assert!(text.contains(&format!("'descr': '{}'", dtype.descr())), "{text}");
                assert_eq!(bytes.len() % 64, 0);
                let h = read_header(&mut &bytes[..], bytes.len() as u64)
                    .map_err(|e| e.at(Path::new("t.npy")))
                    .unwrap();
                assert_eq!(h.dtype.kind, kind);
                // Single bytes are written without a byte order (`|`).
                if kind.size() > 1 {
                    assert_eq!(h.dtype.big_endian, big_endian, "{text}");
                }
                assert_eq!(h.shape, [2, 3]);
            }
        }
        assert_eq!(Dtype::little_endian(Sample(U8)).descr(), "|u1");
        assert_eq!(Dtype { kind: ScalarKind::F16, big_endian: true }.descr(), ">f2");
        assert_eq!(Dtype::little_endian(Sample(I32)).descr(), "<i4");
    }
}
