//! The viewer's keys: which ones move the camera while held, and which act once when
//! pressed. The window maps its keyboard events to [`Key`], so this is testable without one.

use crate::camera_controller::Motion;
use std::collections::BTreeSet;

/// The keys the viewer knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Key {
    /// A letter key, upper case.
    Letter(char),
    /// A digit key, 0 to 9.
    Digit(u8),
    /// Arrow up.
    Up,
    /// Arrow down.
    Down,
    /// Arrow left.
    Left,
    /// Arrow right.
    Right,
    /// The tab key.
    Tab,
    /// The space bar.
    Space,
    /// Plus (or equals, on the same key).
    Plus,
    /// Minus.
    Minus,
    /// F1.
    F1,
    /// F2.
    F2,
    /// Escape.
    Escape,
}

impl Key {
    /// The key named `name` as the script and the help write it: `W`, `3`, `Up`, `Tab`,
    /// `Space`, `Plus`, `Minus`, `F1`, `F2`, `Escape`.
    pub fn from_name(name: &str) -> Option<Key> {
        let key = match name {
            "Up" => Key::Up,
            "Down" => Key::Down,
            "Left" => Key::Left,
            "Right" => Key::Right,
            "Tab" => Key::Tab,
            "Space" => Key::Space,
            "Plus" | "+" => Key::Plus,
            "Minus" => Key::Minus,
            "F1" => Key::F1,
            "F2" => Key::F2,
            "Escape" | "Esc" => Key::Escape,
            _ => {
                let mut chars = name.chars();
                match (chars.next(), chars.next()) {
                    (Some(c), None) if c.is_ascii_alphabetic() => {
                        Key::Letter(c.to_ascii_uppercase())
                    }
                    (Some(c), None) if c.is_ascii_digit() => Key::Digit(c as u8 - b'0'),
                    _ => return None,
                }
            }
        };
        Some(key)
    }
}

/// What a key press does once.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Close the viewer.
    Quit,
    /// Show or hide the key list.
    ToggleHelp,
    /// Show or hide the frame figures.
    ToggleHud,
    /// Switch between flying and orbiting.
    ToggleNavigation,
    /// Save the image shown, without the overlay.
    Screenshot,
    /// Start or stop recording the camera path.
    ToggleRecording,
    /// Go back to the starting view.
    ResetView,
    /// The next tracer the scene offers.
    NextTracer,
    /// The next surface (boxes, triangles) of a height field.
    NextSurface,
    /// The next mode (boxes, smooth) of an MLHM scene.
    NextMode,
    /// The quality preset of this index (0 low .. 3 max).
    Preset(usize),
    /// Shadows on or off.
    ToggleShadows,
    /// Exposure up (+1) or down (-1) a step.
    Exposure(i32),
    /// The sun a step clockwise (+1) or anticlockwise (-1).
    SunAzimuth(i32),
    /// The sun a step higher (+1) or lower (-1).
    SunElevation(i32),
    /// Run or pause the scene's simulation (MLHM).
    ToggleSimulation,
    /// One step of the paused simulation.
    StepSimulation,
    /// The simulation's rain on or off.
    ToggleRain,
}

/// Every key and what it does, as the README and the F1 overlay list them.
pub const KEY_HELP: &[(&str, &str)] = &[
    ("W A S D", "forward, left, back, right (orbit: closer, round, away)"),
    ("Q E", "down, up (orbit: lower, higher)"),
    ("arrows", "turn and tilt"),
    ("mouse drag", "look around (orbit: circle the target)"),
    ("wheel", "fly speed (orbit: distance)"),
    ("Tab", "fly or orbit"),
    ("T", "next tracer"),
    ("G", "next surface (height fields)"),
    ("M", "next mode, boxes or smooth (MLHM)"),
    ("1 2 3 4", "preset low, mid, high, max (MLHM)"),
    ("V", "run or pause the simulation (MLHM)"),
    ("N", "one simulation step, while paused"),
    ("B", "simulation rain on or off"),
    ("H", "shadows on or off"),
    ("J L", "sun anticlockwise, clockwise"),
    ("I K", "sun higher, lower"),
    ("+ -", "exposure up, down"),
    ("Space", "back to the starting view"),
    ("P", "screenshot (PNG, without this overlay)"),
    ("R", "start or stop recording the camera path"),
    ("F1", "this list"),
    ("F2", "frame figures"),
    ("Esc", "quit"),
];

/// What pressing `key` does, if anything (the motion keys act only while held).
pub fn action_for(key: Key) -> Option<Action> {
    let action = match key {
        Key::Escape => Action::Quit,
        Key::F1 => Action::ToggleHelp,
        Key::F2 => Action::ToggleHud,
        Key::Tab => Action::ToggleNavigation,
        Key::Space => Action::ResetView,
        Key::Plus => Action::Exposure(1),
        Key::Minus => Action::Exposure(-1),
        Key::Digit(d @ 1..=4) => Action::Preset(usize::from(d) - 1),
        Key::Letter('P') => Action::Screenshot,
        Key::Letter('R') => Action::ToggleRecording,
        Key::Letter('T') => Action::NextTracer,
        Key::Letter('G') => Action::NextSurface,
        Key::Letter('M') => Action::NextMode,
        Key::Letter('H') => Action::ToggleShadows,
        Key::Letter('J') => Action::SunAzimuth(-1),
        Key::Letter('L') => Action::SunAzimuth(1),
        Key::Letter('I') => Action::SunElevation(1),
        Key::Letter('K') => Action::SunElevation(-1),
        Key::Letter('V') => Action::ToggleSimulation,
        Key::Letter('N') => Action::StepSimulation,
        Key::Letter('B') => Action::ToggleRain,
        _ => return None,
    };
    Some(action)
}

/// The motion the `held` keys ask for.
pub fn motion_from(held: &BTreeSet<Key>) -> Motion {
    let axis = |plus: Key, minus: Key| {
        f64::from(u8::from(held.contains(&plus))) - f64::from(u8::from(held.contains(&minus)))
    };
    Motion {
        forward: axis(Key::Letter('W'), Key::Letter('S')),
        right: axis(Key::Letter('D'), Key::Letter('A')),
        up: axis(Key::Letter('E'), Key::Letter('Q')),
        yaw: axis(Key::Right, Key::Left),
        pitch: axis(Key::Up, Key::Down),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn held_keys_make_motion_and_opposite_keys_cancel() {
        let held: BTreeSet<Key> = [Key::Letter('W'), Key::Letter('A'), Key::Left].into();
        let m = motion_from(&held);
        assert_eq!((m.forward, m.right, m.up, m.yaw, m.pitch), (1.0, -1.0, 0.0, -1.0, 0.0));
        let both: BTreeSet<Key> = [Key::Letter('Q'), Key::Letter('E')].into();
        assert!(!motion_from(&both).is_moving());
        assert!(!motion_from(&BTreeSet::new()).is_moving());
    }

    #[test]
    fn every_key_in_the_help_is_bound_and_no_key_does_two_things() {
        for name in [
            "T", "G", "M", "H", "J", "L", "I", "K", "P", "R", "V", "N", "B", "Plus", "Minus",
            "Space",
        ] {
            let key = Key::from_name(name).unwrap();
            assert!(action_for(key).is_some(), "{name}");
            assert!(!motion_from(&[key].into()).is_moving(), "{name} also moves");
        }
        for name in ["W", "A", "S", "D", "Q", "E", "Up", "Down", "Left", "Right"] {
            let key = Key::from_name(name).unwrap();
            assert!(action_for(key).is_none(), "{name}");
            assert!(motion_from(&[key].into()).is_moving(), "{name}");
        }
        assert_eq!(action_for(Key::Digit(3)), Some(Action::Preset(2)));
        assert_eq!(action_for(Key::Digit(7)), None);
        assert_eq!(action_for(Key::Letter('V')), Some(Action::ToggleSimulation));
        assert_eq!(action_for(Key::Letter('N')), Some(Action::StepSimulation));
        assert_eq!(action_for(Key::Letter('B')), Some(Action::ToggleRain));
        assert_eq!(Key::from_name("w"), Some(Key::Letter('W')));
        assert_eq!(Key::from_name("Nope"), None);
    }
}
