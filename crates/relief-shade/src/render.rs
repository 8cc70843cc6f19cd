//! Primary visibility: traces a camera's rays through a tracer into a G-buffer, tile by tile.

use rayon::prelude::*;
use relief_core::{Aabb, Camera, DVec3, Ray};
use relief_trace::{Hit, Tracer};

use crate::gbuffer::GBufferRows;
use crate::pixel_mask::PixelMask;
use crate::{shadow_ray, Albedo, GBuffer, GBufferPixel, RayBatch, ShadeError, TraceStats};

/// Side of the square image tiles traced as one unit of parallel work, in pixels.
pub const TILE_SIZE: usize = 16;

/// A tile of the image: its top left pixel and its size, clipped to the image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tile {
    /// Column of the top left pixel.
    pub x: usize,
    /// Row of the top left pixel.
    pub y: usize,
    /// Columns of the tile inside the image (up to [`TILE_SIZE`]).
    pub cols: usize,
    /// Rows of the tile inside the image (up to [`TILE_SIZE`]).
    pub rows: usize,
}

impl Tile {
    /// The tile whose top left pixel is `(x, y)`, clipped to a `width x height` image.
    pub fn new(x: usize, y: usize, width: usize, height: usize) -> Tile {
        Tile {
            x,
            y,
            cols: width.saturating_sub(x).min(TILE_SIZE),
            rows: height.saturating_sub(y).min(TILE_SIZE),
        }
    }

    /// The tile's pixels `(column, row)`, in Morton order: every run of 8 is a 4x2 block and
    /// every run of 64 an 8x8 block, so the rays a tracer takes together in a batch's order
    /// stay close.
    pub fn pixels(self) -> impl Iterator<Item = (usize, usize)> + Clone {
        self.offsets().map(move |&(i, j)| (self.x + i as usize, self.y + j as usize))
    }

    /// The offsets of [`MORTON`] that fall inside the image.
    fn offsets(self) -> impl Iterator<Item = &'static (u8, u8)> + Clone {
        MORTON.iter().filter(move |&&(i, j)| (i as usize) < self.cols && (j as usize) < self.rows)
    }

    /// Appends the camera rays of the tile's pixels, in the order of [`Tile::pixels`], to
    /// `rays`: exactly [`Camera::ray`] of each, with the screen coordinates computed once per
    /// column and row.
    pub fn camera_rays(self, camera: &Camera, rays: &mut Vec<Ray>) {
        if self.cols == 0 || self.rows == 0 {
            return;
        }
        let (sx, sy) = self.screen(camera);
        let ray = |&(i, j): &(u8, u8)| camera.ray_through(sx[i as usize], sy[j as usize]);
        if self.cols == TILE_SIZE && self.rows == TILE_SIZE {
            // Whole tiles, most of them, without the per-pixel check.
            rays.extend(MORTON.iter().map(ray));
        } else {
            rays.extend(self.offsets().map(ray));
        }
    }

    /// Appends the [`shadow_ray`] towards `towards_light` of every pixel of the tile that sees
    /// a surface in `gbuffer` (the camera's image), in the order of [`Tile::pixels`], from the
    /// point its camera ray reaches at the stored distance.
    pub fn shadow_rays(
        self,
        camera: &Camera,
        gbuffer: &GBuffer,
        towards_light: DVec3,
        rays: &mut Vec<Ray>,
    ) {
        if self.cols == 0 || self.rows == 0 {
            return;
        }
        let (sx, sy) = self.screen(camera);
        for &(i, j) in self.offsets() {
            let k = self.x + i as usize + (self.y + j as usize) * gbuffer.width;
            let distance = gbuffer.distance[k] as f64;
            if distance.is_finite() {
                let position = camera.ray_through(sx[i as usize], sy[j as usize]).at(distance);
                let normal = DVec3::from_array(gbuffer.normal[k].map(f64::from));
                rays.push(shadow_ray(position, normal, distance, towards_light));
            }
        }
    }

    /// The [`Camera::screen_x`] of the tile's columns and [`Camera::screen_y`] of its rows;
    /// entries past a clipped edge repeat the last column or row (no pixel uses them). The
    /// tile must hold a pixel.
    fn screen(self, camera: &Camera) -> ([f64; TILE_SIZE], [f64; TILE_SIZE]) {
        // Pixels lie in the image, whose size the camera holds as u32.
        let sx = std::array::from_fn(|c| camera.screen_x((self.x + c.min(self.cols - 1)) as u32));
        let sy = std::array::from_fn(|r| camera.screen_y((self.y + r.min(self.rows - 1)) as u32));
        (sx, sy)
    }
}

/// The offsets within a tile in Morton order: the even bits of the index give the column, the
/// odd bits the row (four bits each: the tile is 16 pixels square).
const MORTON: [(u8, u8); TILE_SIZE * TILE_SIZE] = {
    let mut order = [(0, 0); TILE_SIZE * TILE_SIZE];
    let mut k = 0;
    while k < order.len() {
        let (mut i, mut j, mut b) = (0, 0, 0);
        while b < 4 {
            i |= ((k >> (2 * b)) & 1) << b;
            j |= ((k >> (2 * b + 1)) & 1) << b;
            b += 1;
        }
        order[k] = (i as u8, j as u8);
        k += 1;
    }
    order
};
const _: () = assert!(TILE_SIZE == 16, "MORTON spreads four bits per axis");

/// Traces the ray of every pixel of `camera` with `tracer` into a G-buffer.
///
/// `bounds` is the terrain's world bounds (`HeightField::world_bounds` of the traced surface):
/// texture coordinates span its footprint. Strips of [`TILE_SIZE`] rows are traced in parallel,
/// tile by tile, straight into the G-buffer; every pixel is computed on its own, so the result
/// does not depend on the thread count. Each tile's rays go to the tracer as one batch
/// ([`Tracer::intersect_batch`]). `progress` is called from worker threads with the
/// number of pixels of each tile as it finishes. Fails only when the G-buffer cannot be
/// allocated.
///
/// ```
/// use std::sync::Arc;
/// use relief_core::{Camera, GridGeometry, HeightField, Surface};
/// use relief_trace::{build_tracer, TracerKind};
/// let field = Arc::new(HeightField::new(4, 4, vec![1.0; 16], GridGeometry::unit()).unwrap());
/// let bounds = field.world_bounds(Surface::Boxes);
/// let tracer = build_tracer(field, Surface::Boxes, TracerKind::Naive);
/// let camera = Camera::frame(&bounds, 32, 24).unwrap();
/// let (gbuffer, stats) = relief_shade::render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
/// assert_eq!(gbuffer.len(), 32 * 24);
/// assert_eq!(stats.rays, 32 * 24);
/// assert!(stats.hits > 0);
/// ```
pub fn render_gbuffer(
    tracer: &dyn Tracer,
    camera: &Camera,
    bounds: &Aabb,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(GBuffer, TraceStats), ShadeError> {
    let mut gbuffer = GBuffer::new(camera.width() as usize, camera.height() as usize)?;
    let stats = render_gbuffer_into(tracer, camera, bounds, &mut gbuffer, progress)?;
    Ok((gbuffer, stats))
}

/// As [`render_gbuffer`], into an existing G-buffer of the camera's image size (every pixel
/// is overwritten), so that a renderer drawing frame after frame allocates it once.
///
/// Fails when the G-buffer's size is not the camera's image size.
pub fn render_gbuffer_into(
    tracer: &dyn Tracer,
    camera: &Camera,
    bounds: &Aabb,
    gbuffer: &mut GBuffer,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<TraceStats, ShadeError> {
    gbuffer.validate_for(camera)?;
    let encoder = HitEncoder::new(bounds, camera);
    // Strips of TILE_SIZE rows are disjoint slices of every array: each worker writes its own
    // strip in place, tile by tile, so nothing is copied and no pixel depends on the schedule.
    let stats = gbuffer
        .strips_mut(TILE_SIZE)
        .enumerate()
        .map(|(s, mut strip)| {
            trace_strip(tracer, &encoder, s * TILE_SIZE, &mut strip, None, progress)
        })
        .reduce(TraceStats::default, TraceStats::merge);
    Ok(stats)
}

/// Traces the camera rays of the image rows from `top` on that `strip` holds (whole rows of
/// the camera's image, at most [`TILE_SIZE`]) into it, tile by tile, each tile's rays as one
/// batch, calling `progress` with each tile's pixel count. With a `mask`, only its pixels
/// are traced and written.
pub(crate) fn trace_strip(
    tracer: &dyn Tracer,
    encoder: &HitEncoder,
    top: usize,
    strip: &mut GBufferRows,
    mask: Option<&PixelMask>,
    progress: &(dyn Fn(u64) + Sync),
) -> TraceStats {
    let width = encoder.camera.width() as usize;
    let rows = strip.len() / width;
    let mut stats = TraceStats::default();
    let mut batch = RayBatch::default();
    for tile_x in (0..width).step_by(TILE_SIZE) {
        let tile = Tile::new(tile_x, top, width, top + rows);
        batch.clear();
        match mask {
            None => tile.camera_rays(encoder.camera, &mut batch.rays),
            // A tile without a marked pixel is left as it was: nothing reads it.
            Some(mask) if !mask.any_in_tile(tile) => continue,
            // The unmarked pixels of the tile are left as they were: nothing reads them.
            Some(mask) => {
                for (i, j) in tile.pixels().filter(|&(i, j)| mask.contains(i, j)) {
                    // (i, j) lies inside the camera's u32 image.
                    batch.rays.push(encoder.camera.ray(i as u32, j as u32));
                }
            }
        }
        batch.intersect(tracer);
        let traced = tile.pixels().filter(|&(i, j)| mask.is_none_or(|m| m.contains(i, j)));
        for (n, (i, j)) in traced.enumerate() {
            let (hit, steps) = (batch.hits[n], batch.steps[n]);
            stats.record(steps, hit.is_some());
            encoder.write(strip, i + (j - top) * width, hit);
        }
        progress(batch.rays.len() as u64);
    }
    stats
}

/// Writes every pixel of `gbuffer` from `hit_of(index, i, j)`, the hit of pixel (i, j) (index
/// `i + j * width`) seen by `camera`, in parallel by strips of rows: how renderers that find
/// their hits otherwise (rasterized meshes) fill the G-buffer as [`render_gbuffer_into`] does.
pub(crate) fn fill_gbuffer(
    gbuffer: &mut GBuffer,
    camera: &Camera,
    bounds: &Aabb,
    hit_of: impl Fn(usize, u32, u32) -> Option<Hit> + Sync,
) {
    let width = gbuffer.width;
    let encoder = HitEncoder::new(bounds, camera);
    gbuffer.strips_mut(TILE_SIZE).enumerate().for_each(|(s, mut strip)| {
        for k in 0..strip.len() {
            let index = s * TILE_SIZE * width + k;
            let (i, j) = ((index % width) as u32, (index / width) as u32);
            strip.set(k, &encoder.g_buffer_pixel(hit_of(index, i, j)));
        }
    });
}

/// Everything needed to turn one pixel's hit into a G-buffer pixel.
pub(crate) struct HitEncoder<'a> {
    uv: UvMap,
    /// The camera, for the pixel's footprint ([`Camera::pixel_footprint`]).
    pub(crate) camera: &'a Camera,
    /// The channels [`HitEncoder::write`] fills.
    channels: Channels,
}

/// Which channels of a G-buffer a pass fills: every one, or only those the deferred shading
/// of a picture reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Channels {
    /// Every channel, for a G-buffer its caller reads.
    All,
    /// Distance and normal, plus texture coordinates when `uv` and the material when
    /// `material`: what [`crate::ShadingPass`] reads of a strip, the rest left as it was.
    Shaded { uv: bool, material: bool },
}

impl<'a> HitEncoder<'a> {
    /// The encoder of hits seen by `camera`, texture coordinates spanning `bounds`, filling
    /// every channel.
    pub(crate) fn new(bounds: &Aabb, camera: &'a Camera) -> Self {
        HitEncoder { uv: UvMap::new(bounds), camera, channels: Channels::All }
    }

    /// [`HitEncoder::new`] filling only the channels shading with `albedo` reads.
    pub(crate) fn for_shading(bounds: &Aabb, camera: &'a Camera, albedo: &Albedo) -> Self {
        let channels = Channels::Shaded {
            uv: matches!(albedo, Albedo::Texture(_)),
            material: matches!(albedo, Albedo::GBufferColour { .. }),
        };
        HitEncoder { channels, ..HitEncoder::new(bounds, camera) }
    }

    /// Writes the G-buffer pixel of a camera ray's hit (or miss) at `k` of `strip`, the
    /// channels this encoder fills.
    #[inline]
    pub(crate) fn write(&self, strip: &mut GBufferRows, k: usize, hit: Option<Hit>) {
        let Channels::Shaded { uv, material } = self.channels else {
            strip.set(k, &self.g_buffer_pixel(hit));
            return;
        };
        let miss = GBufferPixel::MISS;
        let (distance, normal) = match &hit {
            None => (miss.distance, miss.normal),
            Some(hit) => (hit.t as f32, hit.normal.as_vec3().to_array()),
        };
        strip.distance[k] = distance;
        strip.normal[k] = normal;
        if uv {
            strip.uv[k] = hit.map_or(miss.uv, |hit| self.uv.at(hit.position));
        }
        if material {
            let hit_material = GBufferPixel::HEIGHT_FIELD_MATERIAL;
            strip.material[k] = if hit.is_some() { hit_material } else { miss.material };
        }
    }

    /// The G-buffer pixel of a camera ray's hit (or miss).
    #[inline]
    pub(crate) fn g_buffer_pixel(&self, hit: Option<Hit>) -> GBufferPixel {
        match hit {
            None => GBufferPixel::MISS,
            Some(Hit { t, position, normal }) => GBufferPixel {
                // The camera's directions are unit, so t is the distance from the ray's origin
                // (the eye, or its plane for an orthographic camera).
                distance: t as f32,
                position: position.as_vec3().to_array(),
                normal: normal.as_vec3().to_array(),
                material: GBufferPixel::HEIGHT_FIELD_MATERIAL,
                uv: self.uv.at(position),
                footprint: self.camera.pixel_footprint(t) as f32,
            },
        }
    }
}

/// Maps world (x, y) to texture coordinates over the footprint of a box.
#[derive(Debug, Clone, Copy)]
struct UvMap {
    min: DVec3,
    inv_extent: [Option<f64>; 2],
}

impl UvMap {
    fn new(bounds: &Aabb) -> Self {
        // A flat or invalid extent maps to the middle of the texture instead of dividing by 0.
        let inv = |lo: f64, hi: f64| {
            let extent = hi - lo;
            (extent.is_finite() && extent > 0.0).then(|| 1.0 / extent)
        };
        UvMap {
            min: bounds.min,
            inv_extent: [inv(bounds.min.x, bounds.max.x), inv(bounds.min.y, bounds.max.y)],
        }
    }

    #[inline]
    fn at(&self, p: DVec3) -> [f32; 2] {
        let coord = |x: f64, lo: f64, inv: Option<f64>| inv.map_or(0.5, |s| (x - lo) * s) as f32;
        [coord(p.x, self.min.x, self.inv_extent[0]), coord(p.y, self.min.y, self.inv_extent[1])]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_spans_the_footprint_and_survives_flat_bounds() {
        let b = Aabb::new(DVec3::new(10.0, 20.0, 0.0), DVec3::new(14.0, 22.0, 1.0));
        let map = UvMap::new(&b);
        assert_eq!(map.at(DVec3::new(11.0, 21.5, 0.5)), [0.25, 0.75]);
        let flat = UvMap::new(&Aabb::new(DVec3::ZERO, DVec3::new(0.0, 1.0, 0.0)));
        assert_eq!(flat.at(DVec3::new(0.0, 0.5, 0.0)), [0.5, 0.5]);
    }

    #[test]
    fn tile_camera_rays_are_the_cameras_rays_of_its_pixels() {
        let bounds = Aabb::new(DVec3::ZERO, DVec3::new(50.0, 40.0, 10.0));
        let camera = Camera::frame(&bounds, 37, 21).unwrap();
        // A whole tile, one clipped at the right and bottom edges, and one outside the image.
        for (x, y) in [(16, 0), (32, 16), (48, 32)] {
            let tile = Tile::new(x, y, 37, 21);
            let mut rays = Vec::new();
            tile.camera_rays(&camera, &mut rays);
            let want: Vec<Ray> =
                tile.pixels().map(|(i, j)| camera.ray(i as u32, j as u32)).collect();
            assert_eq!(rays, want, "tile at {x}, {y}");
        }
    }

    #[test]
    fn tile_shadow_rays_start_at_the_hits_of_its_pixels() {
        let bounds = Aabb::new(DVec3::ZERO, DVec3::new(50.0, 40.0, 10.0));
        let camera = Camera::frame(&bounds, 37, 21).unwrap();
        let mut gbuffer = GBuffer::new(37, 21).unwrap();
        for (k, d) in gbuffer.distance.iter_mut().enumerate() {
            *d = if k % 3 == 0 { f32::INFINITY } else { 10.0 + k as f32 };
        }
        gbuffer.normal.fill([0.0, 0.6, 0.8]);
        let sun = DVec3::new(0.0, 0.0, 1.0);
        for (x, y) in [(16, 0), (32, 16), (48, 32)] {
            let tile = Tile::new(x, y, 37, 21);
            let mut rays = Vec::new();
            tile.shadow_rays(&camera, &gbuffer, sun, &mut rays);
            let want: Vec<Ray> = tile
                .pixels()
                .filter(|&(i, j)| (i + j * 37) % 3 != 0)
                .map(|(i, j)| {
                    let d = gbuffer.distance[i + j * 37] as f64;
                    let at = camera.ray(i as u32, j as u32).at(d);
                    shadow_ray(at, DVec3::new(0.0, 0.6, 0.8).as_vec3().as_dvec3(), d, sun)
                })
                .collect();
            assert_eq!(rays, want, "tile at {x}, {y}");
        }
    }

    #[test]
    fn tile_pixels_cover_the_clipped_tile_once_in_morton_blocks() {
        let all: Vec<_> = Tile::new(32, 16, 100, 100).pixels().collect();
        assert_eq!(all.len(), TILE_SIZE * TILE_SIZE);
        // Eight in a row form a 4x2 block, 64 an 8x8 block.
        for (run, block) in [(8, (4, 2)), (64, (8, 8))] {
            for chunk in all.chunks(run) {
                let (i0, j0) = chunk[0];
                assert!(chunk.iter().all(|&(i, j)| i - i0 < block.0 && j - j0 < block.1));
            }
        }
        // A tile at the image's corner keeps only its pixels inside the image, each once.
        let clipped: Vec<_> = Tile::new(16, 32, 21, 35).pixels().collect();
        let mut sorted = clipped.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), clipped.len());
        assert_eq!(clipped.len(), 5 * 3);
        assert!(clipped.iter().all(|&(i, j)| (16..21).contains(&i) && (32..35).contains(&j)));
    }
}
