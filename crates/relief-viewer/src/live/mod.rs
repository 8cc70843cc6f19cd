//! The scenes the viewer draws frame after frame: [`SceneRenderer`]s over relief-render's
//! scenes, rendering with relief's tracers and shading exactly as `relief render` does (a tile
//! store's tiles streamed for each frame), with the settings the viewer switches at run time,
//! and an MLHM scene's erosion simulation, run as `relief simulate` runs it.

mod drawing;
mod height_field;
mod mlhm;
mod stacks;
mod tiles;
mod tracer_cache;
mod view_shading;

pub use drawing::Drawing;
pub use height_field::LiveHeightField;
pub use mlhm::LiveMlhm;
pub use stacks::LiveStacks;
pub use tiles::LiveTiles;

use crate::{SceneRenderer, ViewSettings};
use relief_render::{Progress, RenderError, Scene};
use std::sync::Arc;

/// A scene ready for the viewer: its renderer, the starting settings, and what building it
/// said (where safety shapes came from, ...).
pub struct LiveScene {
    /// The scene's renderer.
    pub renderer: Arc<dyn SceneRenderer>,
    /// The scene's tracer, surface, light and exposure, as it was opened.
    pub settings: ViewSettings,
    /// Notes for the user, each a line.
    pub notes: Vec<String>,
}

/// The renderer of `scene`, drawn as `relief render` draws it (its safety shapes, if it
/// names the safety tracer, built now, reported to `progress`); an MLHM scene's simulation
/// may run.
pub fn live_scene(scene: Scene, progress: &dyn Progress) -> Result<LiveScene, RenderError> {
    let mut notes = Vec::new();
    let (renderer, settings): (Arc<dyn SceneRenderer>, ViewSettings) = match scene {
        Scene::HeightField(field) => {
            let (live, note) = LiveHeightField::new(field, progress)?;
            notes.extend(note);
            let settings = live.settings();
            (Arc::new(live), settings)
        }
        Scene::Mlhm(layered) => {
            let live = LiveMlhm::new(layered);
            let settings = live.settings();
            (Arc::new(live), settings)
        }
        Scene::Stacks(drawing) => {
            let live = LiveStacks::new(*drawing);
            let settings = live.settings();
            (Arc::new(live), settings)
        }
        Scene::Store(store) => {
            let live = LiveTiles::new(store);
            let settings = live.settings();
            (Arc::new(live), settings)
        }
    };
    Ok(LiveScene { renderer, settings, notes })
}
