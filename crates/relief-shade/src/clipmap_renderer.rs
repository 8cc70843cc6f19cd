//! Geometry clipmaps (Losasso & Hoppe 2004) drawn into relief's G-buffer: the comparison
//! renderer of the hybrid paper (Ammann et al. 2010, section 5.2). Approximate: its coarser
//! rings stand on averaged samples, so it smooths the relief away from the eye (measure it
//! with `relief compare` against an exact tracer's depth).

use crate::hybrid::mesh_hit;
use crate::render::fill_gbuffer;
use crate::{GBuffer, Renderer, ShadeError, StageTimings};
use relief_core::{Aabb, Camera, HeightField, SampleRegion, Surface};
use relief_mesh::{Clipmap, ClipmapParams, RasterTarget, Rasterizer};
use relief_trace::{MipmapTracer, Tracer};
use std::sync::Arc;
use std::time::Instant;

/// Counts and stage timings of one clipmap frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ClipmapStats {
    /// Triangles of the frame's rings.
    pub triangles: usize,
    /// Milliseconds building the rings' mesh for the camera.
    pub mesh_ms: f64,
    /// Milliseconds rasterizing it.
    pub raster_ms: f64,
    /// Milliseconds writing the G-buffer.
    pub resolve_ms: f64,
}

impl ClipmapStats {
    /// The frame's stages: `mesh`, `raster`, `resolve`.
    pub fn timings(&self) -> StageTimings {
        let mut timings = StageTimings::new();
        timings.push("mesh", self.mesh_ms);
        timings.push("raster", self.raster_ms);
        timings.push("resolve", self.resolve_ms);
        timings
    }
}

/// The clipmap renderer of one height field: its height pyramid, and the exact tracer of the
/// `triangles` surface for shadow rays.
pub struct ClipmapRenderer {
    clipmap: Clipmap,
    exact: MipmapTracer,
    rasterizer: Rasterizer,
    target: RasterTarget,
}

impl ClipmapRenderer {
    /// The clipmap of `field` with `params` (the paper's: n = 511, 11 levels, transition
    /// n / 10, by default); builds the height pyramid and the exact tracer's.
    pub fn new(field: Arc<HeightField>, params: ClipmapParams) -> Result<Self, ShadeError> {
        let clipmap = Clipmap::new(&field, params)
            .map_err(|e| ShadeError::parameter("clipmap parameters", e.to_string()))?;
        Ok(ClipmapRenderer {
            clipmap,
            exact: MipmapTracer::new(field, Surface::Triangles),
            rasterizer: Rasterizer::new(),
            target: RasterTarget::new(0, 0),
        })
    }

    /// The exact tracer of the same terrain (for shadow rays).
    pub fn tracer(&self) -> &dyn Tracer {
        &self.exact
    }

    /// Takes `region` of the field again after an edit (its pyramid and the exact tracer's).
    pub fn edit(
        &mut self,
        edit: impl FnOnce(&mut HeightField) -> Result<SampleRegion, relief_core::CoreError>,
    ) -> Result<SampleRegion, ShadeError> {
        let region = self.exact.edit(edit).map_err(|e| ShadeError::Mismatch(e.to_string()))?;
        self.clipmap
            .update(self.exact.field(), region)
            .map_err(|e| ShadeError::Mismatch(e.to_string()))?;
        Ok(region)
    }

    /// Renders the view of `camera` into `gbuffer` (every pixel overwritten); `bounds` the box
    /// the texture coordinates span. Fails when the G-buffer's size is not the camera's.
    pub fn render_into(
        &mut self,
        camera: &Camera,
        bounds: &Aabb,
        gbuffer: &mut GBuffer,
    ) -> Result<ClipmapStats, ShadeError> {
        gbuffer.validate_for(camera)?;
        let (width, height) = (gbuffer.width, gbuffer.height);
        let mut stats = ClipmapStats::default();
        let start = Instant::now();
        let mesh = self.clipmap.mesh(camera);
        stats.triangles = mesh.triangle_count();
        stats.mesh_ms = start.elapsed().as_secs_f64() * 1e3;

        let start = Instant::now();
        if (self.target.width, self.target.height) != (width, height) {
            self.target = RasterTarget::for_camera(camera);
        } else {
            self.target.clear();
        }
        self.rasterizer
            .draw(camera, &mesh, 0, &mut self.target)
            .map_err(|e| ShadeError::Limits(e.to_string()))?;
        stats.raster_ms = start.elapsed().as_secs_f64() * 1e3;

        let start = Instant::now();
        let target = &self.target;
        fill_gbuffer(gbuffer, camera, bounds, |index, i, j| match target.triangle[index] {
            RasterTarget::NO_TRIANGLE => None,
            triangle => mesh_hit(&mesh, triangle, &camera.ray(i, j)),
        });
        stats.resolve_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(stats)
    }
}

impl Renderer for ClipmapRenderer {
    /// [`ClipmapRenderer::render_into`], texture coordinates spanning the field's world
    /// bounds.
    fn render_frame(
        &mut self,
        camera: &Camera,
        gbuffer: &mut GBuffer,
    ) -> Result<StageTimings, ShadeError> {
        let bounds = self.exact.field().world_bounds(Surface::Triangles);
        Ok(self.render_into(camera, &bounds, gbuffer)?.timings())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::{DVec3, GridGeometry};

    #[test]
    fn a_flat_field_is_drawn_where_the_exact_tracer_sees_it() {
        let field =
            Arc::new(HeightField::new(64, 64, vec![2.0; 64 * 64], GridGeometry::unit()).unwrap());
        let params = ClipmapParams { ring_vertices: 15, levels: 4, transition: 2 };
        let mut clipmap = ClipmapRenderer::new(field.clone(), params).unwrap();
        let camera = Camera::look_at(
            DVec3::new(10.0, 12.0, 9.0),
            DVec3::new(40.0, 50.0, 2.0),
            DVec3::Z,
            60.0,
            64,
            40,
        )
        .unwrap();
        let bounds = field.world_bounds(Surface::Triangles);
        let mut gbuffer = GBuffer::new(64, 40).unwrap();
        clipmap.render_into(&camera, &bounds, &mut gbuffer).unwrap();
        let (reference, _) =
            crate::render_gbuffer(clipmap.tracer(), &camera, &bounds, &|_| {}).unwrap();
        for (k, (a, b)) in gbuffer.distance.iter().zip(&reference.distance).enumerate() {
            assert_eq!(a.is_finite(), b.is_finite(), "pixel {k}: {a} vs {b}");
            if b.is_finite() {
                assert!((a - b).abs() <= 1e-4 * b, "pixel {k}: {a} vs {b}");
            }
        }
    }
}
