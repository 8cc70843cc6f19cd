//! The MLHM renderer's visibility pass: each camera ray's first surface (solids and water, or
//! solids and air for a ray starting under water) of a box or smooth MLHM tracer, written into
//! the G-buffer with its full-precision hit for the deferred MLHM lighting
//! ([`super::shade_mlhm`]).

use crate::{
    GBuffer, GBufferPixel, PixelMask, Renderer, ShadeError, StageTimings, TraceStats, TILE_SIZE,
};
use rayon::prelude::*;
use relief_core::{Camera, DVec2, Ray};
use relief_trace::{Medium, MlhmHit, MlhmMaterial, MlhmMode, MlhmTracer};

/// The MLHM renderer of one tracer (boxes or a smooth surface: any [`MlhmTracer`]).
pub struct MlhmRenderer<'a> {
    tracer: &'a dyn MlhmTracer,
    /// The pixels traced, where not all ([`MlhmRenderer::marked`]).
    mask: Option<&'a PixelMask>,
    stats: TraceStats,
}

impl<'a> MlhmRenderer<'a> {
    /// The renderer of the MLHM `tracer` traces.
    pub fn new(tracer: &'a dyn MlhmTracer) -> Self {
        MlhmRenderer { tracer, mask: None, stats: TraceStats::default() }
    }

    /// The renderer tracing only the pixels `mask` marks, leaving the others as they were.
    pub fn marked(self, mask: &'a PixelMask) -> Self {
        MlhmRenderer { mask: Some(mask), ..self }
    }

    /// The pixels it traces, where not all.
    pub fn mask(&self) -> Option<&'a PixelMask> {
        self.mask
    }

    /// The camera rays of the last frame.
    pub fn last_stats(&self) -> TraceStats {
        self.stats
    }

    /// Traces every camera ray of `camera` into `gbuffer` (every pixel overwritten, and its
    /// exact hits kept, [`GBuffer::keep_exact_hits`]): distance, position, normal, material
    /// weights (bedrock, sand, water and air, one-hot), texture coordinates over the map's
    /// footprint, pixel footprint. Strips of [`TILE_SIZE`] rows are traced in parallel, tile
    /// by tile; `progress` gets the pixels of each finished tile. Returns the camera rays'
    /// counts.
    ///
    /// Fails when the G-buffer's size is not the camera's image size or its exact hits cannot
    /// be allocated.
    pub fn render_into(
        &mut self,
        camera: &Camera,
        gbuffer: &mut GBuffer,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<TraceStats, ShadeError> {
        gbuffer.validate_for(camera)?;
        if self.mask.is_some_and(|m| !m.fits(gbuffer.width, gbuffer.height)) {
            return Err(ShadeError::Limits("the mask is not of the picture's size".into()));
        }
        gbuffer.keep_exact_hits()?;
        let width = gbuffer.width;
        let Some(mut exact) = gbuffer.exact_hits.take() else {
            return Err(ShadeError::Limits("the G-buffer keeps no exact hits".into()));
        };
        let encoder = MlhmEncoder::new(self.tracer, camera);
        let stats = gbuffer
            .strips_mut(TILE_SIZE)
            .zip(exact.par_chunks_mut(TILE_SIZE * width))
            .enumerate()
            .map(|(s, (mut strip, exact))| {
                let mut stats = TraceStats::default();
                let rows = strip.len() / width;
                for tile_x in (0..width).step_by(TILE_SIZE) {
                    let cols = tile_x..(tile_x + TILE_SIZE).min(width);
                    for r in 0..rows {
                        for i in cols.clone() {
                            let j = s * TILE_SIZE + r;
                            // A pixel the mask leaves out is not drawn: nothing reads it.
                            if self.mask.is_some_and(|m| !m.contains(i, j)) {
                                continue;
                            }
                            // (i, j) lies inside the camera's u32 image.
                            let ray = camera.ray(i as u32, j as u32);
                            let in_water =
                                matches!(self.tracer.medium(ray.origin), Medium::Water { .. });
                            let hit = trace_visible(self.tracer, &ray, in_water, &mut stats);
                            strip.set(i + r * width, &encoder.pixel(hit.as_ref()));
                            exact[i + r * width] = hit.map_or(GBuffer::EXACT_MISS, |h| h.hit);
                        }
                    }
                    progress((cols.len() * rows) as u64);
                }
                stats
            })
            .reduce(TraceStats::default, TraceStats::merge);
        gbuffer.exact_hits = Some(exact);
        self.stats = stats;
        Ok(stats)
    }
}

impl Renderer for MlhmRenderer<'_> {
    /// One stage, `trace`.
    fn render_frame(
        &mut self,
        camera: &Camera,
        gbuffer: &mut GBuffer,
    ) -> Result<StageTimings, ShadeError> {
        let mut timings = StageTimings::new();
        timings.time("trace", || self.render_into(camera, gbuffer, &|_| {}))?;
        Ok(timings)
    }
}

/// The first hit of `ray` with what stops it: solids and water from air, solids and air from
/// inside water; counted in `stats`.
pub(super) fn trace_visible(
    tracer: &dyn MlhmTracer,
    ray: &Ray,
    in_water: bool,
    stats: &mut TraceStats,
) -> Option<MlhmHit> {
    let mode = if in_water { MlhmMode::SolidsAir } else { MlhmMode::SolidsWater };
    let mut steps = 0;
    let hit = tracer.intersect_mode_counted(ray, mode, &mut steps);
    stats.record(steps, hit.is_some());
    hit
}

/// The order of the materials in the G-buffer's weights.
const MATERIALS: [MlhmMaterial; 4] =
    [MlhmMaterial::Bedrock, MlhmMaterial::Sand, MlhmMaterial::Water, MlhmMaterial::Air];

/// The one-hot material weights of `material` (bedrock, sand, water, air).
pub(super) fn material_weights(material: MlhmMaterial) -> [f32; 4] {
    let mut weights = [0.0f32; 4];
    if let Some(k) = MATERIALS.iter().position(|&m| m == material) {
        weights[k] = 1.0;
    }
    weights
}

/// The material whose weight is the largest (the first of equals): the inverse of
/// [`material_weights`].
pub(super) fn material_of(weights: [f32; 4]) -> MlhmMaterial {
    let mut best = 0;
    for k in 1..4 {
        if weights[k] > weights[best] {
            best = k;
        }
    }
    MATERIALS[best]
}

/// Turns an MLHM hit into a G-buffer pixel.
struct MlhmEncoder<'a> {
    camera: &'a Camera,
    origin: DVec2,
    size: DVec2,
}

impl<'a> MlhmEncoder<'a> {
    fn new(tracer: &dyn MlhmTracer, camera: &'a Camera) -> Self {
        let map = tracer.map();
        let size = DVec2::new(map.width() as f64, map.height() as f64) * map.cell_size();
        MlhmEncoder { camera, origin: tracer.origin(), size }
    }

    fn pixel(&self, hit: Option<&MlhmHit>) -> GBufferPixel {
        let Some(h) = hit else { return GBufferPixel::MISS };
        let uv =
            ((h.hit.position.truncate() - self.origin) / self.size).clamp(DVec2::ZERO, DVec2::ONE);
        GBufferPixel {
            distance: h.hit.t as f32,
            position: h.hit.position.as_vec3().to_array(),
            normal: h.hit.normal.as_vec3().to_array(),
            material: material_weights(h.material),
            uv: uv.as_vec2().to_array(),
            footprint: self.camera.pixel_footprint(h.hit.t) as f32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn materials_round_trip_through_their_weights() {
        for m in MATERIALS {
            assert_eq!(material_of(material_weights(m)), m);
        }
        assert_eq!(material_weights(MlhmMaterial::Water), [0.0, 0.0, 1.0, 0.0]);
    }
}
