//! The end every height-field renderer shares: the G-buffer a renderer drew shaded by the
//! deferred pass, and the statistics every such picture reports.

use super::picture::{kept_arrays, ms_since, object, Picture};
use crate::error::RenderError;
use crate::scenes::height_field::HeightFieldScene;
use relief_core::Camera;
use relief_shade::{shade_to_srgb8, GBuffer, KeptHits};
use relief_trace::Tracer;
use serde_json::{json, Map, Value};
use std::time::Instant;

/// What a height-field picture took and found, for its statistics.
pub(crate) struct FieldCounts {
    /// The tracer's or renderer's name.
    pub tracer: String,
    /// Primary rays that hit.
    pub hits: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
    /// Milliseconds building the renderer, tracing and shading.
    pub build_ms: f64,
    pub trace_ms: f64,
    pub shade_ms: f64,
}

/// The statistics of a height-field picture of `camera`: the keys every renderer has
/// (kind, terrain, surface, tracer, image, rays, hits, shadow rays, stage timings) and those
/// of `extra`.
pub(crate) fn field_stats(
    scene: &HeightFieldScene,
    camera: &Camera,
    counts: &FieldCounts,
    extra: Value,
) -> Map<String, Value> {
    let (w, h) = (camera.width(), camera.height());
    let field = &scene.field;
    let mut stats = object(json!({
        "kind": "height field",
        "terrain": [field.width(), field.height()],
        "surface": scene.surface.to_string(),
        "tracer": counts.tracer,
        "width": w,
        "height": h,
        "threads": rayon::current_num_threads(),
        "rays": u64::from(w) * u64::from(h),
        "hits": counts.hits,
        "shadow_rays": counts.shadow_rays,
        "build_ms": counts.build_ms,
        "trace_ms": counts.trace_ms,
        "shade_ms": counts.shade_ms,
    }));
    stats.extend(object(extra));
    stats
}

/// A renderer's G-buffer of a height field, what drew it and how long that took.
pub(crate) struct DrawnGBuffer<'a> {
    /// The primary hits.
    pub gbuffer: GBuffer,
    /// The exact tracer the shadow rays take.
    pub shadow_tracer: &'a dyn Tracer,
    /// The renderer's name.
    pub tracer: &'static str,
    /// Milliseconds building the renderer and filling the G-buffer.
    pub build_ms: f64,
    pub trace_ms: f64,
}

/// Shades `drawn` (then `recolour`s the pixels, counted in the shading time) into the
/// picture of `camera`, keeping the depth and normals `keep` asks for.
pub(crate) fn shade_drawn(
    scene: &HeightFieldScene,
    camera: &Camera,
    drawn: DrawnGBuffer,
    keep: KeptHits,
    recolour: impl FnOnce(&mut [[u8; 3]]),
    summary: String,
    extra: Value,
) -> Result<Picture, RenderError> {
    let DrawnGBuffer { mut gbuffer, shadow_tracer, tracer, build_ms, trace_ms } = drawn;
    let shade_started = Instant::now();
    let (mut rgb, shadow) = shade_to_srgb8(&gbuffer, shadow_tracer, camera, &scene.params)?;
    recolour(&mut rgb);
    let shade_ms = ms_since(shade_started);
    let hits = gbuffer.distance.iter().filter(|d| d.is_finite()).count() as u64;
    let counts = FieldCounts {
        tracer: tracer.to_string(),
        hits,
        shadow_rays: shadow.rays,
        build_ms,
        trace_ms,
        shade_ms,
    };
    let stats = field_stats(scene, camera, &counts, extra);
    let (depth, normals) = kept_arrays(&mut gbuffer, keep);
    Ok(Picture {
        width: camera.width(),
        height: camera.height(),
        rgb,
        depth,
        normals,
        summary,
        notes: Vec::new(),
        stats,
    })
}
