//! What every live scene is: a scene the viewer draws, whose errors it shows as lines of
//! text. The one place the scenes' frames become a [`SceneRenderer`]'s.

use crate::{Cancel, Frame, SceneRenderer, SimulationReport, SimulationRequest, ViewSettings};
use relief_core::Camera;
use relief_render::RenderError;

/// A scene drawn frame after frame.
pub trait Drawing: Send + Sync {
    /// The scene in a few words, e.g. "4096x4096 height field".
    fn describe(&self) -> String;

    /// The diagonal of the scene's bounds, in metres.
    fn scene_size(&self) -> f64;

    /// The frame of `camera` with `settings`; it may stop early once `cancel` is set.
    fn draw(
        &self,
        camera: &Camera,
        settings: &ViewSettings,
        cancel: &Cancel,
    ) -> Result<Frame, RenderError>;

    /// Whether the scene has a simulation the viewer can run.
    fn has_simulation(&self) -> bool {
        false
    }

    /// Advances the scene's simulation as `request` asks.
    fn simulate(&self, request: &SimulationRequest) -> Result<SimulationReport, RenderError> {
        let _ = request;
        Err(RenderError::Unsupported("this scene has no simulation".into()))
    }
}

impl<D: Drawing> SceneRenderer for D {
    fn describe(&self) -> String {
        Drawing::describe(self)
    }

    fn scene_size(&self) -> f64 {
        Drawing::scene_size(self)
    }

    fn render(
        &self,
        camera: &Camera,
        settings: &ViewSettings,
        cancel: &Cancel,
    ) -> Result<Frame, String> {
        self.draw(camera, settings, cancel).map_err(|e| with_causes(&e))
    }

    fn has_simulation(&self) -> bool {
        Drawing::has_simulation(self)
    }

    fn simulate(&self, request: &SimulationRequest) -> Result<SimulationReport, String> {
        Drawing::simulate(self, request).map_err(|e| format!("simulation: {}", with_causes(&e)))
    }
}

/// `error` and its causes on one line, each after a colon.
pub fn with_causes(error: &dyn std::error::Error) -> String {
    let mut line = error.to_string();
    let mut cause = error.source();
    while let Some(inner) = cause {
        line.push_str(": ");
        line.push_str(&inner.to_string());
        cause = inner.source();
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn causes_follow_their_error() {
        let error = RenderError::Placement(relief_core::CoreError::Grid("no samples".into()));
        let line = with_causes(&error);
        assert!(line.starts_with("invalid placement: "), "{line}");
        assert!(line.contains("no samples"), "{line}");
    }
}
