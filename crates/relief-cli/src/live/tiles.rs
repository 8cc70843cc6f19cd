//! A tile store (made by `relief tile`) drawn frame after frame (`relief view STORE`): one
//! streamer (cache and loader) for the whole session, each frame waiting for the tiles its
//! error bound asks for and drawn as `relief render STORE` draws its picture.

use anyhow::Result;
use relief_core::Camera;
use relief_render::draw::store::frame;
use relief_render::StoreScene;
use relief_viewer::{Cancel, Frame, FrameStats, SceneChoices, SceneRenderer, ViewSettings};

/// A tile store with its streamer, shading and starting camera.
pub struct LiveTiles {
    scene: StoreScene,
    camera: Camera,
    describe: String,
}

impl LiveTiles {
    /// The store of `scene`, seen first from `camera`.
    pub fn new(scene: StoreScene, camera: Camera) -> Self {
        let describe = scene.describe();
        LiveTiles { scene, camera, describe }
    }

    /// The starting camera.
    pub fn camera(&self) -> Camera {
        self.camera
    }

    /// The viewer's starting settings: one way to draw (the store's surface), the command
    /// line's sun, exposure and shadows.
    pub fn settings(&self) -> ViewSettings {
        let names = SceneChoices { tracers: vec!["tiles".to_string()], ..SceneChoices::default() };
        let params = &self.scene.params;
        let sun = (params.sun.azimuth_deg, params.sun.elevation_deg);
        ViewSettings::new(names, sun, params.exposure, params.shadows)
    }

    fn render_frame(&self, camera: &Camera, settings: &ViewSettings) -> Result<Frame> {
        let scene = &self.scene;
        let mut params = scene.params.clone();
        super::apply_view_settings(&mut params, settings);
        // Every frame waits for its tiles, so that a view at rest is drawn from the tiles its
        // error bound asks for (shadow rays reach tiles outside the view: no culling then).
        let drawn = frame(scene, camera, &params, true)?;
        let tiles = drawn.tiles;
        let (w, h) = (camera.width(), camera.height());
        Ok(Frame {
            width: w,
            height: h,
            rgb: drawn.rgb,
            stats: FrameStats { rays: drawn.rays, steps_per_ray: Some(drawn.mean_steps) },
            note: Some(format!(
                "{} tiles at <= {:.3} px error, {:.0} ms waiting for tiles",
                tiles.tiles_drawn, tiles.max_error_px, tiles.io_wait_ms
            )),
        })
    }
}

impl SceneRenderer for LiveTiles {
    fn describe(&self) -> String {
        self.describe.clone()
    }

    fn scene_size(&self) -> f64 {
        (self.scene.bounds.max - self.scene.bounds.min).length()
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
