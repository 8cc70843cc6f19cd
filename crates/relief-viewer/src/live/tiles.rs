//! A tile store (made by `relief tile`) drawn frame after frame (`relief view STORE`): one
//! streamer (cache and loader) for the whole session, each frame waiting for the tiles its
//! error bound asks for and drawn as `relief render STORE` draws its picture.

use super::drawing::Drawing;
use super::view_shading::apply_view_settings;
use crate::{Cancel, Frame, FrameStats, SceneChoices, ViewSettings};
use relief_core::Camera;
use relief_render::draw::store::frame;
use relief_render::{RenderError, StoreScene};

/// A tile store with its streamer and shading.
pub struct LiveTiles {
    scene: StoreScene,
    describe: String,
}

impl LiveTiles {
    /// The store of `scene`.
    pub fn new(scene: StoreScene) -> Self {
        let describe = scene.describe();
        LiveTiles { scene, describe }
    }

    /// The viewer's starting settings: one way to draw (the store's surface), the scene's
    /// sun, exposure and shadows.
    pub fn settings(&self) -> ViewSettings {
        let names = SceneChoices { tracers: vec!["tiles".to_string()], ..SceneChoices::default() };
        let params = &self.scene.params;
        let sun = (params.sun.azimuth_deg, params.sun.elevation_deg);
        ViewSettings::new(names, sun, params.exposure, params.shadows)
    }
}

impl Drawing for LiveTiles {
    fn describe(&self) -> String {
        self.describe.clone()
    }

    fn scene_size(&self) -> f64 {
        (self.scene.bounds.max - self.scene.bounds.min).length()
    }

    fn draw(
        &self,
        camera: &Camera,
        settings: &ViewSettings,
        _cancel: &Cancel,
    ) -> Result<Frame, RenderError> {
        let mut params = self.scene.params.clone();
        apply_view_settings(&mut params, settings);
        // Every frame waits for its tiles, so that a view at rest is drawn from the tiles its
        // error bound asks for (shadow rays reach tiles outside the view: no culling then).
        let drawn = frame(&self.scene, camera, &params, true)?;
        let tiles = drawn.tiles;
        Ok(Frame {
            width: camera.width(),
            height: camera.height(),
            rgb: drawn.rgb,
            stats: FrameStats { rays: drawn.rays, steps_per_ray: Some(drawn.mean_steps) },
            note: Some(format!(
                "{} tiles at <= {:.3} px error, {:.0} ms waiting for tiles",
                tiles.tiles_drawn, tiles.max_error_px, tiles.io_wait_ms
            )),
        })
    }
}
