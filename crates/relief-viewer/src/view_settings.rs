//! What the viewer lets the user switch at run time: the tracer, surface, mode and preset a
//! scene offers, the sun, the exposure and shadows.

use crate::input_map::Action;

/// Degrees a sun key turns the sun's azimuth.
const SUN_AZIMUTH_STEP_DEG: f64 = 15.0;
/// Degrees a sun key raises or lowers the sun.
const SUN_ELEVATION_STEP_DEG: f64 = 5.0;
/// Factor an exposure key multiplies or divides the exposure by.
const EXPOSURE_STEP: f64 = 1.25;

/// The choices a scene offers, each a list of names; an empty list means the scene has no
/// such choice (a height field has no preset, an MLHM scene no surface).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SceneChoices {
    /// Tracers, e.g. `["mipmap", "naive"]`.
    pub tracers: Vec<String>,
    /// Surfaces of a height field: `["triangles", "boxes"]`.
    pub surfaces: Vec<String>,
    /// Modes of an MLHM scene: `["boxes", "smooth"]`.
    pub modes: Vec<String>,
    /// Quality presets of an MLHM scene: `["low", "mid", "high", "max"]`.
    pub presets: Vec<String>,
}

/// The settings of the next frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewSettings {
    /// The scene's choices.
    pub choices: SceneChoices,
    /// Index into `choices.tracers`.
    pub tracer: usize,
    /// Index into `choices.surfaces`.
    pub surface: usize,
    /// Index into `choices.modes`.
    pub mode: usize,
    /// Index into `choices.presets`.
    pub preset: usize,
    /// Sun azimuth, degrees clockwise from north.
    pub sun_azimuth_deg: f64,
    /// Sun elevation, degrees above the horizon (-90 to 90).
    pub sun_elevation_deg: f64,
    /// Exposure multiplier.
    pub exposure: f64,
    /// Whether shadows are cast.
    pub shadows: bool,
}

impl ViewSettings {
    /// The first of each choice, the sun at `sun` (azimuth, elevation) and `exposure`.
    pub fn new(choices: SceneChoices, sun: (f64, f64), exposure: f64, shadows: bool) -> Self {
        ViewSettings {
            choices,
            tracer: 0,
            surface: 0,
            mode: 0,
            preset: 0,
            sun_azimuth_deg: sun.0,
            sun_elevation_deg: sun.1,
            exposure,
            shadows,
        }
    }

    /// The tracer's name, if the scene offers tracers.
    pub fn tracer_name(&self) -> Option<&str> {
        self.choices.tracers.get(self.tracer).map(String::as_str)
    }

    /// The surface's name, if the scene offers surfaces.
    pub fn surface_name(&self) -> Option<&str> {
        self.choices.surfaces.get(self.surface).map(String::as_str)
    }

    /// The mode's name, if the scene offers modes.
    pub fn mode_name(&self) -> Option<&str> {
        self.choices.modes.get(self.mode).map(String::as_str)
    }

    /// The preset's name, if the scene offers presets.
    pub fn preset_name(&self) -> Option<&str> {
        self.choices.presets.get(self.preset).map(String::as_str)
    }

    /// Starts at the named choices where the scene offers them (names it does not offer
    /// leave the first).
    pub fn select(
        mut self,
        tracer: Option<&str>,
        surface: Option<&str>,
        mode: Option<&str>,
    ) -> Self {
        let find = |list: &[String], name: Option<&str>, at: usize| {
            name.and_then(|n| list.iter().position(|x| x == n)).unwrap_or(at)
        };
        self.tracer = find(&self.choices.tracers, tracer, self.tracer);
        self.surface = find(&self.choices.surfaces, surface, self.surface);
        self.mode = find(&self.choices.modes, mode, self.mode);
        self
    }

    /// Starts at the named preset, where the scene offers it.
    pub fn with_preset(mut self, preset: Option<&str>) -> Self {
        if let Some(at) = preset.and_then(|n| self.choices.presets.iter().position(|x| x == n)) {
            self.preset = at;
        }
        self
    }

    /// Applies `action` if it changes a setting; whether it did.
    pub fn apply(&mut self, action: Action) -> bool {
        let next = |at: &mut usize, n: usize| {
            if n < 2 {
                return false;
            }
            *at = (*at + 1) % n;
            true
        };
        match action {
            Action::NextTracer => next(&mut self.tracer, self.choices.tracers.len()),
            Action::NextSurface => next(&mut self.surface, self.choices.surfaces.len()),
            Action::NextMode => next(&mut self.mode, self.choices.modes.len()),
            Action::Preset(k) if k < self.choices.presets.len() && k != self.preset => {
                self.preset = k;
                true
            }
            Action::ToggleShadows => {
                self.shadows = !self.shadows;
                true
            }
            Action::Exposure(step) => {
                let e = self.exposure * EXPOSURE_STEP.powi(step);
                self.exposure = e.clamp(1e-4, 1e4);
                true
            }
            Action::SunAzimuth(step) => {
                let a = self.sun_azimuth_deg + f64::from(step) * SUN_AZIMUTH_STEP_DEG;
                self.sun_azimuth_deg = a.rem_euclid(360.0);
                true
            }
            Action::SunElevation(step) => {
                let e = self.sun_elevation_deg + f64::from(step) * SUN_ELEVATION_STEP_DEG;
                self.sun_elevation_deg = e.clamp(-90.0, 90.0);
                true
            }
            _ => false,
        }
    }

    /// One line of what is active, for the overlay and the window title.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        for (label, name) in [
            ("tracer", self.tracer_name()),
            ("surface", self.surface_name()),
            ("mode", self.mode_name()),
            ("preset", self.preset_name()),
        ] {
            if let Some(name) = name {
                parts.push(format!("{label} {name}"));
            }
        }
        parts.push(format!("sun {:.0},{:.0}", self.sun_azimuth_deg, self.sun_elevation_deg));
        parts.push(format!("exposure {:.2}", self.exposure));
        parts.push(if self.shadows { "shadows".into() } else { "no shadows".into() });
        parts.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn height_field() -> ViewSettings {
        let choices = SceneChoices {
            tracers: vec!["mipmap".into(), "naive".into()],
            surfaces: vec!["triangles".into(), "boxes".into()],
            ..SceneChoices::default()
        };
        ViewSettings::new(choices, (315.0, 35.0), 1.0, true)
    }

    #[test]
    fn choices_cycle_and_absent_ones_do_nothing() {
        let mut s = height_field();
        assert!(s.apply(Action::NextTracer));
        assert_eq!(s.tracer_name(), Some("naive"));
        assert!(s.apply(Action::NextTracer));
        assert_eq!(s.tracer_name(), Some("mipmap"));
        assert!(s.apply(Action::NextSurface));
        assert_eq!(s.surface_name(), Some("boxes"));
        assert!(!s.apply(Action::NextMode), "a height field has no modes");
        assert!(!s.apply(Action::Preset(2)), "nor presets");
        assert!(!s.apply(Action::Screenshot));
        assert_eq!(s.mode_name(), None);
        assert!(s.describe().starts_with("tracer mipmap, surface boxes, sun 315,35"));
    }

    #[test]
    fn the_sun_wraps_round_and_stops_at_the_zenith_and_exposure_stays_in_range() {
        let mut s = height_field();
        for _ in 0..4 {
            s.apply(Action::SunAzimuth(1));
        }
        assert_eq!(s.sun_azimuth_deg, 15.0);
        for _ in 0..20 {
            s.apply(Action::SunElevation(1));
        }
        assert_eq!(s.sun_elevation_deg, 90.0);
        s.apply(Action::Exposure(-1));
        assert!((s.exposure - 0.8).abs() < 1e-12);
        for _ in 0..100 {
            s.apply(Action::Exposure(1));
        }
        assert_eq!(s.exposure, 1e4);
        assert!(s.apply(Action::ToggleShadows) && !s.shadows);
    }

    #[test]
    fn the_starting_choices_can_be_named() {
        let s = height_field().select(Some("naive"), Some("boxes"), Some("smooth"));
        assert_eq!(
            (s.tracer_name(), s.surface_name(), s.mode_name()),
            (Some("naive"), Some("boxes"), None)
        );
        let s = height_field().select(Some("safety"), None, None).with_preset(Some("high"));
        assert_eq!((s.tracer_name(), s.preset_name()), (Some("mipmap"), None));
    }
}
