//! GeoTIFF chunks decoded here from their stored bytes rather than by the `tiff` crate:
//! ZSTD-compressed ones (Compression 50000, what GDAL writes for modern COGs), decompressed
//! by the pure-Rust `ruzstd` (the `tiff` crate's own ZSTD support wraps the C library), and
//! Deflate-compressed ones when many are decoded in parallel (by `flate2`'s pure-Rust
//! backend); the predictor is then undone here, leaving native-endian samples as the `tiff`
//! crate's decoder leaves them.

use flate2::{Decompress, FlushDecompress, Status};
use ruzstd::decoding::FrameDecoder;

/// TIFF's Compression code for ZSTD.
pub(crate) const COMPRESSION_ZSTD: u16 = 50000;

/// The largest ZSTD window accepted: libzstd's default limit for decompression (2^27 bytes).
const MAX_WINDOW: u64 = 1 << 27;

/// How the stored samples were transformed before compression (TIFF's Predictor tag).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Predictor {
    /// 1: none.
    None,
    /// 2: each sample, as an unsigned integer of its size, is the difference from the sample
    /// before it in the row.
    Horizontal,
    /// 3: TIFF Technical Note 3's floating-point predictor: the bytes of a row's samples split
    /// into planes (most significant first), each byte then the difference from the one before.
    FloatingPoint,
}

impl Predictor {
    /// The predictor of a Predictor tag's value; `None` for an unknown one.
    pub(crate) fn from_tag(value: u16) -> Option<Predictor> {
        match value {
            1 => Some(Predictor::None),
            2 => Some(Predictor::Horizontal),
            3 => Some(Predictor::FloatingPoint),
            _ => None,
        }
    }
}

/// TIFF's Compression codes for Deflate: 8 (Adobe) and 32946 (the old code).
pub(crate) const COMPRESSION_DEFLATE: [u16; 2] = [8, 32946];

/// The compressions a [`StoredChunkDecoder`] decodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum StoredCodec {
    /// ZSTD frames.
    Zstd,
    /// zlib (RFC 1950) streams.
    Deflate,
}

impl StoredCodec {
    /// The codec of a TIFF Compression code, if it is one of these.
    pub(crate) fn of(compression: u16) -> Option<StoredCodec> {
        if compression == COMPRESSION_ZSTD {
            Some(StoredCodec::Zstd)
        } else if COMPRESSION_DEFLATE.contains(&compression) {
            Some(StoredCodec::Deflate)
        } else {
            None
        }
    }

    /// "ZSTD" or "Deflate".
    fn name(self) -> &'static str {
        match self {
            StoredCodec::Zstd => "ZSTD",
            StoredCodec::Deflate => "Deflate",
        }
    }
}

/// The decompressor of a [`StoredCodec`], kept from one chunk to the next.
enum Decompressor {
    Zstd(Box<FrameDecoder>),
    Deflate(Box<Decompress>),
}

/// Decodes stored chunks one after the other, reusing its buffers.
pub(crate) struct StoredChunkDecoder {
    decompressor: Decompressor,
    predictor: Predictor,
    /// Bytes per sample.
    sample_size: usize,
    /// Whether the file's byte order differs from the machine's.
    swap: bool,
    scratch: Vec<u8>,
}

impl StoredChunkDecoder {
    /// A decoder of `codec` chunks of `sample_size`-byte samples stored with `predictor`, in
    /// a file whose byte order is big-endian when `big_endian`.
    pub(crate) fn new(
        codec: StoredCodec,
        predictor: Predictor,
        sample_size: usize,
        big_endian: bool,
    ) -> Self {
        let decompressor = match codec {
            StoredCodec::Zstd => {
                let mut frames = FrameDecoder::new();
                frames.set_max_window_size(MAX_WINDOW);
                Decompressor::Zstd(Box::new(frames))
            }
            StoredCodec::Deflate => Decompressor::Deflate(Box::new(Decompress::new(true))),
        };
        StoredChunkDecoder {
            decompressor,
            predictor,
            sample_size,
            swap: big_endian != cfg!(target_endian = "big"),
            scratch: Vec::new(),
        }
    }

    /// "ZSTD" or "Deflate".
    pub(crate) fn codec_name(&self) -> &'static str {
        match self.decompressor {
            Decompressor::Zstd(_) => StoredCodec::Zstd.name(),
            Decompressor::Deflate(_) => StoredCodec::Deflate.name(),
        }
    }

    /// Decompresses the `compressed` bytes of one chunk into `out`, then undoes the predictor
    /// on each of its stored rows of `stride` bytes; returns how many bytes were decoded,
    /// which may be fewer than `out` holds (a short last strip). Fails, saying why, on data
    /// that is not of the codec, is corrupt, or decodes to more than `out` holds.
    pub(crate) fn decode(
        &mut self,
        compressed: &[u8],
        out: &mut [u8],
        stride: usize,
    ) -> Result<usize, String> {
        let capacity = out.len();
        let too_large = |codec: StoredCodec| {
            format!("{} data decodes to more than the chunk's {capacity} bytes", codec.name())
        };
        let decoded = match &mut self.decompressor {
            Decompressor::Zstd(frames) => {
                frames.decode_all(compressed, out).map_err(|e| match e {
                    ruzstd::decoding::errors::FrameDecoderError::TargetTooSmall => {
                        too_large(StoredCodec::Zstd)
                    }
                    other => format!("corrupt ZSTD data ({other})"),
                })?
            }
            Decompressor::Deflate(zlib) => {
                zlib.reset(true);
                let status = zlib
                    .decompress(compressed, out, FlushDecompress::Finish)
                    .map_err(|e| format!("corrupt Deflate data ({e})"))?;
                let (read, written) = (zlib.total_in() as usize, zlib.total_out() as usize);
                if status != Status::StreamEnd && read < compressed.len() {
                    // The output is full: the stream must end (its checksum) without more.
                    let mut more = [0u8; 1];
                    let rest = &compressed[read..];
                    let status = zlib
                        .decompress(rest, &mut more, FlushDecompress::Finish)
                        .map_err(|e| format!("corrupt Deflate data ({e})"))?;
                    if zlib.total_out() as usize > written || status != Status::StreamEnd {
                        return Err(too_large(StoredCodec::Deflate));
                    }
                }
                written
            }
        };
        if decoded > capacity {
            return Err(too_large(StoredCodec::Zstd));
        }
        if stride > 0 {
            for row in out[..decoded - decoded % stride].chunks_exact_mut(stride) {
                self.unpredict_row(row);
            }
        }
        Ok(decoded)
    }

    /// Undoes the predictor on one row of stored samples, leaving them native-endian.
    fn unpredict_row(&mut self, row: &mut [u8]) {
        let size = self.sample_size;
        match self.predictor {
            Predictor::FloatingPoint => {
                for j in 1..row.len() {
                    row[j] = row[j].wrapping_add(row[j - 1]);
                }
                // Planes hold the most significant byte first, whatever the file's order.
                let n = row.len() / size;
                self.scratch.clear();
                self.scratch.extend_from_slice(row);
                for i in 0..n {
                    for byte in 0..size {
                        let plane =
                            if cfg!(target_endian = "big") { byte } else { size - 1 - byte };
                        row[i * size + byte] = self.scratch[plane * n + i];
                    }
                }
            }
            Predictor::None | Predictor::Horizontal => {
                if self.swap && size > 1 {
                    for sample in row.chunks_exact_mut(size) {
                        sample.reverse();
                    }
                }
                if self.predictor == Predictor::Horizontal {
                    accumulate(row, size);
                }
            }
        }
    }
}

/// Undoes horizontal differencing on a row of native-endian `size`-byte samples: each becomes
/// the wrapping sum of itself and the (already restored) sample before it.
fn accumulate(row: &mut [u8], size: usize) {
    macro_rules! each {
        ($t:ty) => {{
            const N: usize = std::mem::size_of::<$t>();
            let mut previous: $t = 0;
            for sample in row.chunks_exact_mut(N) {
                let mut raw = [0u8; N];
                raw.copy_from_slice(sample);
                previous = previous.wrapping_add(<$t>::from_ne_bytes(raw));
                sample.copy_from_slice(&previous.to_ne_bytes());
            }
        }};
    }
    match size {
        1 => each!(u8),
        2 => each!(u16),
        4 => each!(u32),
        _ => each!(u64),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ZSTD frame of one raw (uncompressed) block holding `data`, with its content size.
    fn raw_frame(data: &[u8]) -> Vec<u8> {
        let mut frame = vec![0x28, 0xb5, 0x2f, 0xfd];
        // Frame header: single segment, 4-byte content size.
        frame.push(0b1010_0000);
        frame.extend_from_slice(&(data.len() as u32).to_le_bytes());
        // Block header: last block, raw, its size.
        let header = 1 | ((data.len() as u32) << 3);
        frame.extend_from_slice(&header.to_le_bytes()[..3]);
        frame.extend_from_slice(data);
        frame
    }

    #[test]
    fn raw_frames_decode_and_predictors_are_undone() {
        // Horizontal, 16-bit little-endian samples 5, 7, 4 stored as 5, +2, -3.
        let stored: Vec<u8> =
            [5u16, 2, 0u16.wrapping_sub(3)].iter().flat_map(|v| v.to_le_bytes()).collect();
        let mut decoder =
            StoredChunkDecoder::new(StoredCodec::Zstd, Predictor::Horizontal, 2, false);
        let mut out = vec![0u8; 6];
        assert_eq!(decoder.decode(&raw_frame(&stored), &mut out, 6), Ok(6));
        let values: Vec<u16> =
            out.chunks_exact(2).map(|b| u16::from_ne_bytes([b[0], b[1]])).collect();
        assert_eq!(values, [5, 7, 4]);
        // Floating point: 1.0, 1.0 stored as planes then byte differences.
        let stored = [0x3f, 0, 0x41, 0, 0x80, 0, 0, 0];
        let mut decoder =
            StoredChunkDecoder::new(StoredCodec::Zstd, Predictor::FloatingPoint, 4, false);
        let mut out = vec![0u8; 8];
        assert_eq!(decoder.decode(&raw_frame(&stored), &mut out, 8), Ok(8));
        let values: Vec<f32> =
            out.chunks_exact(4).map(|b| f32::from_ne_bytes(b.try_into().unwrap())).collect();
        assert_eq!(values, [1.0, 1.0]);
        // No predictor, big-endian file.
        let mut decoder = StoredChunkDecoder::new(StoredCodec::Zstd, Predictor::None, 2, true);
        let mut out = vec![0u8; 2];
        decoder.decode(&raw_frame(&[0x01, 0x02]), &mut out, 2).unwrap();
        assert_eq!(u16::from_ne_bytes([out[0], out[1]]), 0x0102);
    }

    #[test]
    fn corrupt_or_oversized_data_is_an_error() {
        let mut decoder = StoredChunkDecoder::new(StoredCodec::Zstd, Predictor::None, 1, false);
        let mut out = vec![0u8; 4];
        let err = decoder.decode(&raw_frame(&[1, 2, 3, 4, 5]), &mut out, 4).unwrap_err();
        assert!(err.contains("more than the chunk's 4 bytes"), "{err}");
        for bad in [&b"not zstd"[..], &[], &raw_frame(&[1, 2])[..7]] {
            let err = decoder.decode(bad, &mut out, 4);
            assert!(err.is_err() || err == Ok(0), "{err:?}");
        }
        // Every truncation and every single-byte change of a frame: an error or some bytes,
        // never a panic.
        let frame = raw_frame(&[9; 4]);
        for cut in 0..frame.len() {
            let _ = decoder.decode(&frame[..cut], &mut out, 4);
        }
        for at in 0..frame.len() {
            let mut bad = frame.clone();
            bad[at] ^= 0x5a;
            let _ = decoder.decode(&bad, &mut out, 4);
        }
    }
}
