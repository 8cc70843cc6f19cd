//! The scale bar: a round length (1, 2 or 5 x 10^k metres, in m or km) drawn at the picture's
//! bottom left, as long as that many metres are on the image. Only an orthographic camera
//! has one scale over the whole picture; a perspective picture's scale changes with the
//! distance, so it has no scale bar.

use relief_core::{Camera, Projection};

use super::canvas::{Canvas, INK};
use super::font;
use crate::RenderError;

/// The longest a scale bar may be, as a fraction of the picture's width.
pub const MAX_WIDTH_FRACTION: f64 = 0.25;

/// A scale bar: its length in metres and in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaleBar {
    /// The length it stands for, metres: 1, 2 or 5 x 10^k.
    pub metres: f64,
    /// Its length on the picture, pixels: `metres / metres_per_pixel`, rounded.
    pub pixels: u32,
}

impl ScaleBar {
    /// The longest round length that fits in `max_pixels` pixels of `metres_per_pixel`.
    pub fn choose(metres_per_pixel: f64, max_pixels: u32) -> ScaleBar {
        let metres = round_length(metres_per_pixel * max_pixels.max(1) as f64);
        ScaleBar { metres, pixels: (metres / metres_per_pixel).round() as u32 }
    }

    /// The bar's label: "500 m", "2 km", "0.5 m".
    pub fn label(&self) -> String {
        length_label(self.metres)
    }
}

/// The ground size of a pixel of `camera`'s picture, metres, along the image's rows: the
/// orthographic image's height over its pixels. An error for a perspective camera (its scale
/// changes with the distance) and for an orthographic one whose rows are not level (a rolled
/// camera: a horizontal bar would not measure level ground).
pub fn metres_per_pixel(camera: &Camera) -> Result<f64, RenderError> {
    let Projection::Orthographic { height } = camera.projection() else {
        return Err(RenderError::Furniture(
            "a scale bar needs an orthographic camera (--ortho): the scale of a perspective \
             picture changes with the distance"
                .into(),
        ));
    };
    if camera.right().z.abs() > 1e-9 {
        return Err(RenderError::Furniture(format!(
            "a scale bar measures along the picture's rows, which are not level in this view \
             (the camera is rolled by {:.1} degrees)",
            camera.right().z.asin().to_degrees()
        )));
    }
    Ok(height / camera.height() as f64)
}

/// The largest length of 1, 2 or 5 x 10^k metres that is at most `max_metres` (positive).
pub fn round_length(max_metres: f64) -> f64 {
    let decade = 10f64.powf(max_metres.log10().floor());
    // A whole decade computed as 10^k may fall a hair above the length it should equal.
    let decade = if decade > max_metres { decade / 10.0 } else { decade };
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&l| l <= max_metres * (1.0 + 1e-12))
        .unwrap_or(decade)
}

/// A length for a label: kilometres from 1 km on, metres below; as few decimals as it needs.
pub fn length_label(metres: f64) -> String {
    if metres >= 1000.0 {
        format!("{} km", trim(metres / 1000.0))
    } else {
        format!("{} m", trim(metres))
    }
}

/// `v` with as few decimals as it needs (up to 6), no trailing zeros.
pub(crate) fn trim(v: f64) -> String {
    let text = format!("{v:.6}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".into()
    } else {
        text.to_string()
    }
}

/// Draws `bar` at the bottom left of the picture, its label above it, on a light panel;
/// `unit` is the furniture's pixel scale.
pub(crate) fn draw(canvas: &mut Canvas, bar: &ScaleBar, unit: u32) {
    let u = unit as i64;
    let label = bar.label();
    let (text_w, text_h) = (font::text_width(&label, unit) as i64, font::text_height(unit) as i64);
    let (pad, margin, thick, tick) = (3 * u, 4 * u, 2 * u, 3 * u);
    let inner_w = (bar.pixels as i64).max(text_w);
    let panel_w = inner_w + 2 * pad;
    let panel_h = pad + text_h + 2 * u + tick + thick + pad;
    let (x0, y0) = (margin, canvas.height as i64 - margin - panel_h);
    canvas.panel(x0, y0, panel_w as u32, panel_h as u32);
    let bar_x = x0 + pad + (inner_w - bar.pixels as i64) / 2;
    let bar_y = y0 + pad + text_h + 2 * u + tick;
    canvas.fill_rect(bar_x, bar_y, bar.pixels, thick as u32, INK);
    // End ticks, within the bar's extent, so the bar's rows are exactly its length of ink.
    canvas.fill_rect(bar_x, bar_y - tick, unit, tick as u32, INK);
    canvas.fill_rect(bar_x + bar.pixels as i64 - u, bar_y - tick, unit, tick as u32, INK);
    let text_x = x0 + pad + (inner_w - text_w) / 2;
    canvas.text(&label, text_x, y0 + pad, unit, INK);
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::DVec3;

    #[test]
    fn round_lengths_are_one_two_or_five_times_a_power_of_ten() {
        assert_eq!(round_length(888.9), 500.0);
        assert_eq!(round_length(1000.0), 1000.0);
        assert_eq!(round_length(1999.0), 1000.0);
        assert_eq!(round_length(2000.0), 2000.0);
        assert_eq!(round_length(4999.0), 2000.0);
        assert_eq!(round_length(0.7), 0.5);
        assert_eq!(round_length(0.3), 0.2);
        assert_eq!(round_length(12.0), 10.0);
        for k in -3..7 {
            for m in [1.0, 2.0, 5.0] {
                let l = m * 10f64.powi(k);
                assert_eq!(round_length(l), l, "{l}");
            }
        }
    }

    #[test]
    fn labels_read_as_people_write_them() {
        assert_eq!(length_label(500.0), "500 m");
        assert_eq!(length_label(2000.0), "2 km");
        assert_eq!(length_label(50_000.0), "50 km");
        assert_eq!(length_label(0.5), "0.5 m");
        assert_eq!(length_label(0.02), "0.02 m");
    }

    #[test]
    fn a_bar_of_l_metres_spans_l_over_the_pixel_size() {
        let bar = ScaleBar::choose(2000.0 / 360.0, 160);
        assert_eq!(bar.metres, 500.0);
        assert_eq!(bar.pixels, 90);
        let map = Camera::new(
            DVec3::new(0.0, 0.0, 100.0),
            DVec3::ZERO,
            DVec3::Y,
            Projection::Orthographic { height: 2000.0 },
            640,
            360,
        )
        .unwrap();
        assert!((metres_per_pixel(&map).unwrap() - 2000.0 / 360.0).abs() < 1e-12);
        let pinhole =
            Camera::look_at(DVec3::new(0.0, 0.0, 100.0), DVec3::ZERO, DVec3::Y, 45.0, 64, 36)
                .unwrap();
        let message = metres_per_pixel(&pinhole).unwrap_err().to_string();
        assert!(message.contains("orthographic camera (--ortho)"), "{message}");
        let rolled = Camera::new(
            DVec3::new(0.0, -100.0, 100.0),
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 1.0),
            Projection::Orthographic { height: 10.0 },
            64,
            36,
        )
        .unwrap();
        assert!(metres_per_pixel(&rolled).unwrap_err().to_string().contains("rolled"));
    }
}
