//! The HUD's text: what the overlay shows over the frame (the scene and the navigation, the
//! frame's time, Mrays/s and steps per ray, and what is active), composed apart from the
//! window so that it is testable without one.

use crate::frame::Frame;
use crate::{Navigation, SimulationControl, ViewSettings};
use std::time::Duration;

/// What the HUD shows of a frame.
#[derive(Debug, Clone, Copy)]
pub struct HudState<'a> {
    /// The scene in a few words ([`crate::SceneRenderer::describe`]).
    pub scene: &'a str,
    /// Flying or orbiting.
    pub navigation: Navigation,
    /// The frame shown.
    pub frame: &'a Frame,
    /// The time rendering it took.
    pub elapsed: Duration,
    /// The settings active.
    pub settings: &'a ViewSettings,
    /// Whether the camera path is being recorded.
    pub recording: bool,
    /// The scene's simulation, where it has one.
    pub simulation: Option<&'a SimulationControl>,
}

/// The HUD's lines, top first: the scene and the navigation; the frame time, its size, the
/// Mrays/s and (where the tracer counts them) the steps per ray; the tracer, surface, mode,
/// preset, sun, exposure and shadows active; the simulation's state, where the scene has one
/// (running or paused, step count, rain, milliseconds per step); the renderer's note, if any;
/// whether the path is being recorded; and the key that lists the keys.
pub fn hud_lines(state: &HudState) -> Vec<String> {
    let frame = state.frame;
    let seconds = state.elapsed.as_secs_f64().max(1e-9);
    let steps = frame.stats.steps_per_ray.map_or(String::new(), |s| format!(", {s:.1} steps/ray"));
    let navigation = match state.navigation {
        Navigation::Fly => "fly",
        Navigation::Orbit => "orbit",
    };
    let mut lines = vec![
        format!("{} - {navigation}", state.scene),
        format!(
            "{:.1} ms at {}x{}, {:.1} Mrays/s{steps}",
            seconds * 1e3,
            frame.width,
            frame.height,
            frame.stats.rays as f64 / seconds / 1e6
        ),
        state.settings.describe(),
    ];
    lines.extend(state.simulation.map(SimulationControl::describe));
    lines.extend(frame.note.clone());
    if state.recording {
        lines.push("recording the camera path (R stops)".into());
    }
    lines.push("F1: keys".into());
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::FrameStats;
    use crate::SceneChoices;

    fn frame(rays: u64, steps_per_ray: Option<f64>, note: Option<&str>) -> Frame {
        Frame {
            width: 160,
            height: 90,
            rgb: vec![[0; 3]; 160 * 90],
            stats: FrameStats { rays, steps_per_ray },
            note: note.map(String::from),
        }
    }

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn an_mlhm_frame_names_its_time_rays_steps_and_what_is_active() {
        let choices = SceneChoices {
            tracers: names(&["hierarchy", "naive"]),
            modes: names(&["boxes", "smooth"]),
            presets: names(&["low", "mid", "high", "max"]),
            ..SceneChoices::default()
        };
        let mut settings = ViewSettings::new(choices, (315.0, 35.0), 1.25, true);
        (settings.mode, settings.preset) = (1, 3);
        let frame = frame(3_000_000, Some(12.34), None);
        let state = HudState {
            scene: "64x64 MLHM scene",
            navigation: Navigation::Orbit,
            frame: &frame,
            elapsed: Duration::from_millis(20),
            settings: &settings,
            recording: false,
            simulation: None,
        };
        assert_eq!(
            hud_lines(&state),
            [
                "64x64 MLHM scene - orbit",
                "20.0 ms at 160x90, 150.0 Mrays/s, 12.3 steps/ray",
                "tracer hierarchy, mode smooth, preset max, sun 315,35, exposure 1.25, shadows",
                "F1: keys",
            ]
        );
    }

    #[test]
    fn a_height_field_frame_names_its_surface_note_and_recording_and_no_steps_uncounted() {
        let choices = SceneChoices {
            tracers: names(&["mipmap", "naive", "safety"]),
            surfaces: names(&["triangles", "boxes"]),
            ..SceneChoices::default()
        };
        let mut settings = ViewSettings::new(choices, (90.0, 10.0), 0.8, false);
        (settings.tracer, settings.surface) = (2, 1);
        let note = "the safety tracer draws triangles only: drawn by the mipmap tracer";
        let frame = frame(500_000, None, Some(note));
        let state = HudState {
            scene: "96x96 height field",
            navigation: Navigation::Fly,
            frame: &frame,
            elapsed: Duration::from_micros(2500),
            settings: &settings,
            recording: true,
            simulation: None,
        };
        assert_eq!(
            hud_lines(&state),
            [
                "96x96 height field - fly",
                "2.5 ms at 160x90, 200.0 Mrays/s",
                "tracer safety, surface boxes, sun 90,10, exposure 0.80, no shadows",
                note,
                "recording the camera path (R stops)",
                "F1: keys",
            ]
        );
    }

    #[test]
    fn a_scene_with_a_simulation_shows_its_state_after_what_is_active() {
        let settings = ViewSettings::new(SceneChoices::default(), (0.0, 45.0), 1.0, true);
        let frame = frame(1000, None, None);
        let mut simulation = SimulationControl::new();
        simulation.apply(crate::Action::ToggleSimulation);
        simulation.apply(crate::Action::ToggleRain);
        simulation.record(&crate::SimulationReport { steps: 4, step_count: 9, step_ms: 10.0 });
        let state = HudState {
            scene: "32x32 MLHM scene",
            navigation: Navigation::Orbit,
            frame: &frame,
            elapsed: Duration::from_millis(1),
            settings: &settings,
            recording: false,
            simulation: Some(&simulation),
        };
        let lines = hud_lines(&state);
        assert_eq!(lines[3], "simulation running, step 9, rain off, 2.5 ms/step");
        assert_eq!(lines[4], "F1: keys");
    }

    #[test]
    fn a_frame_that_took_no_measurable_time_gives_finite_figures() {
        let settings = ViewSettings::new(SceneChoices::default(), (0.0, 45.0), 1.0, true);
        let frame = frame(0, Some(0.0), None);
        let state = HudState {
            scene: "scene",
            navigation: Navigation::Fly,
            frame: &frame,
            elapsed: Duration::ZERO,
            settings: &settings,
            recording: false,
            simulation: None,
        };
        let lines = hud_lines(&state);
        assert_eq!(lines[1], "0.0 ms at 160x90, 0.0 Mrays/s, 0.0 steps/ray");
        assert_eq!(lines[2], "sun 0,45, exposure 1.00, shadows");
    }
}
