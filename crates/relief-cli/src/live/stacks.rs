//! A material-stack terrain drawn frame after frame (`relief view --mode mesh`, `relief
//! flythrough --mode mesh`): its LOD mesh for each camera, node meshes kept across frames as
//! Löffler et al. 2011 (section 3.3) keep them, rasterized and shaded as `relief render
//! --mode mesh` does.

use crate::scene::stacks::{self, StacksScene};
use anyhow::Result;
use relief_core::{Aabb, Camera};
use relief_shade::{GBuffer, StacksRenderer};
use relief_viewer::{Cancel, Frame, FrameStats, SceneChoices, SceneRenderer, ViewSettings};
use std::sync::Mutex;

/// A stacks terrain with its renderer (mesher, cache and rasterizer).
pub struct LiveStacks {
    renderer: Mutex<StacksRenderer>,
    bounds: Aabb,
    camera: Camera,
    sun: (f64, f64),
    exposure: f64,
    describe: String,
}

impl LiveStacks {
    /// The terrain of `scene`, drawn with cells of at most `tau_px` pixels, lit by `sun` at
    /// `exposure`.
    pub fn new(scene: StacksScene, tau_px: f64, sun: (f64, f64), exposure: f64) -> Result<Self> {
        let level0 = &scene.mesher.mipmap().levels()[0];
        let describe = format!("{}x{} stacks terrain", level0.width(), level0.height());
        Ok(LiveStacks {
            bounds: scene.bounds,
            camera: scene.camera,
            renderer: Mutex::new(StacksRenderer::new(scene.mesher, tau_px)?),
            sun,
            exposure,
            describe,
        })
    }

    /// The starting camera.
    pub fn camera(&self) -> Camera {
        self.camera
    }

    /// The viewer's starting settings: one way to draw, the command line's sun and exposure.
    pub fn settings(&self) -> ViewSettings {
        let names = SceneChoices { tracers: vec!["mesh".to_string()], ..SceneChoices::default() };
        ViewSettings::new(names, self.sun, self.exposure, false)
    }

    fn render_frame(&self, camera: &Camera, settings: &ViewSettings) -> Result<Frame> {
        let (w, h) = (camera.width(), camera.height());
        let mut gbuffer = GBuffer::new(w as usize, h as usize)?;
        let stats = {
            let mut renderer = self.renderer.lock().expect("no render panicked");
            renderer.render_into(camera, &self.bounds, &mut gbuffer)?
        };
        let sun = (settings.sun_azimuth_deg, settings.sun_elevation_deg);
        let rgb = stacks::shade(&gbuffer, camera, &self.bounds, sun, settings.exposure)?;
        Ok(Frame {
            width: w,
            height: h,
            rgb,
            stats: FrameStats { rays: 0, steps_per_ray: None },
            note: Some(format!(
                "{} nodes ({} meshed), {} triangles; select {:.0} ms, mesh {:.0} ms, append {:.0} \
                 ms, raster {:.0} ms, resolve {:.0} ms",
                stats.mesh.nodes,
                stats.mesh.meshed,
                stats.triangles,
                stats.mesh.select_ms,
                stats.mesh.mesh_ms,
                stats.mesh.join_ms,
                stats.raster_ms,
                stats.resolve_ms
            )),
        })
    }
}

impl SceneRenderer for LiveStacks {
    fn describe(&self) -> String {
        self.describe.clone()
    }

    fn scene_size(&self) -> f64 {
        (self.bounds.max - self.bounds.min).length()
    }

    fn render(
        &self,
        camera: &Camera,
        settings: &ViewSettings,
        _cancel: &Cancel,
    ) -> Result<Frame, String> {
        self.render_frame(camera, settings).map_err(|e| format!("{e:#}"))
    }
}
