//! The overlay drawn over the frame in the window: lines of text on a dark panel, in the
//! public-domain 8x8 font of `font8x8`. Screenshots never include it.

use font8x8::legacy::BASIC_LEGACY;

/// Pixels per glyph cell, each way.
const GLYPH: usize = 8;
/// Space between lines, in pixels.
const LINE_GAP: usize = 3;
/// Margin of the panel around the text, in pixels.
const MARGIN: usize = 6;

/// Draws `lines` at the top-left corner of `target` (0RGB pixels, `width` x `height`), on a
/// panel that darkens the picture behind it. Characters outside ASCII are drawn as '?'.
pub fn draw_panel(target: &mut [u32], width: usize, height: usize, lines: &[String]) {
    if lines.is_empty() {
        return;
    }
    let columns = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let panel_w = (2 * MARGIN + columns * GLYPH).min(width);
    let panel_h = (2 * MARGIN + lines.len() * (GLYPH + LINE_GAP)).min(height);
    for row in target.chunks_exact_mut(width).take(panel_h) {
        for pixel in &mut row[..panel_w] {
            // A quarter of the brightness, each channel.
            *pixel = (*pixel >> 2) & 0x3f3f3f;
        }
    }
    for (k, line) in lines.iter().enumerate() {
        let y = MARGIN + k * (GLYPH + LINE_GAP);
        for (c, ch) in line.chars().enumerate() {
            draw_glyph(target, width, height, MARGIN + c * GLYPH, y, ch);
        }
    }
}

/// Draws `ch` in white with its top-left corner at (`x`, `y`), clipped to the target.
fn draw_glyph(target: &mut [u32], width: usize, height: usize, x: usize, y: usize, ch: char) {
    let code = if ch.is_ascii() { ch as usize } else { '?' as usize };
    let bitmap = BASIC_LEGACY[code];
    for (dy, bits) in bitmap.iter().enumerate() {
        for dx in 0..GLYPH {
            let (px, py) = (x + dx, y + dy);
            if bits >> dx & 1 == 1 && px < width && py < height {
                target[px + py * width] = 0xffffff;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_drawn_white_on_a_darkened_panel_and_clipped() {
        let (w, h) = (40, 12);
        let mut target = vec![0x808080u32; w * h];
        draw_panel(&mut target, w, h, &["Hi relief, clipped".into()]);
        assert!(target.contains(&0xffffff), "some glyph pixels");
        assert!(target.contains(&0x202020), "darkened background");
        // Outside the panel's rows nothing changed: the panel is 6 + 11 + 6 rows, but the
        // target has 12, so every row is touched; the right edge is clipped, not wrapped.
        assert_eq!(target.len(), w * h);
        let mut empty = vec![0x808080u32; w * h];
        draw_panel(&mut empty, w, h, &[]);
        assert!(empty.iter().all(|&p| p == 0x808080));
    }
}
