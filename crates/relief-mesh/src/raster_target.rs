//! The rasterizer's output: per pixel the distance along its camera ray and the triangle seen.

use rayon::prelude::*;
use relief_core::Camera;

/// Per pixel of a `width x height` image (row-major, row 0 the image's top row): the distance
/// along the pixel's unit camera ray to the nearest surface drawn (`+inf`: nothing drawn) and
/// the id of the triangle that wrote it ([`RasterTarget::NO_TRIANGLE`]: none).
///
/// Several meshes can be drawn into one target: each draw call adds its `id_offset` to the
/// mesh's triangle indices, so the caller knows which mesh a pixel came from.
#[derive(Debug, Clone, PartialEq)]
pub struct RasterTarget {
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// Distance along each pixel's unit camera ray; `+inf` where nothing was drawn.
    pub distance: Vec<f32>,
    /// Id (`id_offset + triangle index`) of the triangle each pixel shows;
    /// [`RasterTarget::NO_TRIANGLE`] where nothing was drawn.
    pub triangle: Vec<u32>,
    /// For a target made by [`RasterTarget::with_barycentrics`] (else empty): where a pixel's
    /// ray meets the triangle it shows, the barycentric coordinates of the triangle's corners
    /// 1 and 2 (corner 0's is one minus their sum), from the rasterizer's edge functions.
    /// Stale where nothing was drawn.
    pub barycentrics: Vec<[f32; 2]>,
}

impl RasterTarget {
    /// The triangle id of a pixel nothing was drawn into.
    pub const NO_TRIANGLE: u32 = u32::MAX;

    /// An empty target of `width x height` pixels.
    pub fn new(width: usize, height: usize) -> Self {
        let n = width * height;
        RasterTarget {
            width,
            height,
            distance: vec![f32::INFINITY; n],
            triangle: vec![Self::NO_TRIANGLE; n],
            barycentrics: Vec::new(),
        }
    }

    /// An empty target of `width x height` pixels that also keeps each pixel's barycentrics.
    pub fn with_barycentrics(width: usize, height: usize) -> Self {
        RasterTarget { barycentrics: vec![[0.0; 2]; width * height], ..Self::new(width, height) }
    }

    /// An empty target of the camera's image size.
    pub fn for_camera(camera: &Camera) -> Self {
        Self::new(camera.width() as usize, camera.height() as usize)
    }

    /// Forgets everything drawn.
    pub fn clear(&mut self) {
        const CHUNK: usize = 1 << 16;
        rayon::join(
            || self.distance.par_chunks_mut(CHUNK).for_each(|d| d.fill(f32::INFINITY)),
            || self.triangle.par_chunks_mut(CHUNK).for_each(|t| t.fill(Self::NO_TRIANGLE)),
        );
    }

    /// The distance and triangle id of pixel (i, j) (column, row from the top), if something
    /// was drawn there.
    pub fn get(&self, i: usize, j: usize) -> Option<(f32, u32)> {
        if i >= self.width || j >= self.height {
            return None;
        }
        let k = i + j * self.width;
        (self.triangle[k] != Self::NO_TRIANGLE).then(|| (self.distance[k], self.triangle[k]))
    }

    /// Whether the buffers hold `width * height` values each (the barycentrics, if kept).
    pub(crate) fn is_consistent(&self) -> bool {
        let n = self.width.checked_mul(self.height);
        n == Some(self.distance.len())
            && n == Some(self.triangle.len())
            && (self.barycentrics.is_empty() || n == Some(self.barycentrics.len()))
    }
}
