//! The north arrow: a compass needle at the picture's top right pointing where north runs on
//! the picture at the point looked at (the projection of the direction +y there), red half
//! to the north, with an upright 'N' beyond its tip.

use relief_core::{Camera, DVec3, Projection};

use super::canvas::{Canvas, INK};
use crate::RenderError;

/// The colour of the needle's north half.
pub const NORTH_RED: [u8; 3] = [200, 30, 30];
/// The colour of the needle's south half.
pub const SOUTH_GREY: [u8; 3] = [96, 96, 96];

/// The unit direction north takes on `camera`'s picture at the point it looks at, in pixel
/// axes (x to the right, y down): `[0, -1]` on a north-up map. An error where north runs
/// along the view (straight into or out of the picture), so that it has no direction there.
pub fn north_on_screen(camera: &Camera) -> Result<[f64; 2], RenderError> {
    let (eye, target) = (camera.eye(), camera.target());
    let step = (target - eye).length().max(1.0) * 1e-3;
    let screen = |p: DVec3| {
        let d = p - eye;
        let (x, y) = (d.dot(camera.right()), d.dot(camera.image_up()));
        match camera.projection() {
            Projection::Orthographic { .. } => (x, y),
            Projection::Perspective { .. } => {
                let depth = d.dot(camera.forward());
                (x / depth, y / depth)
            }
        }
    };
    let (x0, y0) = screen(target);
    let (x1, y1) = screen(target + DVec3::Y * step);
    // Foreshortening: the screen length of the step against its length across the view.
    let scale = match camera.projection() {
        Projection::Orthographic { .. } => step,
        Projection::Perspective { .. } => step / (target - eye).dot(camera.forward()).max(1e-300),
    };
    let (dx, dy) = (x1 - x0, y1 - y0);
    let length = dx.hypot(dy);
    if length.is_nan() || length <= 1e-3 * scale {
        return Err(RenderError::Furniture(
            "north runs along the view here (straight into or out of the picture): a north \
             arrow has no direction to point"
                .into(),
        ));
    }
    Ok([dx / length, -dy / length])
}

/// Half the side of the arrow's square panel, pixels, at furniture scale `unit`.
fn half_panel(unit: u32) -> f64 {
    20.0 * unit as f64
}

/// The first row below the arrow's panel and its margin, at furniture scale `unit`.
pub(crate) fn bottom(unit: u32) -> i64 {
    (4.0 * unit as f64 + 2.0 * half_panel(unit)) as i64 + 4 * unit as i64
}

/// Draws the needle pointing along `north` (pixel axes, unit) at the picture's top right, on
/// a light panel; `unit` is the furniture's pixel scale.
pub(crate) fn draw(canvas: &mut Canvas, north: [f64; 2], unit: u32) {
    let u = unit as f64;
    let (needle, half_width, letter_gap) = (10.0 * u, 3.5 * u, 6.0 * u);
    let half = half_panel(unit);
    let margin = 4.0 * u;
    let (cx, cy) = (canvas.width as f64 - margin - half, margin + half);
    canvas.panel((cx - half) as i64, (cy - half) as i64, (2.0 * half) as u32, (2.0 * half) as u32);
    let [nx, ny] = north;
    let (px, py) = (-ny, nx);
    let tip = [cx + nx * needle, cy + ny * needle];
    let tail = [cx - nx * needle, cy - ny * needle];
    let left = [cx + px * half_width, cy + py * half_width];
    let right = [cx - px * half_width, cy - py * half_width];
    canvas.fill_triangle(tip, left, right, NORTH_RED);
    canvas.fill_triangle(tail, left, right, SOUTH_GREY);
    // The letter, upright, centred beyond the tip.
    let (lw, lh) = (5.0 * u, 7.0 * u);
    let (lx, ly) = (cx + nx * (needle + letter_gap), cy + ny * (needle + letter_gap));
    canvas.text("N", (lx - lw / 2.0).round() as i64, (ly - lh / 2.0).round() as i64, unit, INK);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ortho(eye: DVec3, up: DVec3) -> Camera {
        Camera::new(eye, DVec3::ZERO, up, Projection::Orthographic { height: 100.0 }, 64, 36)
            .unwrap()
    }

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9
    }

    #[test]
    fn north_is_up_on_a_north_up_map_and_turns_with_the_view() {
        let up = north_on_screen(&ortho(DVec3::Z * 100.0, DVec3::Y)).unwrap();
        assert!(close(up, [0.0, -1.0]), "{up:?}");
        // East at the top: north is to the left.
        let east_up = north_on_screen(&ortho(DVec3::Z * 100.0, DVec3::X)).unwrap();
        assert!(close(east_up, [-1.0, 0.0]), "{east_up:?}");
        // Looking north-east from the south-west at 30 degrees: north leans to the left.
        let eye = DVec3::new(-1.0, -1.0, 0.8165) * 100.0;
        let oblique = north_on_screen(&ortho(eye, DVec3::Z)).unwrap();
        let pinhole = Camera::look_at(eye, DVec3::ZERO, DVec3::Z, 45.0, 64, 36).unwrap();
        let seen = north_on_screen(&pinhole).unwrap();
        for d in [oblique, seen] {
            assert!(d[0] < -0.3 && d[1] < -0.3, "{d:?}");
        }
    }

    #[test]
    fn north_along_the_view_has_no_direction() {
        let level =
            Camera::look_at(DVec3::new(0.0, -100.0, 0.0), DVec3::ZERO, DVec3::Z, 45.0, 8, 8)
                .unwrap();
        let message = north_on_screen(&level).unwrap_err().to_string();
        assert!(message.contains("north runs along the view"), "{message}");
    }
}
