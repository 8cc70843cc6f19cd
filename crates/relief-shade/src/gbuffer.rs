//! The G-buffer: what every renderer writes per pixel and the deferred shading pass reads.

use rayon::prelude::*;

use crate::ShadeError;
use relief_core::DVec3;
use relief_trace::Hit;

/// One pixel of a [`GBuffer`]: the first surface seen through it, or a miss.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GBufferPixel {
    /// Distance from the eye to the hit along the pixel's unit ray; `+inf` for a miss.
    pub distance: f32,
    /// World position of the hit.
    pub position: [f32; 3],
    /// Unit world geometric normal of the hit, facing the eye; zeros for a miss.
    pub normal: [f32; 3],
    /// Material weights (`[1, 0, 0, 0]` for a height field hit; zeros for a miss).
    pub material: [f32; 4],
    /// Texture coordinates of the hit over the terrain's world footprint, in `[0, 1]`.
    pub uv: [f32; 2],
    /// World width of the pixel at the hit: `distance * 2 tan(fov / 2) / height`; 0 for a miss.
    pub footprint: f32,
}

impl GBufferPixel {
    /// A pixel that sees no surface.
    pub const MISS: GBufferPixel = GBufferPixel {
        distance: f32::INFINITY,
        position: [0.0; 3],
        normal: [0.0; 3],
        material: [0.0; 4],
        uv: [0.0; 2],
        footprint: 0.0,
    };

    /// The material weights of a height field hit: one material.
    pub const HEIGHT_FIELD_MATERIAL: [f32; 4] = [1.0, 0.0, 0.0, 0.0];

    /// Whether the pixel sees a surface (its distance is finite).
    pub fn is_hit(&self) -> bool {
        self.distance.is_finite()
    }
}

/// Per-pixel surface attributes of a `width x height` image as a struct of arrays.
///
/// Every array is row-major with `width * height` entries, index `i + j * width` for column `i`
/// from the left and row `j` from the top (row 0 is the image's top row).
#[derive(Debug, Clone, PartialEq)]
pub struct GBuffer {
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// Distance from the eye to the hit along the pixel's unit ray; `+inf` for a miss.
    pub distance: Vec<f32>,
    /// World position of the hit.
    pub position: Vec<[f32; 3]>,
    /// Unit world geometric normal; zeros on a miss.
    pub normal: Vec<[f32; 3]>,
    /// Material weights; `[1, 0, 0, 0]` on height field hits, zeros on a miss.
    pub material: Vec<[f32; 4]>,
    /// Texture coordinates over the terrain's world footprint.
    pub uv: Vec<[f32; 2]>,
    /// World width of the pixel at the hit.
    pub footprint: Vec<f32>,
    /// Each pixel's hit in full precision ([`GBuffer::EXACT_MISS`], `t = +inf`, for a miss),
    /// for shading that continues rays from it and must not move their origins (the MLHM
    /// renderer's water and shadow rays); `None` unless a renderer that keeps it fills it
    /// ([`GBuffer::keep_exact_hits`]). Read it with [`GBuffer::exact_hit`].
    pub exact_hits: Option<Vec<Hit>>,
}

impl GBuffer {
    /// A `width x height` G-buffer in which every pixel is a miss.
    ///
    /// Fails when the size is zero or the buffer cannot be allocated.
    pub fn new(width: usize, height: usize) -> Result<Self, ShadeError> {
        if width == 0 || height == 0 {
            return Err(ShadeError::parameter(
                "G-buffer size",
                format!("{width} x {height} has no pixels"),
            ));
        }
        let n = width.checked_mul(height).ok_or_else(|| {
            ShadeError::Limits(format!("a {width} x {height} G-buffer has too many pixels"))
        })?;
        let m = GBufferPixel::MISS;
        Ok(GBuffer {
            width,
            height,
            distance: filled(n, m.distance)?,
            position: filled(n, m.position)?,
            normal: filled(n, m.normal)?,
            material: filled(n, m.material)?,
            uv: filled(n, m.uv)?,
            footprint: filled(n, m.footprint)?,
            exact_hits: None,
        })
    }

    /// A miss in [`GBuffer::exact_hits`].
    pub const EXACT_MISS: Hit =
        Hit { t: f64::INFINITY, position: DVec3::ZERO, normal: DVec3::ZERO };

    /// Gives the buffer a plane of full-precision hits (all misses), unless it has one.
    ///
    /// Fails when the plane cannot be allocated.
    pub fn keep_exact_hits(&mut self) -> Result<(), ShadeError> {
        if self.exact_hits.is_none() {
            let plane = image_plane(self.len(), Self::EXACT_MISS, "G-buffer's exact hits")?;
            self.exact_hits = Some(plane);
        }
        Ok(())
    }

    /// The full-precision hit of the pixel at `index`: `None` for a miss, past the end, or
    /// when the buffer keeps no exact hits.
    pub fn exact_hit(&self, index: usize) -> Option<Hit> {
        let hit = *self.exact_hits.as_ref()?.get(index)?;
        hit.t.is_finite().then_some(hit)
    }

    /// Number of pixels, `width * height`.
    pub fn len(&self) -> usize {
        self.width * self.height
    }

    /// Whether the buffer has no pixels (never true for a buffer from [`GBuffer::new`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Checks that every array holds `width * height` entries (the fields are public, so a
    /// buffer assembled by hand may not).
    pub fn validate(&self) -> Result<(), ShadeError> {
        let n = self.width.checked_mul(self.height).ok_or_else(|| {
            ShadeError::Mismatch(format!("{} x {} overflows", self.width, self.height))
        })?;
        let lengths = [
            ("distance", self.distance.len()),
            ("position", self.position.len()),
            ("normal", self.normal.len()),
            ("material", self.material.len()),
            ("uv", self.uv.len()),
            ("footprint", self.footprint.len()),
            ("exact hits", self.exact_hits.as_ref().map_or(n, Vec::len)),
        ];
        for (name, len) in lengths {
            if len != n {
                return Err(ShadeError::Mismatch(format!(
                    "G-buffer {name} has {len} entries, {} x {} needs {n}",
                    self.width, self.height
                )));
            }
        }
        Ok(())
    }

    /// [`validate`](Self::validate)s the buffer and checks that it is `camera`'s image size,
    /// as a renderer needs before it overwrites every pixel.
    pub fn validate_for(&self, camera: &relief_core::Camera) -> Result<(), ShadeError> {
        self.validate()?;
        let (width, height) = (camera.width() as usize, camera.height() as usize);
        if (self.width, self.height) != (width, height) {
            return Err(ShadeError::Mismatch(format!(
                "G-buffer is {} x {} but the camera's image is {width} x {height}",
                self.width, self.height
            )));
        }
        Ok(())
    }

    /// The pixel at `index` (`i + j * width`), or `None` past the end.
    pub fn pixel(&self, index: usize) -> Option<GBufferPixel> {
        Some(GBufferPixel {
            distance: *self.distance.get(index)?,
            position: *self.position.get(index)?,
            normal: *self.normal.get(index)?,
            material: *self.material.get(index)?,
            uv: *self.uv.get(index)?,
            footprint: *self.footprint.get(index)?,
        })
    }

    /// Writes `pixel` at `index` (`i + j * width`).
    pub fn set_pixel(&mut self, index: usize, pixel: &GBufferPixel) -> Result<(), ShadeError> {
        self.validate()?;
        if index >= self.len() {
            return Err(ShadeError::parameter(
                "pixel index",
                format!("{index} is past the {} pixels of the G-buffer", self.len()),
            ));
        }
        self.distance[index] = pixel.distance;
        self.position[index] = pixel.position;
        self.normal[index] = pixel.normal;
        self.material[index] = pixel.material;
        self.uv[index] = pixel.uv;
        self.footprint[index] = pixel.footprint;
        Ok(())
    }

    /// The depth image in `(H, W)` order, row 0 the top row (`+inf` for misses), as the `.npy`
    /// depth output stores it.
    pub fn depth_hw(&self) -> Vec<f32> {
        self.distance.clone()
    }

    /// The normals as a flat `(H, W, 3)` array, row 0 the top row.
    pub fn normals_hw3(&self) -> Vec<f32> {
        self.normal.iter().flatten().copied().collect()
    }
}

/// Consecutive whole rows of a [`GBuffer`], borrowed mutably: a strip that one worker fills.
pub(crate) struct GBufferRows<'a> {
    pub(crate) distance: &'a mut [f32],
    pub(crate) position: &'a mut [[f32; 3]],
    pub(crate) normal: &'a mut [[f32; 3]],
    pub(crate) material: &'a mut [[f32; 4]],
    pub(crate) uv: &'a mut [[f32; 2]],
    pub(crate) footprint: &'a mut [f32],
}

impl GBufferRows<'_> {
    /// Writes `pixel` at `k`, counted from the strip's first pixel.
    #[inline]
    pub(crate) fn set(&mut self, k: usize, pixel: &GBufferPixel) {
        self.distance[k] = pixel.distance;
        self.position[k] = pixel.position;
        self.normal[k] = pixel.normal;
        self.material[k] = pixel.material;
        self.uv[k] = pixel.uv;
        self.footprint[k] = pixel.footprint;
    }

    /// Pixels in the strip.
    pub(crate) fn len(&self) -> usize {
        self.distance.len()
    }
}

impl GBuffer {
    /// The first `rows` rows (at most the buffer's).
    pub(crate) fn rows_mut(&mut self, rows: usize) -> GBufferRows<'_> {
        let n = rows * self.width;
        GBufferRows {
            distance: &mut self.distance[..n],
            position: &mut self.position[..n],
            normal: &mut self.normal[..n],
            material: &mut self.material[..n],
            uv: &mut self.uv[..n],
            footprint: &mut self.footprint[..n],
        }
    }

    /// The buffer cut into strips of `rows` rows (the last may be shorter), top to bottom, to
    /// fill in parallel. The buffer must be [`validate`](Self::validate)d.
    pub(crate) fn strips_mut(
        &mut self,
        rows: usize,
    ) -> impl IndexedParallelIterator<Item = GBufferRows<'_>> {
        let n = rows * self.width;
        self.distance
            .par_chunks_mut(n)
            .zip(self.position.par_chunks_mut(n))
            .zip(self.normal.par_chunks_mut(n))
            .zip(self.material.par_chunks_mut(n))
            .zip(self.uv.par_chunks_mut(n))
            .zip(self.footprint.par_chunks_mut(n))
            .map(|(((((distance, position), normal), material), uv), footprint)| GBufferRows {
                distance,
                position,
                normal,
                material,
                uv,
                footprint,
            })
    }
}

/// A vector of `n` copies of `value`, or an error when it cannot be allocated.
fn filled<T: Copy>(n: usize, value: T) -> Result<Vec<T>, ShadeError> {
    image_plane(n, value, "G-buffer plane")
}

/// `n` copies of `value`, or an error naming `what` when they cannot be allocated.
pub(crate) fn image_plane<T: Copy>(n: usize, value: T, what: &str) -> Result<Vec<T>, ShadeError> {
    let mut plane = Vec::new();
    plane.try_reserve_exact(n).map_err(|e| {
        ShadeError::Limits(format!("cannot allocate the {what} of {n} pixels: {e}"))
    })?;
    plane.resize(n, value);
    Ok(plane)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn new_buffer_is_all_misses_and_pixels_round_trip() {
        let mut g = GBuffer::new(3, 2).unwrap();
        assert_eq!(g.len(), 6);
        assert!((0..6).all(|k| g.pixel(k) == Some(GBufferPixel::MISS)));
        let p = GBufferPixel {
            distance: 2.5,
            position: [1.0, 2.0, 3.0],
            normal: [0.0, 0.0, 1.0],
            material: GBufferPixel::HEIGHT_FIELD_MATERIAL,
            uv: [0.25, 0.75],
            footprint: 0.1,
        };
        g.set_pixel(4, &p).unwrap();
        assert_eq!(g.pixel(4), Some(p));
        assert_eq!(g.depth_hw()[4], 2.5);
        assert_eq!(&g.normals_hw3()[12..15], &[0.0, 0.0, 1.0]);
        assert!(g.set_pixel(6, &p).is_err());
        assert_eq!(g.pixel(6), None);
    }

    #[test]
    fn refuses_empty_and_inconsistent_buffers() {
        assert!(GBuffer::new(0, 4).is_err());
        let mut g = GBuffer::new(2, 2).unwrap();
        g.uv.pop();
        assert!(matches!(g.validate(), Err(ShadeError::Mismatch(_))));
        let mut g = GBuffer::new(2, 2).unwrap();
        g.keep_exact_hits().unwrap();
        assert_eq!(g.exact_hits.as_ref().map(Vec::len), Some(4));
        assert_eq!(g.exact_hit(1), None);
        let hit = Hit { t: 2.0, position: DVec3::X, normal: DVec3::Z };
        g.exact_hits.as_mut().unwrap()[1] = hit;
        assert_eq!((g.exact_hit(1), g.exact_hit(4)), (Some(hit), None));
        g.exact_hits.as_mut().unwrap().pop();
        assert!(matches!(g.validate(), Err(ShadeError::Mismatch(_))));
    }
}
