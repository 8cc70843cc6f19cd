//! Drawing on a finished picture's pixels: panels, filled rectangles and triangles, and
//! text, clipped to the picture, without anti-aliasing (the colours stay exact).

use super::font;

/// The ink of furniture: black.
pub const INK: [u8; 3] = [0, 0, 0];

/// A picture's 8-bit sRGB pixels, row-major from the top, to draw on.
pub struct Canvas<'a> {
    /// The pixels.
    pub rgb: &'a mut [[u8; 3]],
    /// Pixels a row.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

impl Canvas<'_> {
    /// Sets pixel (x, y) to `colour`, where it is in the picture.
    pub fn set(&mut self, x: i64, y: i64, colour: [u8; 3]) {
        if x >= 0 && y >= 0 && x < self.width as i64 && y < self.height as i64 {
            self.rgb[y as usize * self.width as usize + x as usize] = colour;
        }
    }

    /// Fills the rectangle of `w` x `h` pixels whose top-left pixel is (x, y).
    pub fn fill_rect(&mut self, x: i64, y: i64, w: u32, h: u32, colour: [u8; 3]) {
        for yy in y..y + h as i64 {
            for xx in x..x + w as i64 {
                self.set(xx, yy, colour);
            }
        }
    }

    /// A light panel under furniture: the rectangle's pixels mixed three quarters of the way
    /// to white, with a one-pixel grey border, so that ink reads on any terrain.
    pub fn panel(&mut self, x: i64, y: i64, w: u32, h: u32) {
        for yy in y..y + h as i64 {
            for xx in x..x + w as i64 {
                if xx < 0 || yy < 0 || xx >= self.width as i64 || yy >= self.height as i64 {
                    continue;
                }
                let edge = xx == x || yy == y || xx == x + w as i64 - 1 || yy == y + h as i64 - 1;
                let pixel = &mut self.rgb[yy as usize * self.width as usize + xx as usize];
                *pixel =
                    if edge { [128; 3] } else { pixel.map(|c| ((c as u32 + 3 * 255) / 4) as u8) };
            }
        }
    }

    /// Draws `text` with its top-left corner at (x, y), each font pixel `scale` x `scale`;
    /// characters the font does not hold are left blank.
    pub fn text(&mut self, text: &str, x: i64, y: i64, scale: u32, colour: [u8; 3]) {
        let s = scale as i64;
        for (k, c) in text.chars().enumerate() {
            let Some(rows) = font::glyph(c) else { continue };
            let left = x + k as i64 * font::ADVANCE as i64 * s;
            for gy in 0..font::GLYPH_HEIGHT {
                for gx in 0..font::GLYPH_WIDTH {
                    if font::ink(&rows, gx, gy) {
                        self.fill_rect(
                            left + gx as i64 * s,
                            y + gy as i64 * s,
                            scale,
                            scale,
                            colour,
                        );
                    }
                }
            }
        }
    }

    /// Fills the triangle `a`, `b`, `c` (pixel coordinates, y down): every pixel whose centre
    /// is inside it or on its edges.
    pub fn fill_triangle(&mut self, a: [f64; 2], b: [f64; 2], c: [f64; 2], colour: [u8; 3]) {
        let (x0, x1) = (a[0].min(b[0]).min(c[0]).floor(), a[0].max(b[0]).max(c[0]).ceil());
        let (y0, y1) = (a[1].min(b[1]).min(c[1]).floor(), a[1].max(b[1]).max(c[1]).ceil());
        let edge = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
            (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
        };
        let area = edge(a, b, c);
        if area == 0.0 {
            return;
        }
        for y in y0 as i64..=y1 as i64 {
            for x in x0 as i64..=x1 as i64 {
                let p = [x as f64 + 0.5, y as f64 + 0.5];
                let (w0, w1, w2) = (edge(b, c, p), edge(c, a, p), edge(a, b, p));
                let inside = if area > 0.0 {
                    w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0
                } else {
                    w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0
                };
                if inside {
                    self.set(x, y, colour);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn count(rgb: &[[u8; 3]], colour: [u8; 3]) -> usize {
        rgb.iter().filter(|p| **p == colour).count()
    }

    #[test]
    fn shapes_are_clipped_and_exact() {
        let mut rgb = vec![[50u8; 3]; 20 * 10];
        let mut canvas = Canvas { rgb: &mut rgb, width: 20, height: 10 };
        canvas.fill_rect(-3, -3, 5, 5, INK);
        assert_eq!(count(canvas.rgb, INK), 4);
        canvas.fill_triangle([10.0, 0.0], [14.0, 4.0], [6.0, 4.0], [255, 0, 0]);
        let red = count(canvas.rgb, [255, 0, 0]);
        assert!((12..=20).contains(&red), "a triangle of area 16: {red} pixels");
        canvas.panel(0, 5, 20, 5);
        assert_eq!(canvas.rgb[7 * 20 + 10], [203; 3]);
        assert_eq!(canvas.rgb[5 * 20 + 10], [128; 3]);
    }

    #[test]
    fn text_inks_its_glyphs() {
        let mut rgb = vec![[255u8; 3]; 30 * 14];
        let mut canvas = Canvas { rgb: &mut rgb, width: 30, height: 14 };
        canvas.text("-", 0, 0, 2, INK);
        // The minus sign: row 3 of the glyph, five pixels, at scale 2.
        assert_eq!(count(canvas.rgb, INK), 5 * 2 * 2);
        assert_eq!(canvas.rgb[6 * 30], INK);
    }
}
