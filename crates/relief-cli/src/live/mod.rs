//! The scenes `relief view` draws frame after frame: [`SceneRenderer`]s over the scenes the command
//! line opens, rendering with relief's tracers and shading exactly as `relief render` does (a tile
//! store's tiles streamed for each frame), with the settings the viewer switches at run time, and
//! an MLHM scene's erosion simulation, run as `relief simulate` runs it.
//!
//! [`SceneRenderer`]: relief_viewer::SceneRenderer

mod height_field;
mod mlhm;
mod simulation;
mod stacks;
mod tiles;

pub use height_field::LiveHeightField;
pub use mlhm::LiveMlhm;
pub use stacks::LiveStacks;
pub use tiles::LiveTiles;

/// `sun` turned to the azimuth and elevation the viewer's `settings` hold.
fn viewer_sun(sun: relief_shade::Sun, settings: &relief_viewer::ViewSettings) -> relief_shade::Sun {
    relief_shade::Sun {
        azimuth_deg: settings.sun_azimuth_deg,
        elevation_deg: settings.sun_elevation_deg,
        ..sun
    }
}

/// `params` with the viewer's sun, shadows and exposure from `settings`.
fn apply_view_settings(
    params: &mut relief_shade::ShadingParams,
    settings: &relief_viewer::ViewSettings,
) {
    params.sun = viewer_sun(params.sun, settings);
    params.shadows = settings.shadows;
    params.exposure = settings.exposure;
}

/// The index of `name` in `names`, or 0.
fn position(names: &[String], name: &str) -> usize {
    names.iter().position(|n| n == name).unwrap_or(0)
}
