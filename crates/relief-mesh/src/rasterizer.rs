//! The binned, tile-parallel CPU rasterizer: triangles are projected and binned into screen
//! tiles in parallel, then every tile is rasterized by one worker into its own pixels, so the
//! image is the same whatever the thread count.

use crate::triangle_setup::{is_back_face, ScreenProjection, TriangleSetup};
use crate::{IndexedMesh, MeshError, RasterTarget};
use rayon::prelude::*;
use relief_core::Camera;

/// Triangles per binning job.
const BIN_CHUNK: usize = 16 * 1024;

/// The CPU triangle rasterizer of relief (see the crate docs): watertight coverage with the
/// top-left rule, both windings drawn, triangles crossing the eye's plane drawn exactly, and
/// per pixel the exact distance along its camera ray to the triangle's plane.
///
/// ```
/// use relief_core::{Camera, DVec3};
/// use relief_mesh::{IndexedMesh, RasterTarget, Rasterizer};
/// let quad = IndexedMesh::new(
///     vec![DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, -1.0, 0.0),
///          DVec3::new(-1.0, 1.0, 0.0), DVec3::new(1.0, 1.0, 0.0)],
///     vec![[0, 1, 2], [1, 3, 2]],
/// ).unwrap();
/// let camera = Camera::look_at(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y, 30.0, 8, 8)
///     .unwrap();
/// let mut target = RasterTarget::for_camera(&camera);
/// Rasterizer::new().draw(&camera, &quad, 0, &mut target).unwrap();
/// let (distance, _triangle) = target.get(4, 4).unwrap();
/// assert!((distance as f64 - camera.ray(4, 4).dir.z.recip().abs() * 5.0).abs() < 1e-5);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rasterizer {
    tile_size: usize,
    culling: Culling,
}

/// Which triangles a [`Rasterizer`] skips by their facing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Culling {
    /// Draw both windings (the default).
    #[default]
    None,
    /// Skip triangles whose normal `(p1 - p0) x (p2 - p0)` does not face the camera's rays
    /// (counter-clockwise seen from the camera is the front). For closed, outward-oriented
    /// meshes such as [`crate::height_field_mesh`]'s, seen from outside, the image is the same
    /// and about half the triangles are skipped.
    BackFaces,
}

/// What one draw call did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DrawStats {
    /// Triangles that reached at least one tile (not culled as off screen, behind the eye or
    /// covering no pixel centre's bounding box).
    pub triangles_binned: usize,
    /// (tile, triangle) pairs scanned.
    pub bin_entries: usize,
    /// Pixels covered with a positive distance (depth-tested writes, won or lost).
    pub fragments: usize,
}

/// A triangle's part of one tile: its index and its pixel bounds relative to the tile.
#[derive(Debug, Clone, Copy)]
struct BinEntry {
    triangle: u32,
    rect: [u8; 4],
}

impl Default for Rasterizer {
    fn default() -> Self {
        Rasterizer { tile_size: 64, culling: Culling::None }
    }
}

impl Rasterizer {
    /// A rasterizer with 64 x 64 pixel tiles.
    pub fn new() -> Self {
        Self::default()
    }

    /// A rasterizer with `tile_size x tile_size` pixel tiles, `tile_size` a power of two in
    /// 8..=256.
    pub fn with_tile_size(tile_size: u32) -> Result<Self, MeshError> {
        if !(8..=256).contains(&tile_size) || !tile_size.is_power_of_two() {
            return Err(MeshError::Parameter {
                name: "tile size",
                reason: format!("{tile_size} is not a power of two in 8..=256 pixels"),
            });
        }
        Ok(Rasterizer { tile_size: tile_size as usize, ..Self::default() })
    }

    /// The same rasterizer with `culling`.
    pub fn with_culling(self, culling: Culling) -> Self {
        Rasterizer { culling, ..self }
    }

    /// Which triangles are skipped by their facing.
    pub fn culling(&self) -> Culling {
        self.culling
    }

    /// The side of a screen tile in pixels.
    pub fn tile_size(&self) -> u32 {
        self.tile_size as u32
    }

    /// Draws `mesh` as seen by `camera` into `target`, depth-tested: a pixel takes the triangle
    /// whose distance is strictly smaller than what it holds, or, at an equal distance, the
    /// smaller id. Triangle `k` is written as id `id_offset + k`.
    ///
    /// Fails when the target's size differs from the camera's image or the ids would reach
    /// [`RasterTarget::NO_TRIANGLE`].
    pub fn draw(
        &self,
        camera: &Camera,
        mesh: &IndexedMesh,
        id_offset: u32,
        target: &mut RasterTarget,
    ) -> Result<DrawStats, MeshError> {
        if !target.is_consistent()
            || target.width != camera.width() as usize
            || target.height != camera.height() as usize
        {
            return Err(MeshError::TargetSize {
                target_width: target.width,
                target_height: target.height,
                camera_width: camera.width(),
                camera_height: camera.height(),
            });
        }
        if id_offset as u64 + mesh.triangle_count() as u64 >= RasterTarget::NO_TRIANGLE as u64 {
            return Err(MeshError::Limits(format!(
                "id offset {id_offset} plus {} triangles reaches the u32 ids",
                mesh.triangle_count()
            )));
        }
        let width = target.width;
        let read_only: &RasterTarget = target;
        let (tiles, stats) = self.rasterize(camera, mesh, |rect, tile_w, tile_h| {
            let mut distance = vec![f32::INFINITY; tile_w * tile_h];
            let mut triangle = vec![RasterTarget::NO_TRIANGLE; tile_w * tile_h];
            let keeps = !read_only.barycentrics.is_empty();
            let mut barycentrics = vec![[0.0f32; 2]; if keeps { tile_w * tile_h } else { 0 }];
            for row in 0..tile_h {
                let src = rect[0] + (rect[1] + row) * width;
                let dst = row * tile_w;
                distance[dst..dst + tile_w].copy_from_slice(&read_only.distance[src..src + tile_w]);
                triangle[dst..dst + tile_w].copy_from_slice(&read_only.triangle[src..src + tile_w]);
                if keeps {
                    barycentrics[dst..dst + tile_w]
                        .copy_from_slice(&read_only.barycentrics[src..src + tile_w]);
                }
            }
            DepthTile { distance, triangle, barycentrics, width: tile_w, id_offset }
        });
        // The tiles written back band by band (a band: one row of tiles), bands in parallel.
        let band = self.tile_size * width;
        let mut by_band: Vec<Vec<([usize; 2], DepthTile)>> =
            (0..target.height.div_ceil(self.tile_size)).map(|_| Vec::new()).collect();
        for (rect, tile) in tiles {
            by_band[rect[1] / self.tile_size].push((rect, tile));
        }
        let barycentric_bands: Vec<Option<&mut [[f32; 2]]>> = if target.barycentrics.is_empty() {
            by_band.iter().map(|_| None).collect()
        } else {
            target.barycentrics.chunks_mut(band).map(Some).collect()
        };
        target
            .distance
            .par_chunks_mut(band)
            .zip(target.triangle.par_chunks_mut(band))
            .zip(barycentric_bands)
            .zip(by_band)
            .for_each(|(((distance, triangle), mut barycentrics), tiles)| {
                for ([x, _], tile) in tiles {
                    let w = tile.width;
                    for row in 0..tile.distance.len() / w {
                        let (dst, src) = (x + row * width, row * w);
                        distance[dst..dst + w].copy_from_slice(&tile.distance[src..src + w]);
                        triangle[dst..dst + w].copy_from_slice(&tile.triangle[src..src + w]);
                        if let Some(b) = barycentrics.as_deref_mut() {
                            b[dst..dst + w].copy_from_slice(&tile.barycentrics[src..src + w]);
                        }
                    }
                }
            });
        Ok(stats)
    }

    /// How many of the mesh's triangles cover each pixel's centre in front of the camera
    /// (row-major, row 0 at the top), without depth test: the rasterizer's coverage alone, for
    /// checking its fill rule (a pixel inside one layer of a closed triangulated surface is
    /// covered exactly once).
    pub fn coverage_counts(&self, camera: &Camera, mesh: &IndexedMesh) -> Vec<u32> {
        let (width, height) = (camera.width() as usize, camera.height() as usize);
        let (tiles, _) =
            self.rasterize(camera, mesh, |_, w, h| CountTile { counts: vec![0; w * h], width: w });
        let mut counts = vec![0; width * height];
        for (rect, tile) in tiles {
            for (row, chunk) in tile.counts.chunks_exact(tile.width).enumerate() {
                let dst = rect[0] + (rect[1] + row) * width;
                counts[dst..dst + tile.width].copy_from_slice(chunk);
            }
        }
        counts
    }

    /// Projects, bins and scans `mesh`, each tile into a sink made by `make_sink(tile pixel
    /// origin, tile width, tile height)`; returns the origin and sink of every tile some
    /// triangle reached (the others are left as they are).
    fn rasterize<S: TileSink>(
        &self,
        camera: &Camera,
        mesh: &IndexedMesh,
        make_sink: impl Fn([usize; 2], usize, usize) -> S + Sync,
    ) -> (Vec<([usize; 2], S)>, DrawStats) {
        let projection = ScreenProjection::new(camera);
        let (width, height, size) = (projection.width, projection.height, self.tile_size);
        let (tiles_x, tiles_y) = (width.div_ceil(size), height.div_ceil(size));
        let shift = size.trailing_zeros();
        let (projected, outcodes): (Vec<[f64; 3]>, Vec<u8>) = mesh
            .positions()
            .par_iter()
            .map(|&p| {
                let v = projection.project(p);
                (v, projection.outcode(v))
            })
            .unzip();
        let triangles = mesh.triangles();
        let positions = mesh.positions();
        let cull = self.culling == Culling::BackFaces;
        let corners = |tri: &[u32; 3]| tri.map(|v| projected[v as usize]);

        // Binning: every chunk of triangles fills its own bins, in triangle order.
        let binned: Vec<(Vec<Vec<BinEntry>>, usize)> = triangles
            .par_chunks(BIN_CHUNK)
            .enumerate()
            .map(|(chunk, tris)| {
                let mut bins: Vec<Vec<BinEntry>> = vec![Vec::new(); tiles_x * tiles_y];
                let mut count = 0;
                for (k, tri) in tris.iter().enumerate() {
                    let [a, b, c] = tri.map(|v| outcodes[v as usize]);
                    if a & b & c != 0 {
                        continue;
                    }
                    let projected = corners(tri);
                    // Culled triangles are skipped first (their facing costs less than their
                    // bounds); one spanning several tiles is set up below to skip the tiles
                    // its edges exclude.
                    if cull && is_back_face(&projection, &projected) {
                        continue;
                    }
                    let Some([x0, y0, x1, y1]) = projection.pixel_bounds(&projected) else {
                        continue;
                    };
                    let world = tri.map(|v| positions[v as usize]);
                    let (tx0, ty0, tx1, ty1) = (x0 >> shift, y0 >> shift, x1 >> shift, y1 >> shift);
                    let setup = if tx0 != tx1 || ty0 != ty1 {
                        match TriangleSetup::new(&projection, &projected, &world, cull) {
                            Some(setup) => Some(setup),
                            None => continue,
                        }
                    } else {
                        None
                    };
                    count += 1;
                    let triangle = (chunk * BIN_CHUNK + k) as u32;
                    for ty in ty0..=ty1 {
                        for tx in tx0..=tx1 {
                            let (ox, oy) = (tx * size, ty * size);
                            let rect = [
                                x0.max(ox),
                                y0.max(oy),
                                x1.min(ox + size - 1),
                                y1.min(oy + size - 1),
                            ];
                            let spans_tiles = tx0 != tx1 || ty0 != ty1;
                            if spans_tiles && setup.is_some_and(|s| s.misses_rect(rect)) {
                                continue;
                            }
                            let [a, b, c, d] = rect;
                            let rect = [a - ox, b - oy, c - ox, d - oy].map(|v| v as u8);
                            bins[tx + ty * tiles_x].push(BinEntry { triangle, rect });
                        }
                    }
                }
                (bins, count)
            })
            .collect();
        let triangles_binned = binned.iter().map(|(_, count)| count).sum();
        let bins: Vec<Vec<Vec<BinEntry>>> = binned.into_iter().map(|(bins, _)| bins).collect();

        // Scanning: one worker per tile, triangles in id order.
        let busy: Vec<usize> = (0..tiles_x * tiles_y)
            .filter(|&tile| bins.iter().any(|chunk| !chunk[tile].is_empty()))
            .collect();
        let results: Vec<(([usize; 2], S), usize, usize)> = busy
            .into_par_iter()
            .map(|tile| {
                let (ox, oy) = ((tile % tiles_x) * size, (tile / tiles_x) * size);
                let (tw, th) = (size.min(width - ox), size.min(height - oy));
                let mut sink = make_sink([ox, oy], tw, th);
                let (mut entries, mut fragments) = (0, 0);
                for entry in bins.iter().flat_map(|chunk| &chunk[tile]) {
                    entries += 1;
                    let tri = &triangles[entry.triangle as usize];
                    let world = tri.map(|v| positions[v as usize]);
                    let Some(setup) = TriangleSetup::new(&projection, &corners(tri), &world, false)
                    else {
                        continue;
                    };
                    let [x0, y0, x1, y1] = entry.rect.map(|c| c as usize);
                    let rect = [ox + x0, oy + y0, ox + x1, oy + y1];
                    fragments += setup.scan(&projection, rect, |i, j, distance, edges| {
                        sink.write(i - ox, j - oy, distance, entry.triangle, edges)
                    });
                }
                (([ox, oy], sink), entries, fragments)
            })
            .collect();
        let mut stats = DrawStats { triangles_binned, ..DrawStats::default() };
        let tiles = results
            .into_iter()
            .map(|(tile, entries, fragments)| {
                stats.bin_entries += entries;
                stats.fragments += fragments;
                tile
            })
            .collect();
        (tiles, stats)
    }
}

/// Where a tile's covered pixels go.
trait TileSink: Send {
    /// Pixel (i, j) of the tile is covered by `triangle` at `distance`, its edge functions
    /// `edges` there (see `TriangleSetup::scan`).
    fn write(&mut self, i: usize, j: usize, distance: f32, triangle: u32, edges: [f64; 3]);
}

/// A tile of a [`RasterTarget`], depth-tested.
struct DepthTile {
    distance: Vec<f32>,
    triangle: Vec<u32>,
    /// The barycentrics of corners 1 and 2, when the target keeps them (else empty).
    barycentrics: Vec<[f32; 2]>,
    width: usize,
    id_offset: u32,
}

impl TileSink for DepthTile {
    #[inline(always)]
    fn write(&mut self, i: usize, j: usize, distance: f32, triangle: u32, edges: [f64; 3]) {
        let k = i + j * self.width;
        let id = self.id_offset + triangle;
        let held = self.distance[k];
        if distance < held || (distance == held && id < self.triangle[k]) {
            self.distance[k] = distance;
            self.triangle[k] = id;
            if !self.barycentrics.is_empty() {
                let inverse = 1.0 / (edges[0] + edges[1] + edges[2]);
                self.barycentrics[k] = [(edges[1] * inverse) as f32, (edges[2] * inverse) as f32];
            }
        }
    }
}

/// A tile of coverage counts.
struct CountTile {
    counts: Vec<u32>,
    width: usize,
}

impl TileSink for CountTile {
    #[inline(always)]
    fn write(&mut self, i: usize, j: usize, _distance: f32, _triangle: u32, _edges: [f64; 3]) {
        self.counts[i + j * self.width] += 1;
    }
}
