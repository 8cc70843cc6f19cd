//! Primary visibility: traces a camera's rays through a tracer into a G-buffer, tile by tile.

use rayon::prelude::*;
use relief_core::{Aabb, Camera, DVec3};
use relief_trace::{Hit, Tracer};

use crate::{GBuffer, GBufferPixel, ShadeError, TraceStats};

/// Side of the square image tiles traced as one unit of parallel work, in pixels.
pub const TILE_SIZE: usize = 16;

/// Traces the ray of every pixel of `camera` with `tracer` into a G-buffer.
///
/// `bounds` is the terrain's world bounds (`HeightField::world_bounds` of the traced surface):
/// texture coordinates span its footprint. Tiles of [`TILE_SIZE`]² pixels are traced in
/// parallel and then written in a fixed order, so the result does not depend on the thread
/// count. `progress` is called from worker threads with the number of pixels of each tile as it
/// finishes. Fails only when the G-buffer cannot be allocated.
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
    let (width, height) = (camera.width() as usize, camera.height() as usize);
    let mut gbuffer = GBuffer::new(width, height)?;
    let tiles_x = width.div_ceil(TILE_SIZE);
    let tile_count = tiles_x * height.div_ceil(TILE_SIZE);
    let pixel = PixelTracer {
        tracer,
        camera,
        uv: UvMap::new(bounds),
        footprint_per_distance: 2.0 * (camera.fov_deg().to_radians() / 2.0).tan() / height as f64,
    };
    let tiles: Vec<(Vec<GBufferPixel>, TraceStats)> = (0..tile_count)
        .into_par_iter()
        .map(|k| {
            let (cols, rows) = tile_span(k, tiles_x, width, height);
            let mut stats = TraceStats::default();
            let mut pixels = Vec::with_capacity(cols.len() * rows.len());
            for j in rows {
                for i in cols.clone() {
                    pixels.push(pixel.trace(i, j, &mut stats));
                }
            }
            progress(pixels.len() as u64);
            (pixels, stats)
        })
        .collect();
    let mut stats = TraceStats::default();
    for (k, (pixels, tile_stats)) in tiles.iter().enumerate() {
        let (cols, rows) = tile_span(k, tiles_x, width, height);
        let indices = rows.flat_map(|j| cols.clone().map(move |i| i + j * width));
        for (index, p) in indices.zip(pixels) {
            gbuffer.set_pixel(index, p)?;
        }
        stats = stats.merge(*tile_stats);
    }
    Ok((gbuffer, stats))
}

/// The pixel columns and rows of tile `k` (tiles numbered row-major, `tiles_x` per row).
fn tile_span(
    k: usize,
    tiles_x: usize,
    width: usize,
    height: usize,
) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
    let (tx, ty) = (k % tiles_x, k / tiles_x);
    let cols = tx * TILE_SIZE..((tx + 1) * TILE_SIZE).min(width);
    let rows = ty * TILE_SIZE..((ty + 1) * TILE_SIZE).min(height);
    (cols, rows)
}

/// Everything needed to turn one pixel's ray into a G-buffer pixel.
struct PixelTracer<'a> {
    tracer: &'a dyn Tracer,
    camera: &'a Camera,
    uv: UvMap,
    /// Pixel width at unit distance: `2 tan(fov / 2) / H`.
    footprint_per_distance: f64,
}

impl PixelTracer<'_> {
    /// Traces pixel (i, j) (column from the left, row from the top), counting into `stats`.
    #[inline]
    fn trace(&self, i: usize, j: usize, stats: &mut TraceStats) -> GBufferPixel {
        // i < width and j < height, which the camera holds as u32.
        let ray = self.camera.ray(i as u32, j as u32);
        let mut steps = 0;
        let hit = self.tracer.intersect_counted(&ray, &mut steps);
        stats.record(steps, hit.is_some());
        match hit {
            None => GBufferPixel::MISS,
            Some(Hit { t, position, normal }) => GBufferPixel {
                // The camera's directions are unit, so t is the distance from the eye.
                distance: t as f32,
                position: position.as_vec3().to_array(),
                normal: normal.as_vec3().to_array(),
                material: GBufferPixel::HEIGHT_FIELD_MATERIAL,
                uv: self.uv.at(position),
                footprint: (t * self.footprint_per_distance) as f32,
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
    fn tiles_cover_the_image_once() {
        let (w, h): (usize, usize) = (37, 20);
        let tiles_x = w.div_ceil(TILE_SIZE);
        let mut seen = vec![0u8; w * h];
        for k in 0..tiles_x * h.div_ceil(TILE_SIZE) {
            let (cols, rows) = tile_span(k, tiles_x, w, h);
            for j in rows {
                for i in cols.clone() {
                    seen[i + j * w] += 1;
                }
            }
        }
        assert!(seen.iter().all(|&c| c == 1));
    }

    #[test]
    fn uv_spans_the_footprint_and_survives_flat_bounds() {
        let b = Aabb::new(DVec3::new(10.0, 20.0, 0.0), DVec3::new(14.0, 22.0, 1.0));
        let map = UvMap::new(&b);
        assert_eq!(map.at(DVec3::new(11.0, 21.5, 0.5)), [0.25, 0.75]);
        let flat = UvMap::new(&Aabb::new(DVec3::ZERO, DVec3::new(0.0, 1.0, 0.0)));
        assert_eq!(flat.at(DVec3::new(0.0, 0.5, 0.0)), [0.5, 0.5]);
    }
}
