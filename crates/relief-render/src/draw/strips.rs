//! A height field drawn by a ray caster (the naive, mipmap and safety tracers), traced and
//! shaded strip by strip with no image-sized G-buffer.

use super::field_picture::{field_stats, FieldCounts};
use super::picture::{ms_since, Picture};
use crate::antialias::{self, Antialiasing};
use crate::error::RenderError;
use crate::progress::Progress;
use crate::scenes::height_field::{check_safety_view, HeightFieldScene};
use relief_core::Camera;
use relief_shade::{
    render_marked_to_srgb8, render_to_srgb8, sun_shadow_sweep, KeptHits, PixelMask, StripTracers,
};
use relief_trace::Tracer;
use serde_json::json;
use std::time::Instant;

/// Draws `scene` from `camera` with its tracer (built now; safety shapes from the cache or
/// precomputed), anti-aliased as `aa` says, keeping the depth and normals `keep` asks for.
pub fn draw(
    scene: &HeightFieldScene,
    camera: &Camera,
    keep: KeptHits,
    aa: Antialiasing,
    progress: &dyn Progress,
) -> Result<Picture, RenderError> {
    let build_started = Instant::now();
    let (surface, choice) = (scene.surface, &scene.choice);
    let built = scene.tracer_spec(choice, surface).build_reporting(&scene.field, progress)?;
    if let Some(safety) = &built.safety {
        check_safety_view(safety, camera, &scene.params)?;
    }
    let notes: Vec<String> = Some(built.note).filter(|n| !n.is_empty()).into_iter().collect();
    let tracer = built.tracer;
    let pixels = camera.width() as usize * camera.height() as usize;
    let sweep = sun_shadow_sweep(tracer.as_ref(), &scene.field, surface, &scene.params, pixels);
    let shadow_tracer: &dyn Tracer = match &sweep {
        Some(sweep) => sweep,
        None => tracer.as_ref(),
    };
    let tracers = StripTracers { primary: tracer.as_ref(), shadow: shadow_tracer };
    let build_ms = ms_since(build_started);
    let mut pass =
        |camera: &Camera, keep: KeptHits, mask: Option<&PixelMask>, progress: &dyn Progress| {
            let (bounds, params) = (&scene.bounds(), &scene.params);
            let drawn = match mask {
                None => {
                    progress
                        .begin("rendering", Some(camera.width() as u64 * camera.height() as u64));
                    let (primary, shadow) = (tracers.primary, tracers.shadow);
                    let advance = |n| progress.advance(n);
                    let drawn =
                        render_to_srgb8(primary, shadow, camera, bounds, params, keep, &advance);
                    progress.end();
                    drawn?
                }
                Some(mask) => {
                    render_marked_to_srgb8(tracers, camera, bounds, params, keep, mask, &|_| {})?
                }
            };
            let stats = &drawn.stats;
            let counts = FieldCounts {
                tracer: choice.to_string(),
                hits: stats.primary.hits,
                shadow_rays: stats.shadow.rays,
                build_ms,
                trace_ms: stats.trace_ms,
                shade_ms: stats.shade_ms,
            };
            let extra = json!({ "mean_steps": stats.primary.mean_steps() });
            let stats = field_stats(scene, camera, &counts, extra);
            Ok(Picture {
                width: camera.width(),
                height: camera.height(),
                rgb: drawn.rgb,
                depth: drawn.depth,
                normals: drawn.normals,
                summary: format!("{surface} {choice} tracer"),
                notes: notes.clone(),
                stats,
            })
        };
    antialias::draw(camera, keep, aa, progress, &mut pass)
}
