//! The binned, tile-parallel CPU rasterizer: triangles are projected and binned into screen
//! tiles in parallel, then every row of tiles is scanned by one worker, tile after tile, each
//! into its own pixels of the target (`tile_scan.rs`, `tile_sinks.rs`), so the image is the
//! same whatever the thread count.

use crate::tile_scan::{scan_tile, BandSink, BinEntry, ScanInput, ScanLanes};
use crate::tile_sinks::{CountBand, DepthBand};
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
    lanes: ScanLanes,
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

impl Default for Rasterizer {
    fn default() -> Self {
        Rasterizer { tile_size: 64, culling: Culling::None, lanes: ScanLanes::fastest() }
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

    /// The same rasterizer testing pixel centres the way `lanes` says (by default the
    /// fastest this processor runs; every way draws the same image). Fails when the
    /// processor lacks it.
    pub fn with_lanes(self, lanes: ScanLanes) -> Result<Self, MeshError> {
        if !lanes.is_available() {
            return Err(MeshError::Parameter {
                name: "lanes",
                reason: format!("this processor does not run {lanes:?}"),
            });
        }
        Ok(Rasterizer { lanes, ..self })
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
        let (width, size) = (target.width, self.tile_size);
        let band = size * width;
        let mut barycentrics = target.barycentrics.chunks_mut(band);
        let bands: Vec<DepthBand> = target
            .distance
            .chunks_mut(band)
            .zip(target.triangle.chunks_mut(band))
            .map(|(distance, triangle)| {
                DepthBand::new(distance, triangle, barycentrics.next(), width, id_offset)
            })
            .collect();
        let stats = self.rasterize(camera, mesh, bands);
        Ok(stats)
    }

    /// How many of the mesh's triangles cover each pixel's centre in front of the camera
    /// (row-major, row 0 at the top), without depth test: the rasterizer's coverage alone, for
    /// checking its fill rule (a pixel inside one layer of a closed triangulated surface is
    /// covered exactly once).
    pub fn coverage_counts(&self, camera: &Camera, mesh: &IndexedMesh) -> Vec<u32> {
        let (width, height) = (camera.width() as usize, camera.height() as usize);
        let mut counts = vec![0; width * height];
        let bands =
            counts.chunks_mut(self.tile_size * width).map(|counts| CountBand { counts, width });
        self.rasterize(camera, mesh, bands.collect());
        counts
    }

    /// Projects, bins and scans `mesh` into `bands`, one per row of tiles from the top: each
    /// tile some triangle reaches is scanned into its band's sink for it (the others are left
    /// as they are).
    fn rasterize<B: BandSink>(
        &self,
        camera: &Camera,
        mesh: &IndexedMesh,
        bands: Vec<B>,
    ) -> DrawStats {
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
                    // Culled triangles are skipped here; one spanning several tiles is set up
                    // below to skip the tiles its edges exclude.
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

        // Scanning: one worker per band of tiles, each tile's triangles in id order.
        let input =
            ScanInput { projection: &projection, triangles, positions, projected: &projected };
        let counts: Vec<(usize, usize)> = bands
            .into_par_iter()
            .enumerate()
            .map(|(ty, mut band)| {
                let (mut scanned, mut fragments) = (0, 0);
                for tx in 0..tiles_x {
                    let tile = tx + ty * tiles_x;
                    if bins.iter().all(|chunk| chunk[tile].is_empty()) {
                        continue;
                    }
                    let (ox, oy) = (tx * size, ty * size);
                    let (tw, th) = (size.min(width - ox), size.min(height - oy));
                    let mut sink = band.tile(&projection, [ox, oy], tw, th);
                    let entries = bins.iter().flat_map(|chunk| &chunk[tile]);
                    let (s, f) = scan_tile(self.lanes, &input, [ox, oy], entries, &mut sink);
                    (scanned, fragments) = (scanned + s, fragments + f);
                }
                (scanned, fragments)
            })
            .collect();
        DrawStats {
            triangles_binned,
            bin_entries: counts.iter().map(|c| c.0).sum(),
            fragments: counts.iter().map(|c| c.1).sum(),
        }
    }
}
