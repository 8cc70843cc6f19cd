//! An MLHM scene drawn by box ray tracing or smooth-surface ray marching, shaded as the MLHM
//! paper does (Nilles & Müller 2025, sections 4.6 and 5) at a quality preset.

use super::picture::{kept_arrays, ms_since, object, Picture};
use crate::antialias::{self, Antialiasing};
use crate::error::RenderError;
use crate::options::RenderMode;
use crate::progress::Progress;
use crate::scenes::mlhm::{LayeredScene, MlhmTracerChoice};
use relief_core::{Camera, Precision};
use relief_shade::mlhm::{render_mlhm, render_mlhm_marked, MlhmRayCounts, MlhmShading};
use relief_shade::{tonemap_reinhard_to_rgb8, GBuffer, KeptHits, PixelMask};
use relief_trace::MlhmTracer;
use serde_json::json;
use std::time::Instant;

/// Draws `scene` from `camera`, anti-aliased as `aa` says, keeping the depth and normals
/// `keep` asks for.
///
/// The renderer traces and shades each pixel in one pass: the statistics put that pass in
/// `trace_ms` and the tone mapping in `shade_ms`.
pub fn draw(
    scene: &LayeredScene,
    camera: &Camera,
    keep: KeptHits,
    aa: Antialiasing,
    progress: &dyn Progress,
) -> Result<Picture, RenderError> {
    let (mode, choice) = (scene.mode, scene.choice);
    let build_started = Instant::now();
    let tracer = scene.tracer(mode, choice, scene.shading.quality.central_differences)?;
    let build_ms = ms_since(build_started);
    // The anti-aliasing passes draw into one G-buffer, taken back after each.
    let mut spare = None;
    let mut pass = |camera: &Camera, keep, mask: Option<&PixelMask>, progress: &dyn Progress| {
        let pass = MlhmPass { scene, tracer: tracer.as_ref(), build_ms, mask, spare: &mut spare };
        draw_pass(pass, camera, keep, progress)
    };
    antialias::draw(camera, keep, aa, progress, &mut pass)
}

/// What a pass of [`draw`] draws with.
struct MlhmPass<'a> {
    scene: &'a LayeredScene,
    /// The tracer, built in `build_ms`.
    tracer: &'a dyn MlhmTracer,
    build_ms: f64,
    /// The pixels drawn, where not all.
    mask: Option<&'a PixelMask>,
    /// A G-buffer a masked pass draws into and leaves for the next.
    spare: &'a mut Option<GBuffer>,
}

/// One pass of [`draw`]: the whole picture of `camera`, or the pixels its mask marks.
fn draw_pass(
    pass: MlhmPass,
    camera: &Camera,
    keep: KeptHits,
    progress: &dyn Progress,
) -> Result<Picture, RenderError> {
    let MlhmPass { scene, tracer, build_ms, mask, spare } = pass;
    let (mode, choice, shading) = (scene.mode, scene.choice, &scene.shading);
    let (w, h) = (camera.width(), camera.height());
    progress.begin("rendering", Some(w as u64 * h as u64));
    let render_started = Instant::now();
    let advance = |n| progress.advance(n);
    let image = match mask {
        Some(mask) => render_mlhm_marked(tracer, camera, shading, mask, spare.take(), &advance),
        None => render_mlhm(tracer, camera, shading, &advance),
    };
    let render_ms = ms_since(render_started);
    progress.end();
    let mut image = image?;
    let tonemap_started = Instant::now();
    let rgb = tonemap_reinhard_to_rgb8(&image.radiance, shading.exposure)?;
    let shade_ms = ms_since(tonemap_started);
    let how = match choice {
        MlhmTracerChoice::Naive if mode == RenderMode::Smooth => {
            "marching without the hierarchy".to_string()
        }
        MlhmTracerChoice::Naive => "naive tracer".to_string(),
        MlhmTracerChoice::Hierarchy(b, bounds) => {
            let bounds = match bounds {
                Precision::F32 => "f32",
                Precision::F16 => "f16",
            };
            format!(
                "hierarchy tracer, {b} backtracking, {bounds} bounds, built in {build_ms:.1} ms"
            )
        }
    };
    let rays_per_pixel = image.counts.rays() as f64 / (w as f64 * h as f64);
    let steps = image.counts.primary.mean_steps();
    let surface = match mode {
        RenderMode::Boxes => "boxes".to_string(),
        RenderMode::Smooth => format!("a smooth surface (sigma {} m)", scene.sigma_or_cell()),
        RenderMode::Mesh => "a mesh".to_string(),
    };
    let summary = format!(
        "{}x{} MLHM scene as {surface}, preset {}, {how}; rendered in {render_ms:.0} ms, \
         {rays_per_pixel:.2} rays per pixel, {steps:.1} steps per camera ray",
        scene.map.width(),
        scene.map.height(),
        scene.preset
    );
    let primary = &image.counts.primary;
    let stats = object(json!({
        "kind": "mlhm",
        "terrain": [scene.map.width(), scene.map.height()],
        "surface": match mode {
            RenderMode::Boxes => "boxes",
            RenderMode::Smooth => "smooth",
            RenderMode::Mesh => "mesh",
        },
        "tracer": how,
        "preset": scene.preset.to_string(),
        "width": w,
        "height": h,
        "threads": rayon::current_num_threads(),
        "rays": image.counts.rays(),
        "primary_rays": primary.rays,
        "hits": primary.hits,
        "mean_steps": steps,
        "build_ms": build_ms,
        "trace_ms": render_ms,
        "shade_ms": shade_ms,
        "shading_in_trace": true,
    }));
    let (depth, normals) = kept_arrays(&mut image.gbuffer, keep);
    if mask.is_some() {
        *spare = Some(image.gbuffer);
    }
    let rgb = rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    Ok(Picture { width: w, height: h, rgb, depth, normals, summary, notes: vec![], stats })
}

/// A frame of an MLHM scene: its pixels and the rays it took.
pub struct MlhmFrame {
    /// 8-bit sRGB pixels, rows from the top.
    pub rgb: Vec<[u8; 3]>,
    /// The rays traced, primary and secondary.
    pub counts: MlhmRayCounts,
}

/// The frame `tracer` draws of `camera`'s view, shaded with `shading` and tone mapped (what
/// the viewer shows and `relief simulate --frames` writes).
pub fn mlhm_frame(
    tracer: &dyn MlhmTracer,
    camera: &Camera,
    shading: &MlhmShading,
) -> Result<MlhmFrame, RenderError> {
    let image = render_mlhm(tracer, camera, shading, &|_| {})?;
    let rgb = tonemap_reinhard_to_rgb8(&image.radiance, shading.exposure)?;
    let rgb = rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    Ok(MlhmFrame { rgb, counts: image.counts })
}
