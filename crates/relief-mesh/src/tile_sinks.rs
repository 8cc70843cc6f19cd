//! What the rasterizer writes its covered pixels into: a [`crate::RasterTarget`]'s rows,
//! depth-tested, or coverage counts. Each row of screen tiles is one band of the target's
//! arrays, so a tile is written in place.

use crate::tile_scan::{BandSink, TileSink};
use crate::triangle_setup::{ScreenProjection, TileRays};

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
    /// One tile's depth keys (NaN: not found yet).
    key: Vec<f64>,
    /// Whether a triangle of this draw won each pixel of the tile.
    written: Vec<bool>,
    /// The edge functions of the triangle that won each pixel (stale where none did).
    edges: Vec<[f64; 3]>,
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
        let (key, written, edges) = (Vec::new(), Vec::new(), Vec::new());
        DepthBand { distance, triangle, barycentrics, width, id_offset, key, written, edges }
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
        let n = width * height;
        if self.edges.len() < n {
            // Read only where `written` says a triangle won: never reset.
            self.edges.resize(n, [0.0; 3]);
        }
        self.key.clear();
        self.key.resize(n, f64::NAN);
        self.written.clear();
        self.written.resize(n, false);
        DepthTile {
            distance: &mut self.distance[x..],
            triangle: &mut self.triangle[x..],
            barycentrics: self.barycentrics.as_deref_mut().map(|b| &mut b[x..]),
            stride: self.width,
            key: &mut self.key[..n],
            written: &mut self.written[..n],
            edges: &mut self.edges[..n],
            width,
            id_offset: self.id_offset,
            rays: projection.tile_rays([x, y], width, height),
        }
    }
}

/// One tile of a [`crate::RasterTarget`], written in place and depth-tested by depth key (see
/// `TriangleSetup::scan`): the key of a pixel the target held is found from its distance when
/// a triangle first reaches it; a pixel a triangle won gets its distance from its key, and
/// its barycentrics from the winner's edge functions, once, when the tile is finished.
pub(crate) struct DepthTile<'t> {
    /// The target's arrays from the tile's top-left pixel on, rows `stride` apart.
    distance: &'t mut [f32],
    triangle: &'t mut [u32],
    barycentrics: Option<&'t mut [[f32; 2]]>,
    stride: usize,
    /// The tile's depth keys and won pixels, rows `width` apart.
    key: &'t mut [f64],
    written: &'t mut [bool],
    edges: &'t mut [[f64; 3]],
    width: usize,
    id_offset: u32,
    rays: TileRays<'t>,
}

impl TileSink for DepthTile<'_> {
    #[inline(always)]
    fn write(&mut self, i: usize, j: usize, key: f64, triangle: u32, edges: [f64; 3]) {
        let (k, t) = (i + j * self.stride, i + j * self.width);
        let id = self.id_offset + triangle;
        let mut held = self.key[t];
        if held.is_nan() {
            held = self.rays.key(i, j, self.distance[k]);
            self.key[t] = held;
        }
        if key > held || (key == held && id < self.triangle[k]) {
            self.key[t] = key;
            self.written[t] = true;
            self.triangle[k] = id;
            self.edges[t] = edges;
        }
    }

    fn finish(&mut self) {
        for (t, _) in self.written.iter().enumerate().filter(|(_, &w)| w) {
            let (i, j) = (t % self.width, t / self.width);
            let k = i + j * self.stride;
            self.distance[k] = self.rays.distance(i, j, self.key[t]);
            if let Some(barycentrics) = self.barycentrics.as_deref_mut() {
                let e = self.edges[t];
                let inverse = 1.0 / (e[0] + e[1] + e[2]);
                barycentrics[k] = [(e[1] * inverse) as f32, (e[2] * inverse) as f32];
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
    fn write(&mut self, i: usize, j: usize, _key: f64, _triangle: u32, _edges: [f64; 3]) {
        self.counts[i + j * self.stride] += 1;
    }
}
