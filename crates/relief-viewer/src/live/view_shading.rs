//! The viewer's settings applied to a scene's shading.

use crate::ViewSettings;
use relief_shade::{ShadingParams, Sun};

/// `sun` turned to the azimuth and elevation the viewer's `settings` hold.
pub fn viewer_sun(sun: Sun, settings: &ViewSettings) -> Sun {
    Sun { azimuth_deg: settings.sun_azimuth_deg, elevation_deg: settings.sun_elevation_deg, ..sun }
}

/// `params` with the viewer's sun, shadows and exposure from `settings`.
pub fn apply_view_settings(params: &mut ShadingParams, settings: &ViewSettings) {
    params.sun = viewer_sun(params.sun, settings);
    params.shadows = settings.shadows;
    params.exposure = settings.exposure;
}

/// The index of `name` in `names`, or 0.
pub fn position(names: &[String], name: &str) -> usize {
    names.iter().position(|n| n == name).unwrap_or(0)
}
