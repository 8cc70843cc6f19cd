//! A height field drawn by the hybrid renderer (Ammann et al. 2010), the near field
//! rasterized and the far field ray cast, then shaded as every renderer is (shadow rays by
//! the exact tracer).

use super::field_picture::{shade_drawn, DrawnGBuffer};
use super::picture::{ms_since, Picture};
use crate::error::RenderError;
use crate::scenes::height_field::HeightFieldScene;
use relief_core::Camera;
use relief_shade::{GBuffer, HybridRenderer, KeptHits, PixelSource};
use serde_json::json;
use std::time::Instant;

/// Draws `scene` from `camera` with the hybrid renderer (its options the scene's), keeping
/// the depth and normals `keep` asks for.
pub fn draw(
    scene: &HeightFieldScene,
    camera: &Camera,
    keep: KeptHits,
) -> Result<Picture, RenderError> {
    let hybrid = &scene.hybrid;
    let far = hybrid.far.unwrap_or_default();
    let surface = scene.surface;
    let build_started = Instant::now();
    let mut renderer = HybridRenderer::new(scene.field.clone(), surface, hybrid.params, far)?;
    let build_ms = ms_since(build_started);

    let trace_started = Instant::now();
    let mut gbuffer = GBuffer::new(camera.width() as usize, camera.height() as usize)?;
    let mut sources = Vec::new();
    let frame = renderer.render_into(camera, &scene.bounds(), &mut gbuffer, Some(&mut sources))?;
    let trace_ms = ms_since(trace_started);

    let levels = renderer.heuristic().steps().len();
    let recolour = |rgb: &mut [[u8; 3]]| {
        if hybrid.show_lop {
            for (pixel, source) in rgb.iter_mut().zip(&sources) {
                *pixel = tint(*pixel, *source, levels);
            }
        }
    };
    let summary = format!(
        "{surface} hybrid renderer, far field {far}: {} cells meshed, {} ray cast, {} culled",
        frame.mesh_cells,
        frame.ray_cast_cells.iter().sum::<usize>(),
        frame.culled_cells
    );
    let params = hybrid.params;
    let extra = json!({
        "far": far.name(),
        "cell": params.cell,
        "threshold": params.threshold,
        "k": params.k,
        "lop": params.levels,
        "mesh_cells": frame.mesh_cells,
        "ray_cast_cells": frame.ray_cast_cells,
        "culled_cells": frame.culled_cells,
        "triangles": frame.triangles,
        "far_rays": frame.far_rays,
        "heuristic_ms": frame.heuristic_ms,
        "mesh_build_ms": frame.mesh_build_ms,
        "raster_ms": frame.raster_ms,
        "far_ms": frame.far_ms,
        "resolve_ms": frame.resolve_ms,
    });
    let drawn = DrawnGBuffer {
        gbuffer,
        shadow_tracer: renderer.tracer(),
        tracer: "hybrid",
        build_ms,
        trace_ms,
    };
    shade_drawn(scene, camera, drawn, keep, recolour, summary, extra)
}

/// `pixel` half blended with the colour of what drew it (the paper's Figure 1): mesh white,
/// levels of precision from green (the most precise) to red, the exact far field blue; the
/// sky unchanged.
fn tint(pixel: [u8; 3], source: PixelSource, levels: usize) -> [u8; 3] {
    let colour: [f32; 3] = match source {
        PixelSource::Nothing => return pixel,
        PixelSource::Mesh => [255.0, 255.0, 255.0],
        PixelSource::Exact => [40.0, 90.0, 255.0],
        PixelSource::RayCast(level) => {
            let f = level as f32 / (levels.max(2) - 1) as f32;
            [255.0 * f, 255.0 * (1.0 - f), 0.0]
        }
    };
    std::array::from_fn(|c| (0.5 * pixel[c] as f32 + 0.5 * colour[c]).round() as u8)
}
