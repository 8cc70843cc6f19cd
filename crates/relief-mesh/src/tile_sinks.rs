//! What the rasterizer writes its covered pixels into: a [`crate::RasterTarget`]'s rows,
//! depth-tested, or coverage counts. Each row of screen tiles is one band of the target's
//! arrays, so a tile is written in place.

use crate::tile_scan::{BandSink, TileSink};
use crate::triangle_setup::{ScreenProjection, TileRays, TriangleSetup, BLOCK_LANES, BLOCK_SIDE};
use crate::RasterTarget;

/// One row of tiles of a [`crate::RasterTarget`] (its rows `tile size` at a time), with the
/// scratch its tiles' depth test needs.
pub(crate) struct DepthBand<'a> {
    distance: &'a mut [f32],
    triangle: &'a mut [u32],
    /// The barycentrics, when the target keeps them.
    barycentrics: Option<&'a mut [[f32; 2]]>,
    /// The image's width: the stride of the band's rows.
    width: usize,
    id_offset: u32,
    /// One tile's depth keys, triangle ids and entries (see [`DepthTile`]).
    key: Vec<f64>,
    ids: Vec<u32>,
    entry: Vec<u32>,
    /// Whether nothing is drawn in the band yet (then its tiles need not read the target),
    /// found by its first tile.
    empty: Option<bool>,
}

impl<'a> DepthBand<'a> {
    /// The band of a target's rows `distance`, `triangle` and `barycentrics` (`width` pixels
    /// a row), whose triangle ids are offset by `id_offset`. Its scratch is made by the first
    /// tile some triangle reaches.
    pub(crate) fn new(
        distance: &'a mut [f32],
        triangle: &'a mut [u32],
        barycentrics: Option<&'a mut [[f32; 2]]>,
        width: usize,
        id_offset: u32,
    ) -> Self {
        let (key, ids, entry, empty) = (Vec::new(), Vec::new(), Vec::new(), None);
        DepthBand { distance, triangle, barycentrics, width, id_offset, key, ids, entry, empty }
    }
}

impl BandSink for DepthBand<'_> {
    type Tile<'t>
        = DepthTile<'t>
    where
        Self: 't;

    fn tile<'t>(
        &'t mut self,
        projection: &'t ScreenProjection,
        [x, y]: [usize; 2],
        width: usize,
        height: usize,
    ) -> DepthTile<'t> {
        let blocks = width.div_ceil(BLOCK_SIDE);
        let n = blocks * height.div_ceil(BLOCK_SIDE) * BLOCK_LANES;
        // What the target holds: its keys from its distances (`-inf` where nothing is drawn)
        // and its ids; no entry of this draw yet.
        let rays = projection.tile_rays([x, y], width, height);
        self.key.clear();
        self.key.resize(n, f64::NEG_INFINITY);
        self.ids.clear();
        self.ids.resize(n, RasterTarget::NO_TRIANGLE);
        self.entry.clear();
        self.entry.resize(n, NO_ENTRY);
        let distance = &self.distance;
        let empty = *self.empty.get_or_insert_with(|| distance.iter().all(|&d| d == f32::INFINITY));
        for j in (0..height).filter(|_| !empty) {
            for i in 0..width {
                let (k, t) = (x + i + j * self.width, block_index(blocks, i, j));
                self.key[t] = rays.key(i, j, self.distance[k]);
                self.ids[t] = self.triangle[k];
            }
        }
        DepthTile {
            distance: &mut self.distance[x..],
            triangle: &mut self.triangle[x..],
            barycentrics: self.barycentrics.as_deref_mut().map(|b| &mut b[x..]),
            stride: self.width,
            key: &mut self.key[..n],
            ids: &mut self.ids[..n],
            entry: &mut self.entry[..n],
            blocks,
            origin: [x, y],
            width,
            height,
            id_offset: self.id_offset,
            rays,
        }
    }
}

/// The entry of a pixel no triangle of this draw won.
const NO_ENTRY: u32 = u32::MAX;

/// The index of a tile's pixel (i, j) in its arrays stored block after block (`blocks` blocks
/// a row of blocks), each block's sixteen pixels row after row.
#[inline(always)]
fn block_index(blocks: usize, i: usize, j: usize) -> usize {
    ((j / BLOCK_SIDE) * blocks + i / BLOCK_SIDE) * BLOCK_LANES
        + (j % BLOCK_SIDE) * BLOCK_SIDE
        + i % BLOCK_SIDE
}

/// One tile of a [`crate::RasterTarget`], depth-tested by depth key (see
/// `TriangleSetup::scan`) in arrays of its own stored block after block, so that a block of
/// pixels is tested sixteen lanes at a time: the keys and ids of what the target held, and
/// the entry of the triangle of this draw that won each pixel. When the tile is finished, a
/// pixel some triangle won gets its id, its distance from its key, and its barycentrics from
/// the winner's edge functions there.
pub(crate) struct DepthTile<'t> {
    /// The target's arrays from the tile's top-left pixel on, rows `stride` apart.
    distance: &'t mut [f32],
    triangle: &'t mut [u32],
    barycentrics: Option<&'t mut [[f32; 2]]>,
    stride: usize,
    key: &'t mut [f64],
    ids: &'t mut [u32],
    entry: &'t mut [u32],
    /// Blocks a row of blocks.
    blocks: usize,
    /// The tile's top-left pixel in the image.
    origin: [usize; 2],
    width: usize,
    height: usize,
    id_offset: u32,
    rays: TileRays<'t>,
}

impl TileSink for DepthTile<'_> {
    #[inline(always)]
    fn write(&mut self, i: usize, j: usize, key: f64, entry: u32, triangle: u32) {
        let t = block_index(self.blocks, i, j);
        let id = self.id_offset + triangle;
        let held = self.key[t];
        if key > held || (key == held && id < self.ids[t]) {
            self.key[t] = key;
            self.ids[t] = id;
            self.entry[t] = entry;
        }
    }

    #[inline(always)]
    fn write_block(
        &mut self,
        i: usize,
        j: usize,
        keys: &[f64; BLOCK_LANES],
        entry: u32,
        triangle: u32,
    ) {
        let start = block_index(self.blocks, i, j);
        let id = self.id_offset + triangle;
        let held: &mut [f64; BLOCK_LANES] =
            (&mut self.key[start..start + BLOCK_LANES]).try_into().expect("a whole block");
        let ids: &mut [u32; BLOCK_LANES] =
            (&mut self.ids[start..start + BLOCK_LANES]).try_into().expect("a whole block");
        let entries: &mut [u32; BLOCK_LANES] =
            (&mut self.entry[start..start + BLOCK_LANES]).try_into().expect("a whole block");
        // Selects, not branches, so that the lanes stay lanes; a NaN key (a lane not
        // covered) wins nothing.
        for l in 0..BLOCK_LANES {
            let win = (keys[l] > held[l]) | ((keys[l] == held[l]) & (id < ids[l]));
            held[l] = if win { keys[l] } else { held[l] };
            ids[l] = if win { id } else { ids[l] };
            entries[l] = if win { entry } else { entries[l] };
        }
    }

    fn finish(&mut self, setups: &[TriangleSetup]) {
        let [x, y] = self.origin;
        for j in 0..self.height {
            for i in 0..self.width {
                let t = block_index(self.blocks, i, j);
                let Some(setup) = setups.get(self.entry[t] as usize) else {
                    continue;
                };
                let k = i + j * self.stride;
                self.triangle[k] = self.ids[t];
                self.distance[k] = self.rays.distance(i, j, self.key[t]);
                if let Some(barycentrics) = self.barycentrics.as_deref_mut() {
                    let e = setup.edges_at(x + i, y + j);
                    let inverse = 1.0 / (e[0] + e[1] + e[2]);
                    barycentrics[k] = [(e[1] * inverse) as f32, (e[2] * inverse) as f32];
                }
            }
        }
    }
}

/// One row of tiles of coverage counts.
pub(crate) struct CountBand<'a> {
    pub(crate) counts: &'a mut [u32],
    /// The image's width: the stride of the band's rows.
    pub(crate) width: usize,
}

impl BandSink for CountBand<'_> {
    type Tile<'t>
        = CountTile<'t>
    where
        Self: 't;

    fn tile<'t>(
        &'t mut self,
        _: &'t ScreenProjection,
        [x, _]: [usize; 2],
        _: usize,
        _: usize,
    ) -> CountTile<'t> {
        CountTile { counts: &mut self.counts[x..], stride: self.width }
    }
}

/// One tile of coverage counts, written in place.
pub(crate) struct CountTile<'t> {
    counts: &'t mut [u32],
    stride: usize,
}

impl TileSink for CountTile<'_> {
    #[inline(always)]
    fn write(&mut self, i: usize, j: usize, _key: f64, _entry: u32, _triangle: u32) {
        self.counts[i + j * self.stride] += 1;
    }
}
