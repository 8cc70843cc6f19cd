//! The numeric sample types relief reads from raster files.

/// A stored sample type: signed and unsigned integers of 8 to 64 bits, 32- and 64-bit floats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SampleType {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

/// The byte order of stored samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SampleOrder {
    /// Least significant byte first.
    Little,
    /// Most significant byte first.
    Big,
    /// This processor's order (what a decoder that swapped already leaves).
    Native,
}

impl SampleType {
    /// Converts `bytes`, samples of this type in `order`, to `f32` into `out`, one a sample
    /// (as many as both hold).
    pub(crate) fn decode(self, bytes: &[u8], order: SampleOrder, out: &mut [f32]) {
        macro_rules! each {
            ($t:ty) => {{
                const N: usize = std::mem::size_of::<$t>();
                for (o, b) in out.iter_mut().zip(bytes.chunks_exact(N)) {
                    let mut raw = [0u8; N];
                    raw.copy_from_slice(b);
                    *o = match order {
                        SampleOrder::Little => <$t>::from_le_bytes(raw),
                        SampleOrder::Big => <$t>::from_be_bytes(raw),
                        SampleOrder::Native => <$t>::from_ne_bytes(raw),
                    } as f32;
                }
            }};
        }
        use SampleType::*;
        match self {
            I8 => each!(i8),
            U8 => each!(u8),
            I16 => each!(i16),
            U16 => each!(u16),
            I32 => each!(i32),
            U32 => each!(u32),
            I64 => each!(i64),
            U64 => each!(u64),
            F32 => each!(f32),
            F64 => each!(f64),
        }
    }

    /// Bytes per sample.
    pub(crate) fn size(self) -> usize {
        use SampleType::*;
        match self {
            I8 | U8 => 1,
            I16 | U16 => 2,
            I32 | U32 | F32 => 4,
            I64 | U64 | F64 => 8,
        }
    }

    /// Every sample type.
    pub(crate) const ALL: [SampleType; 10] = {
        use SampleType::*;
        [I8, U8, I16, U16, I32, U32, I64, U64, F32, F64]
    };

    /// The type's code in a NumPy type string, without the byte order: kind and bytes (`i2`).
    pub(crate) fn numpy_code(self) -> &'static str {
        use SampleType::*;
        match self {
            I8 => "i1",
            U8 => "u1",
            I16 => "i2",
            U16 => "u2",
            I32 => "i4",
            U32 => "u4",
            I64 => "i8",
            U64 => "u8",
            F32 => "f4",
            F64 => "f8",
        }
    }

    /// The name [`crate::RasterInfo::sample_type`] reports, as NumPy spells it (`int16`).
    pub(crate) fn name(self) -> &'static str {
        use SampleType::*;
        match self {
            I8 => "int8",
            U8 => "uint8",
            I16 => "int16",
            U16 => "uint16",
            I32 => "int32",
            U32 => "uint32",
            I64 => "int64",
            U64 => "uint64",
            F32 => "float32",
            F64 => "float64",
        }
    }
}
