//! Scripted input for `relief view --frames N --script ...`: keys held or pressed, frame by
//! frame, so that tests and scripts fly the same path every run.
//!
//! A script is a comma-separated list of steps `COUNT:KEYS`: the keys (joined by `+`) are
//! held for COUNT frames; a key written `!K` is pressed once at the step's first frame
//! instead; `-` holds nothing. `20:W+Left,1:!T,10:-` flies forward turning left for 20
//! frames, switches the tracer, and rests for 10. Each scripted frame advances the camera by
//! [`SCRIPT_FRAME_S`], whatever the frame really took.

use crate::input_map::Key;
use crate::ViewerError;
use std::collections::BTreeSet;

/// The time one scripted frame stands for, in seconds.
pub const SCRIPT_FRAME_S: f64 = 1.0 / 30.0;

/// One frame of a script: the keys held and the keys pressed.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ScriptFrame {
    /// Held during the frame.
    pub held: BTreeSet<Key>,
    /// Pressed at the frame's start.
    pub pressed: Vec<Key>,
}

/// A parsed script, frame by frame.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Script {
    frames: Vec<ScriptFrame>,
}

impl Script {
    /// Parses `text` (see the module's documentation).
    pub fn parse(text: &str) -> Result<Script, ViewerError> {
        let bad = |reason: String| ViewerError::Script(reason);
        let mut frames = Vec::new();
        for step in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (count, keys) = step
                .split_once(':')
                .ok_or_else(|| bad(format!("step '{step}' is not COUNT:KEYS")))?;
            let count: usize = count
                .parse()
                .ok()
                .filter(|&n| (1..=100_000).contains(&n))
                .ok_or_else(|| bad(format!("step '{step}': COUNT must be 1 to 100000")))?;
            let mut frame = ScriptFrame::default();
            for name in keys.split('+').map(str::trim).filter(|k| *k != "-") {
                let (press, name) = match name.strip_prefix('!') {
                    Some(rest) => (true, rest),
                    None => (false, name),
                };
                let key = Key::from_name(name)
                    .ok_or_else(|| bad(format!("step '{step}': unknown key '{name}'")))?;
                if press {
                    frame.pressed.push(key);
                } else {
                    frame.held.insert(key);
                }
            }
            let held_only = ScriptFrame { held: frame.held.clone(), pressed: vec![] };
            frames.push(frame);
            frames.extend(std::iter::repeat_n(held_only, count - 1));
        }
        Ok(Script { frames })
    }

    /// The number of frames the script lasts.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether the script has no frames.
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Frame `k` (nothing held or pressed past the end).
    pub fn frame(&self, k: usize) -> ScriptFrame {
        self.frames.get(k).cloned().unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_hold_keys_for_their_count_and_presses_happen_once() {
        let script = Script::parse("2:W+Left, 1:!T+!3, 2:-").unwrap();
        assert_eq!(script.len(), 5);
        let w_left: BTreeSet<Key> = [Key::Letter('W'), Key::Left].into();
        assert_eq!(script.frame(0).held, w_left);
        assert_eq!(script.frame(1).held, w_left);
        assert_eq!(script.frame(2).pressed, [Key::Letter('T'), Key::Digit(3)]);
        assert!(script.frame(3).held.is_empty() && script.frame(3).pressed.is_empty());
        assert_eq!(script.frame(99), ScriptFrame::default());
    }

    #[test]
    fn bad_scripts_say_which_step_is_wrong() {
        for (text, needle) in [
            ("W", "not COUNT:KEYS"),
            ("0:W", "COUNT must be"),
            ("x:W", "COUNT must be"),
            ("3:W+Jump", "unknown key 'Jump'"),
        ] {
            let err = Script::parse(text).unwrap_err().to_string();
            assert!(err.contains(needle), "{text}: {err}");
        }
    }
}
