//! winit's physical key codes as the viewer's [`Key`]s: by position on the keyboard, so
//! that W A S D stay where they are on any layout.

use crate::input_map::Key;
use winit::keyboard::KeyCode;

/// The viewer's key for a physical key code (layout-independent: WASD stay where they are).
pub(crate) fn key_of(code: KeyCode) -> Option<Key> {
    use KeyCode::*;
    let letters = [
        (KeyA, 'A'),
        (KeyB, 'B'),
        (KeyC, 'C'),
        (KeyD, 'D'),
        (KeyE, 'E'),
        (KeyF, 'F'),
        (KeyG, 'G'),
        (KeyH, 'H'),
        (KeyI, 'I'),
        (KeyJ, 'J'),
        (KeyK, 'K'),
        (KeyL, 'L'),
        (KeyM, 'M'),
        (KeyN, 'N'),
        (KeyO, 'O'),
        (KeyP, 'P'),
        (KeyQ, 'Q'),
        (KeyR, 'R'),
        (KeyS, 'S'),
        (KeyT, 'T'),
        (KeyU, 'U'),
        (KeyV, 'V'),
        (KeyW, 'W'),
        (KeyX, 'X'),
        (KeyY, 'Y'),
        (KeyZ, 'Z'),
    ];
    if let Some(&(_, c)) = letters.iter().find(|(k, _)| *k == code) {
        return Some(Key::Letter(c));
    }
    let digits = [Digit0, Digit1, Digit2, Digit3, Digit4, Digit5, Digit6, Digit7, Digit8, Digit9];
    if let Some(d) = digits.iter().position(|&k| k == code) {
        return Some(Key::Digit(d as u8));
    }
    Some(match code {
        ArrowUp => Key::Up,
        ArrowDown => Key::Down,
        ArrowLeft => Key::Left,
        ArrowRight => Key::Right,
        Tab => Key::Tab,
        Space => Key::Space,
        Equal | NumpadAdd => Key::Plus,
        Minus | NumpadSubtract => Key::Minus,
        F1 => Key::F1,
        F2 => Key::F2,
        Escape => Key::Escape,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_map_by_position() {
        assert_eq!(key_of(KeyCode::KeyW), Some(Key::Letter('W')));
        assert_eq!(key_of(KeyCode::KeyZ), Some(Key::Letter('Z')));
        assert_eq!(key_of(KeyCode::Digit3), Some(Key::Digit(3)));
        assert_eq!(key_of(KeyCode::NumpadAdd), Some(Key::Plus));
        assert_eq!(key_of(KeyCode::Equal), Some(Key::Plus));
        assert_eq!(key_of(KeyCode::ArrowLeft), Some(Key::Left));
        assert_eq!(key_of(KeyCode::F1), Some(Key::F1));
        assert_eq!(key_of(KeyCode::CapsLock), None);
    }
}
