//! A scene's live simulation as the viewer drives it: running or paused, steps asked for
//! while paused, rain on or off, and what the last steps took. The viewer only keeps this
//! state and asks for steps; the scene renderer ([`crate::SceneRenderer::simulate`]) takes
//! them.

use crate::input_map::Action;
use std::time::Duration;

/// What the viewer asks a scene's simulation to do before the next frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimulationRequest {
    /// Steps to take (at least this many).
    pub steps: u32,
    /// More steps while the next one is predicted to fit this time (a running simulation
    /// of an interactive view); `None`: exactly `steps`.
    pub budget: Option<Duration>,
    /// Whether it rains (the scene's rain rate) or not (rain rate 0).
    pub rain: bool,
}

/// What a scene's simulation did for a request.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SimulationReport {
    /// Steps taken.
    pub steps: u32,
    /// The simulation's step count after them (the scene's own count included).
    pub step_count: u64,
    /// Milliseconds the steps took, in all.
    pub step_ms: f64,
}

/// The viewer's controls of a scene's simulation. It opens paused, with rain on, so that the
/// frame at rest is the scene as `relief render` draws it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimulationControl {
    /// Whether it advances every frame.
    pub running: bool,
    /// Whether it rains.
    pub rain_off: bool,
    /// Steps asked for while paused and not yet requested.
    pub pending: u32,
    /// The simulation's step count, once it has taken a step.
    pub step_count: Option<u64>,
    /// Milliseconds per step of the last request.
    pub ms_per_step: Option<f64>,
}

impl SimulationControl {
    /// Paused, rain on.
    pub fn new() -> Self {
        SimulationControl::default()
    }

    /// Applies `action` if it is one of the simulation's; whether the view needs a new frame
    /// (the simulation starts or a step is asked for).
    pub fn apply(&mut self, action: Action) -> bool {
        match action {
            Action::ToggleSimulation => {
                self.running = !self.running;
                self.running
            }
            Action::StepSimulation if !self.running => {
                self.pending += 1;
                true
            }
            // Rain changes the steps to come, not the terrain shown.
            Action::ToggleRain => {
                self.rain_off = !self.rain_off;
                false
            }
            _ => false,
        }
    }

    /// Whether the next frame should advance the simulation.
    pub fn wants_step(&self) -> bool {
        self.running || self.pending > 0
    }

    /// What to ask of the simulation with the next frame, if anything: one step (and, given a
    /// `budget`, as many more as fit it) while running, else the steps asked for, which it
    /// takes.
    pub fn take_request(&mut self, budget: Option<Duration>) -> Option<SimulationRequest> {
        let rain = !self.rain_off;
        if self.running {
            return Some(SimulationRequest { steps: 1, budget, rain });
        }
        if self.pending == 0 {
            return None;
        }
        let steps = std::mem::take(&mut self.pending);
        Some(SimulationRequest { steps, budget: None, rain })
    }

    /// Takes note of what the simulation did.
    pub fn record(&mut self, report: &SimulationReport) {
        if report.steps > 0 {
            self.step_count = Some(report.step_count);
            self.ms_per_step = Some(report.step_ms / f64::from(report.steps));
        }
    }

    /// One line for the HUD: running or paused, the step count, rain, milliseconds per step.
    pub fn describe(&self) -> String {
        let state = if self.running { "running" } else { "paused" };
        let step = self.step_count.map_or("not stepped yet".into(), |n| format!("step {n}"));
        let rain = if self.rain_off { "rain off" } else { "rain on" };
        let ms = self.ms_per_step.map_or(String::new(), |ms| format!(", {ms:.1} ms/step"));
        format!("simulation {state}, {step}, {rain}{ms}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn it_opens_paused_with_rain_and_steps_only_when_asked() {
        let mut s = SimulationControl::new();
        assert!(!s.wants_step());
        assert_eq!(s.take_request(None), None);
        assert_eq!(s.describe(), "simulation paused, not stepped yet, rain on");
        assert!(s.apply(Action::StepSimulation));
        assert!(s.apply(Action::StepSimulation));
        assert!(s.wants_step());
        let budget = Some(Duration::from_millis(20));
        let request = s.take_request(budget).unwrap();
        assert_eq!(request, SimulationRequest { steps: 2, budget: None, rain: true });
        assert!(!s.wants_step() && s.take_request(budget).is_none(), "taken once");
        s.record(&SimulationReport { steps: 2, step_count: 12, step_ms: 7.0 });
        assert_eq!(s.describe(), "simulation paused, step 12, rain on, 3.5 ms/step");
    }

    #[test]
    fn running_steps_every_frame_within_the_budget_and_rain_toggles() {
        let mut s = SimulationControl::new();
        assert!(!s.apply(Action::ToggleRain), "rain alone needs no new frame");
        assert!(s.apply(Action::ToggleSimulation));
        assert!(!s.apply(Action::StepSimulation), "the step key steps a paused simulation");
        let budget = Some(Duration::from_millis(20));
        for _ in 0..2 {
            assert_eq!(
                s.take_request(budget),
                Some(SimulationRequest { steps: 1, budget, rain: false })
            );
        }
        s.record(&SimulationReport { steps: 0, step_count: 0, step_ms: 0.0 });
        assert!(s.describe().starts_with("simulation running, not stepped yet, rain off"));
        assert!(!s.apply(Action::ToggleSimulation), "pausing keeps the terrain");
        assert!(!s.wants_step());
        assert!(!s.apply(Action::NextMode));
    }
}
