//! A height field drawn by geometry clipmaps (n = 511, 11 levels, as the hybrid paper
//! compares them), then shaded as every renderer is (shadow rays by the exact tracer).

use super::field_picture::{shade_drawn, DrawnGBuffer};
use super::picture::{ms_since, Picture};
use crate::error::RenderError;
use crate::scenes::height_field::HeightFieldScene;
use relief_core::{Camera, Surface};
use relief_mesh::ClipmapParams;
use relief_shade::{ClipmapRenderer, GBuffer, KeptHits};
use serde_json::json;
use std::time::Instant;

/// Draws `scene` from `camera` with geometry clipmaps, keeping the depth and normals `keep`
/// asks for. Clipmaps draw the triangles surface only.
pub fn draw(
    scene: &HeightFieldScene,
    camera: &Camera,
    keep: KeptHits,
) -> Result<Picture, RenderError> {
    if scene.surface == Surface::Boxes {
        return Err(RenderError::Unsupported(
            "geometry clipmaps draw the triangles surface only (use --surface triangles)".into(),
        ));
    }
    let build_started = Instant::now();
    let mut renderer = ClipmapRenderer::new(scene.field.clone(), ClipmapParams::default())?;
    let build_ms = ms_since(build_started);

    let trace_started = Instant::now();
    let mut gbuffer = GBuffer::new(camera.width() as usize, camera.height() as usize)?;
    let frame = renderer.render_into(camera, &scene.bounds(), &mut gbuffer)?;
    let trace_ms = ms_since(trace_started);

    let summary = format!("geometry clipmaps: {} triangles", frame.triangles);
    let extra = json!({
        "triangles": frame.triangles,
        "mesh_ms": frame.mesh_ms,
        "raster_ms": frame.raster_ms,
        "resolve_ms": frame.resolve_ms,
    });
    let drawn = DrawnGBuffer {
        gbuffer,
        shadow_tracer: renderer.tracer(),
        tracer: "clipmap",
        build_ms,
        trace_ms,
    };
    shade_drawn(scene, camera, drawn, keep, |_| {}, summary, extra)
}
