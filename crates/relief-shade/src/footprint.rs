//! A G-buffer is the frame a pixel's ground footprint is computed from: its distances and
//! normals, as [`relief_core::texture::PixelHits`] reads them (the footprint itself, and the
//! texture filter over it, live in relief-core's `texture` module, which relief-tiles shares).

use relief_core::texture::PixelHits;
use relief_core::DVec3;

use crate::GBuffer;

impl PixelHits for GBuffer {
    fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    fn hit_distance(&self, i: u32, j: u32) -> Option<f32> {
        self.distance.get(i as usize + j as usize * self.width).copied()
    }

    fn hit_normal(&self, i: u32, j: u32) -> DVec3 {
        DVec3::from(self.normal[i as usize + j as usize * self.width].map(f64::from))
    }
}
