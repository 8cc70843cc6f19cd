//! A small bitmap font for map furniture: 5 x 7 glyphs of the digits, the letters of units
//! and of north ('m', 'k', 'N'), and '.', '-', '+' and ' ', drawn at a whole-pixel scale.

/// Columns of a glyph.
pub const GLYPH_WIDTH: u32 = 5;
/// Rows of a glyph.
pub const GLYPH_HEIGHT: u32 = 7;
/// Columns from one glyph's left edge to the next one's: the glyph and one blank column.
pub const ADVANCE: u32 = GLYPH_WIDTH + 1;

/// The glyphs: a character and its seven rows from the top, each row's five pixels in the
/// low five bits, the leftmost in bit 4.
#[rustfmt::skip]
const GLYPHS: [(char, [u8; 7]); 17] = [
    ('0', [0b01110, 0b10001, 0b10011, 0b10101, 0b11001, 0b10001, 0b01110]),
    ('1', [0b00100, 0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110]),
    ('2', [0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b01000, 0b11111]),
    ('3', [0b11111, 0b00010, 0b00100, 0b00010, 0b00001, 0b10001, 0b01110]),
    ('4', [0b00010, 0b00110, 0b01010, 0b10010, 0b11111, 0b00010, 0b00010]),
    ('5', [0b11111, 0b10000, 0b11110, 0b00001, 0b00001, 0b10001, 0b01110]),
    ('6', [0b00110, 0b01000, 0b10000, 0b11110, 0b10001, 0b10001, 0b01110]),
    ('7', [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b01000, 0b01000]),
    ('8', [0b01110, 0b10001, 0b10001, 0b01110, 0b10001, 0b10001, 0b01110]),
    ('9', [0b01110, 0b10001, 0b10001, 0b01111, 0b00001, 0b00010, 0b01100]),
    ('m', [0b00000, 0b00000, 0b11010, 0b10101, 0b10101, 0b10101, 0b10101]),
    ('k', [0b10000, 0b10000, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010]),
    ('N', [0b10001, 0b11001, 0b10101, 0b10011, 0b10001, 0b10001, 0b10001]),
    ('.', [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b01100]),
    ('-', [0b00000, 0b00000, 0b00000, 0b11111, 0b00000, 0b00000, 0b00000]),
    ('+', [0b00000, 0b00100, 0b00100, 0b11111, 0b00100, 0b00100, 0b00000]),
    (' ', [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000]),
];

/// The rows of `c`'s glyph; `None` for a character the font does not hold.
pub fn glyph(c: char) -> Option<[u8; 7]> {
    GLYPHS.iter().find(|(g, _)| *g == c).map(|(_, rows)| *rows)
}

/// Whether glyph pixel (column `x`, row `y` from the top) of `rows` is ink.
pub fn ink(rows: &[u8; 7], x: u32, y: u32) -> bool {
    x < GLYPH_WIDTH && y < GLYPH_HEIGHT && rows[y as usize] >> (GLYPH_WIDTH - 1 - x) & 1 == 1
}

/// The width in pixels of `text` drawn at `scale` (no trailing blank column).
pub fn text_width(text: &str, scale: u32) -> u32 {
    let n = text.chars().count() as u32;
    (n * ADVANCE).saturating_sub(1) * scale
}

/// The height in pixels of a line of text drawn at `scale`.
pub fn text_height(scale: u32) -> u32 {
    GLYPH_HEIGHT * scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_label_character_has_a_distinct_glyph() {
        for c in "0123456789mkN.-+ ".chars() {
            assert!(glyph(c).is_some(), "{c}");
        }
        assert_eq!(glyph('Q'), None);
        let mut seen: Vec<[u8; 7]> = GLYPHS.iter().map(|(_, rows)| *rows).collect();
        seen.sort();
        seen.dedup();
        assert_eq!(seen.len(), GLYPHS.len(), "two glyphs are the same");
        for (c, rows) in GLYPHS {
            assert!(rows.iter().all(|r| *r < 32), "{c} is wider than 5 pixels");
        }
    }

    #[test]
    fn widths_and_ink() {
        assert_eq!(text_width("10 m", 1), 4 * 6 - 1);
        assert_eq!(text_width("10 m", 3), 3 * (4 * 6 - 1));
        assert_eq!(text_width("", 2), 0);
        let one = glyph('1').unwrap();
        assert!(ink(&one, 2, 0) && !ink(&one, 0, 0) && !ink(&one, 5, 0));
    }
}
