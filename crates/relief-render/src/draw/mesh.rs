//! A material-stack terrain drawn as a mesh: its LOD mesh for each camera rasterized into the
//! G-buffer (node meshes kept across frames, as Löffler et al. 2011, section 3.3, keep them)
//! and shaded by the deferred pass like every other renderer.

use super::picture::{kept_arrays, ms_since, object, Picture};
use crate::error::RenderError;
use crate::options::{LightSettings, DEFAULT_TAU_PX};
use crate::scenes::stacks::StacksScene;
use relief_core::{Aabb, Camera};
use relief_shade::{
    shade_to_srgb8, Albedo, GBuffer, KeptHits, ShadingParams, StacksFrameStats, StacksRenderer, Sun,
};
use relief_trace::adapters::NoOccluders;
use serde_json::json;
use std::sync::Mutex;
use std::time::Instant;

/// A stacks terrain with its renderer (mesher, node cache and rasterizer), its sun and
/// exposure.
pub struct StacksDrawing {
    /// The renderer; frames take turns.
    renderer: Mutex<StacksRenderer>,
    /// A finite box holding the terrain.
    pub bounds: Aabb,
    /// The largest screen-space size of a mesh cell, pixels.
    pub tau_px: f64,
    /// The sun's azimuth and elevation, degrees.
    pub sun: (f64, f64),
    /// Exposure before tone mapping.
    pub exposure: f64,
    describe: String,
    warnings: Vec<String>,
}

/// A frame of a stacks terrain: its G-buffer and what drawing it did.
pub struct StacksFrame {
    /// The rasterized surfaces.
    pub gbuffer: GBuffer,
    /// The mesher's and rasterizer's counts and timings.
    pub stats: StacksFrameStats,
}

impl StacksDrawing {
    /// Draws `scene` with cells of at most `tau_px` pixels (default: 10), lit as `light` says
    /// (no shadows: a mesh has no exact tracer for them).
    pub fn new(
        scene: StacksScene,
        tau_px: Option<f64>,
        light: &LightSettings,
    ) -> Result<Self, RenderError> {
        let tau_px = tau_px.unwrap_or(DEFAULT_TAU_PX);
        let describe = scene.describe();
        Ok(StacksDrawing {
            bounds: scene.bounds,
            renderer: Mutex::new(StacksRenderer::new(scene.mesher, tau_px)?),
            tau_px,
            sun: light.sun,
            exposure: light.exposure,
            describe,
            warnings: scene.warnings,
        })
    }

    /// The drawing with at most `budget` node meshes made a frame beyond those nothing drawn
    /// before stands in for (`None`: every node a frame wants; see
    /// [`relief_mesh::StacksMesher::set_node_budget`]).
    #[must_use]
    pub fn with_node_budget(self, budget: Option<usize>) -> Self {
        self.renderer.lock().expect("no render panicked").set_node_budget(budget);
        self
    }

    /// The scene in a few words.
    pub fn describe(&self) -> String {
        self.describe.clone()
    }

    /// What opening it found that the user should know.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The warning for a `camera` whose eye is inside the terrain, if it is.
    pub fn camera_warning(&self, camera: &Camera) -> Option<String> {
        let renderer = self.renderer.lock().expect("no render panicked");
        crate::warnings::eye_in_stacks(&renderer.mesher().mipmap().levels()[0], camera)
    }

    /// The G-buffer of `camera`'s view.
    pub fn frame(&self, camera: &Camera) -> Result<StacksFrame, RenderError> {
        let mut gbuffer = GBuffer::new(camera.width() as usize, camera.height() as usize)?;
        let mut renderer = self.renderer.lock().expect("no render panicked");
        let stats = renderer.render_into(camera, &self.bounds, &mut gbuffer)?;
        Ok(StacksFrame { gbuffer, stats })
    }

    /// The shaded picture of `camera` (sun at `sun`, `exposure`; see [`StacksDrawing::shade`])
    /// and what drawing it did: a frame of a flight, resolved and shaded strip by strip
    /// without a whole-frame G-buffer (the same pixels; its `resolve_ms` counts the shading).
    pub fn frame_rgb(
        &self,
        camera: &Camera,
        sun: (f64, f64),
        exposure: f64,
    ) -> Result<(Vec<[u8; 3]>, StacksFrameStats), RenderError> {
        let params = self.shading(sun, exposure)?;
        let mut renderer = self.renderer.lock().expect("no render panicked");
        Ok(renderer.render_srgb8(camera, &self.bounds, &params)?)
    }

    /// Shades a frame's `gbuffer` with the deferred pass: the vertex colours as albedo, the
    /// sun at `sun` (azimuth, elevation in degrees), `exposure`; no shadow rays.
    pub fn shade(
        &self,
        gbuffer: &GBuffer,
        camera: &Camera,
        sun: (f64, f64),
        exposure: f64,
    ) -> Result<Vec<[u8; 3]>, RenderError> {
        let params = self.shading(sun, exposure)?;
        Ok(shade_to_srgb8(gbuffer, &NoOccluders, camera, &params)?.0)
    }

    /// The shading of [`StacksDrawing::shade`].
    fn shading(&self, sun: (f64, f64), exposure: f64) -> Result<ShadingParams, RenderError> {
        let mut params = ShadingParams::for_terrain(&self.bounds)?;
        params.sun = Sun { azimuth_deg: sun.0, elevation_deg: sun.1, ..params.sun };
        params.exposure = exposure;
        params.albedo = Albedo::GBufferColour { fallback: [0.3; 3] };
        params.shadows = false;
        Ok(params)
    }

    /// The picture of `camera`, keeping the depth and normals `keep` asks for.
    pub fn draw(&self, camera: &Camera, keep: KeptHits) -> Result<Picture, RenderError> {
        let frame_started = Instant::now();
        let StacksFrame { mut gbuffer, stats: frame } = self.frame(camera)?;
        let frame_ms = ms_since(frame_started);
        let shade_started = Instant::now();
        let rgb = self.shade(&gbuffer, camera, self.sun, self.exposure)?;
        let shade_ms = ms_since(shade_started);
        let (w, h) = (camera.width(), camera.height());
        let summary = format!(
            "stacks mesh of {} octree nodes, {} triangles, tau {} px",
            frame.mesh.nodes, frame.triangles, self.tau_px
        );
        let stats = object(json!({
            "kind": "stacks mesh",
            "width": w,
            "height": h,
            "nodes": frame.mesh.nodes,
            "triangles": frame.triangles,
            "build_ms": frame.mesh_ms,
            "trace_ms": frame.raster_ms + frame.resolve_ms,
            "frame_ms": frame_ms,
            "mesh_ms": frame.mesh_ms,
            "raster_ms": frame.raster_ms,
            "resolve_ms": frame.resolve_ms,
            "shade_ms": shade_ms,
        }));
        let (depth, normals) = kept_arrays(&mut gbuffer, keep);
        Ok(Picture { width: w, height: h, rgb, depth, normals, summary, notes: vec![], stats })
    }
}
