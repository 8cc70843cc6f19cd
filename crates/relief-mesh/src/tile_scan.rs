//! Scanning one screen tile: its binned triangles, in id order, set up and tested against the
//! tile's pixel centres, row by row or, where the processor has AVX-512, sixteen pixels of a
//! 4 x 4 block at a time. Both give the same pixels, depth keys and edge values.

use crate::triangle_setup::{ScreenProjection, TriangleSetup, BLOCK_LANES, BLOCK_SIDE};
use relief_core::DVec3;
use std::sync::OnceLock;

/// A triangle's part of one tile: its index and its pixel bounds relative to the tile.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BinEntry {
    pub(crate) triangle: u32,
    pub(crate) rect: [u8; 4],
}

/// Where a tile's covered pixels go. Pixels are relative to the tile, whose top-left pixel
/// lies on the image's grid of 4 x 4 blocks; `entry` numbers the tile's triangles in the
/// order they are scanned (an index into the set-ups `finish` gets).
pub(crate) trait TileSink: Send {
    /// Pixel (i, j) is covered by `triangle` at depth key `key` (larger is nearer; see
    /// `TriangleSetup::scan`).
    fn write(&mut self, i: usize, j: usize, key: f64, entry: u32, triangle: u32);

    /// The block of 4 x 4 pixels from (i, j) on (a multiple of 4 each) is covered by
    /// `triangle` where `keys` (row after row) is not NaN, at those depth keys. By default,
    /// pixel by pixel.
    #[inline(always)]
    fn write_block(
        &mut self,
        i: usize,
        j: usize,
        keys: &[f64; BLOCK_LANES],
        entry: u32,
        triangle: u32,
    ) {
        for (l, &key) in keys.iter().enumerate().filter(|(_, key)| !key.is_nan()) {
            self.write(i + l % BLOCK_SIDE, j + l / BLOCK_SIDE, key, entry, triangle);
        }
    }

    /// Called once every triangle of the tile has been written, with their set-ups by entry.
    fn finish(&mut self, _setups: &[TriangleSetup]) {}
}

/// Where the covered pixels of one row of tiles go: a sink for each of its tiles in turn.
pub(crate) trait BandSink: Send {
    /// The sink of one tile.
    type Tile<'t>: TileSink
    where
        Self: 't;

    /// The sink of the `width x height` tile whose top-left pixel is `origin` (in the image).
    fn tile<'t>(
        &'t mut self,
        projection: &'t ScreenProjection,
        origin: [usize; 2],
        width: usize,
        height: usize,
    ) -> Self::Tile<'t>;
}

/// How the rasterizer tests a triangle's pixel centres: every way covers the same pixels with
/// the same distances (the same IEEE operations for each pixel), so they differ only in speed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ScanLanes {
    /// Pixel by pixel along each row, over the row's span: runs everywhere.
    Rows,
    /// Blocks of 4 x 4 pixels, sixteen lanes an instruction, compiled for AVX-512 F, VL and
    /// DQ (x86-64).
    Avx512Blocks,
}

impl ScanLanes {
    /// Every way, the plainest first.
    pub const ALL: [ScanLanes; 2] = [ScanLanes::Rows, ScanLanes::Avx512Blocks];

    /// Whether this processor runs it.
    pub fn is_available(self) -> bool {
        match self {
            ScanLanes::Rows => true,
            #[cfg(target_arch = "x86_64")]
            ScanLanes::Avx512Blocks => {
                is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512vl")
                    && is_x86_feature_detected!("avx512dq")
            }
            #[cfg(not(target_arch = "x86_64"))]
            ScanLanes::Avx512Blocks => false,
        }
    }

    /// The fastest way this processor runs, found once per process: the blocks where there
    /// is AVX-512.
    pub fn fastest() -> ScanLanes {
        static FASTEST: OnceLock<ScanLanes> = OnceLock::new();
        *FASTEST.get_or_init(|| {
            ScanLanes::ALL.into_iter().rev().find(|w| w.is_available()).unwrap_or(Self::Rows)
        })
    }
}

/// What a tile's scan reads: the triangles, their world and projected corners, the camera.
pub(crate) struct ScanInput<'a> {
    pub(crate) projection: &'a ScreenProjection,
    pub(crate) triangles: &'a [[u32; 3]],
    pub(crate) positions: &'a [DVec3],
    pub(crate) projected: &'a [[f64; 3]],
}

/// Scans into `sink` the `entries` of the tile whose top-left pixel is `origin`, in the order
/// given, the way `lanes` says (which this processor must run), and finishes the sink;
/// returns the entries scanned and the pixels written.
#[allow(unsafe_code)]
pub(crate) fn scan_tile<'e, S: TileSink>(
    lanes: ScanLanes,
    input: &ScanInput,
    origin: [usize; 2],
    entries: impl Iterator<Item = &'e BinEntry>,
    sink: &mut S,
) -> (usize, usize) {
    assert!(lanes.is_available(), "{lanes:?} on a processor without it");
    let mut setups = Vec::new();
    let counts = match lanes {
        ScanLanes::Rows => scan_tile_with::<S, false>(input, origin, entries, sink, &mut setups),
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the processor runs AVX-512 F, VL and DQ (asserted above).
        ScanLanes::Avx512Blocks => unsafe {
            scan_tile_avx512(input, origin, entries, sink, &mut setups)
        },
        #[cfg(not(target_arch = "x86_64"))]
        ScanLanes::Avx512Blocks => unreachable!("no AVX-512 off x86-64"),
    };
    sink.finish(&setups);
    counts
}

/// [`scan_tile_with`] in blocks, compiled for AVX-512.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx2")]
fn scan_tile_avx512<'e, S: TileSink>(
    input: &ScanInput,
    origin: [usize; 2],
    entries: impl Iterator<Item = &'e BinEntry>,
    sink: &mut S,
    setups: &mut Vec<TriangleSetup>,
) -> (usize, usize) {
    scan_tile_with::<S, true>(input, origin, entries, sink, setups)
}

/// The tile's scan, in blocks of pixels (`BLOCKS`) or along rows; each triangle's set-up is
/// pushed to `setups`, its entry number.
#[inline(always)]
#[allow(unsafe_code)]
fn scan_tile_with<'e, S: TileSink, const BLOCKS: bool>(
    input: &ScanInput,
    [ox, oy]: [usize; 2],
    entries: impl Iterator<Item = &'e BinEntry>,
    sink: &mut S,
    setups: &mut Vec<TriangleSetup>,
) -> (usize, usize) {
    let (mut scanned, mut fragments) = (0, 0);
    for entry in entries {
        scanned += 1;
        let tri = &input.triangles[entry.triangle as usize];
        let world = tri.map(|v| input.positions[v as usize]);
        let corners = tri.map(|v| input.projected[v as usize]);
        let Some(setup) = TriangleSetup::new(input.projection, &corners, &world, false) else {
            continue;
        };
        let [x0, y0, x1, y1] = entry.rect.map(|c| c as usize);
        let rect = [ox + x0, oy + y0, ox + x1, oy + y1];
        let (number, triangle) = (setups.len() as u32, entry.triangle);
        fragments += if BLOCKS {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `BLOCKS` only where the processor runs AVX-512 (see `scan_tile`).
            unsafe {
                crate::block_scan::scan_blocks(&setup, input.projection, rect, |i, j, keys| {
                    sink.write_block(i - ox, j - oy, keys, number, triangle)
                })
            }
            #[cfg(not(target_arch = "x86_64"))]
            unreachable!("no AVX-512 off x86-64")
        } else {
            setup.scan(input.projection, rect, |i, j, key| {
                sink.write(i - ox, j - oy, key, number, triangle)
            })
        };
        setups.push(setup);
    }
    (scanned, fragments)
}
