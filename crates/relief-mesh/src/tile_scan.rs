//! Scanning one screen tile: its binned triangles, in id order, set up and tested against the
//! tile's pixel centres, row by row or, where the processor has AVX-512, sixteen pixels of a
//! 4 x 4 block at a time. Both give the same pixels, depth keys and edge values.

use crate::triangle_setup::{ScreenProjection, TriangleSetup};
use relief_core::DVec3;
use std::sync::OnceLock;

/// A triangle's part of one tile: its index and its pixel bounds relative to the tile.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BinEntry {
    pub(crate) triangle: u32,
    pub(crate) rect: [u8; 4],
}

/// Where a tile's covered pixels go.
pub(crate) trait TileSink: Send {
    /// Pixel (i, j) of the tile is covered by `triangle` at depth key `key` (larger is
    /// nearer), its edge functions `edges` there (see `TriangleSetup::scan`).
    fn write(&mut self, i: usize, j: usize, key: f64, triangle: u32, edges: [f64; 3]);

    /// Called once every triangle of the tile has been written.
    fn finish(&mut self) {}
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
    let counts = match lanes {
        ScanLanes::Rows => scan_tile_with::<S, false>(input, origin, entries, sink),
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the processor runs AVX-512 F, VL and DQ (asserted above).
        ScanLanes::Avx512Blocks => unsafe { scan_tile_avx512(input, origin, entries, sink) },
        #[cfg(not(target_arch = "x86_64"))]
        ScanLanes::Avx512Blocks => unreachable!("no AVX-512 off x86-64"),
    };
    sink.finish();
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
) -> (usize, usize) {
    scan_tile_with::<S, true>(input, origin, entries, sink)
}

/// The tile's scan, in blocks of pixels (`BLOCKS`) or along rows.
#[inline(always)]
fn scan_tile_with<'e, S: TileSink, const BLOCKS: bool>(
    input: &ScanInput,
    [ox, oy]: [usize; 2],
    entries: impl Iterator<Item = &'e BinEntry>,
    sink: &mut S,
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
        let write = |i: usize, j: usize, key: f64, edges: [f64; 3]| {
            sink.write(i - ox, j - oy, key, entry.triangle, edges)
        };
        fragments += if BLOCKS {
            setup.scan_blocks(input.projection, rect, write)
        } else {
            setup.scan(input.projection, rect, write)
        };
    }
    (scanned, fragments)
}
