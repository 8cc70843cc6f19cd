//! A material-stack terrain drawn frame after frame (`relief view --mode mesh`, `relief
//! flythrough --mode mesh`): its LOD mesh for each camera, node meshes kept across frames as
//! Löffler et al. 2011 (section 3.3) keep them, rasterized and shaded as `relief render
//! --mode mesh` does.

use super::drawing::Drawing;
use crate::{Cancel, Frame, FrameStats, SceneChoices, ViewSettings};
use relief_core::Camera;
use relief_render::{RenderError, StacksDrawing};

/// A stacks terrain with its renderer (mesher, cache and rasterizer).
pub struct LiveStacks {
    drawing: StacksDrawing,
}

impl LiveStacks {
    /// The terrain of `drawing`.
    pub fn new(drawing: StacksDrawing) -> Self {
        LiveStacks { drawing }
    }

    /// The viewer's starting settings: one way to draw, the scene's sun and exposure.
    pub fn settings(&self) -> ViewSettings {
        let names = SceneChoices { tracers: vec!["mesh".to_string()], ..SceneChoices::default() };
        ViewSettings::new(names, self.drawing.sun, self.drawing.exposure, false)
    }
}

impl Drawing for LiveStacks {
    fn describe(&self) -> String {
        self.drawing.describe()
    }

    fn scene_size(&self) -> f64 {
        (self.drawing.bounds.max - self.drawing.bounds.min).length()
    }

    fn draw(
        &self,
        camera: &Camera,
        settings: &ViewSettings,
        _cancel: &Cancel,
    ) -> Result<Frame, RenderError> {
        let (w, h) = (camera.width(), camera.height());
        let sun = (settings.sun_azimuth_deg, settings.sun_elevation_deg);
        let (rgb, stats) = self.drawing.frame_rgb(camera, sun, settings.exposure)?;
        Ok(Frame {
            width: w,
            height: h,
            rgb,
            stats: FrameStats { rays: 0, steps_per_ray: None },
            note: Some(format!(
                "{} nodes ({} meshed, {} waiting), {} triangles; select {:.0} ms, mesh {:.0} ms, append {:.0} \
                 ms, raster {:.0} ms, resolve and shade {:.0} ms",
                stats.mesh.nodes,
                stats.mesh.meshed,
                stats.mesh.waiting,
                stats.triangles,
                stats.mesh.select_ms,
                stats.mesh.mesh_ms,
                stats.mesh.join_ms,
                stats.raster_ms,
                stats.resolve_ms,
            )),
        })
    }
}
