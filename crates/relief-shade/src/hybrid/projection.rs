//! Where the hybrid renderer's proxy boxes land on a camera's image: the projected rectangle
//! of a box and the pixels whose rays may pass through it (Ammann et al. 2010, section 4.2),
//! and whether a view sees the solid's bottom face.

use relief_core::{Aabb, Camera, DVec3, Projection};
use relief_trace::hybrid::HybridCells;

/// Where a box lands on the screen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BoxProjection {
    /// Wholly outside the view frustum.
    Outside,
    /// Crosses the eye's plane (or touches it): its projection is unbounded.
    Unbounded,
    /// The bounding rectangle of the 8 projected corners, in continuous pixel coordinates
    /// (pixel (i, j)'s centre is at (i + 0.5, j + 0.5), y down), not clipped to the image.
    Rect {
        /// Left edge.
        x0: f64,
        /// Top edge.
        y0: f64,
        /// Right edge.
        x1: f64,
        /// Bottom edge.
        y1: f64,
    },
}

/// An inclusive range of pixels: columns `i0..=i1`, rows `j0..=j1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PixelRect {
    /// First column.
    pub i0: u32,
    /// First row (from the top).
    pub j0: u32,
    /// Last column.
    pub i1: u32,
    /// Last row.
    pub j1: u32,
}

impl BoxProjection {
    /// Screen area of the bounding rectangle in pixels² (infinite when unbounded, 0 outside).
    pub fn area(&self) -> f64 {
        match *self {
            BoxProjection::Outside => 0.0,
            BoxProjection::Unbounded => f64::INFINITY,
            BoxProjection::Rect { x0, y0, x1, y1 } => (x1 - x0) * (y1 - y0),
        }
    }

    /// The pixels of a `width x height` image whose rays may pass through the box: every pixel
    /// whose centre lies in the rectangle, with one pixel of margin against rounding; the
    /// whole image when unbounded; `None` when outside or off the image.
    pub fn pixels(&self, width: u32, height: u32) -> Option<PixelRect> {
        let (w, h) = (width as f64, height as f64);
        match *self {
            BoxProjection::Outside => None,
            BoxProjection::Unbounded => {
                Some(PixelRect { i0: 0, j0: 0, i1: width - 1, j1: height - 1 })
            }
            BoxProjection::Rect { x0, y0, x1, y1 } => {
                let (lo_x, hi_x) = ((x0 - 0.5).floor() - 1.0, (x1 - 0.5).ceil() + 1.0);
                let (lo_y, hi_y) = ((y0 - 0.5).floor() - 1.0, (y1 - 0.5).ceil() + 1.0);
                if hi_x < 0.0 || hi_y < 0.0 || lo_x > w - 1.0 || lo_y > h - 1.0 {
                    return None;
                }
                Some(PixelRect {
                    i0: lo_x.max(0.0) as u32,
                    j0: lo_y.max(0.0) as u32,
                    i1: hi_x.min(w - 1.0) as u32,
                    j1: hi_y.min(h - 1.0) as u32,
                })
            }
        }
    }
}

/// Projects `b` with `camera`: [`BoxProjection::Outside`] when the box lies wholly on the
/// outer side of one plane of the view frustum (behind the eye's plane or beyond an image
/// edge), [`BoxProjection::Unbounded`] when a corner lies on or behind the eye's plane of a
/// pinhole camera, else the bounding rectangle of its 8 projected corners.
pub fn project_box(camera: &Camera, b: &Aabb) -> BoxProjection {
    let (eye, fwd, right, up) = (camera.eye(), camera.forward(), camera.right(), camera.image_up());
    let (w, h) = (camera.width() as f64, camera.height() as f64);
    let s = camera.half_height();
    let aspect = s * w / h;
    let perspective = matches!(camera.projection(), Projection::Perspective { .. });
    // Camera coordinates of the corners.
    let corners: [DVec3; 8] = std::array::from_fn(|k| {
        let p = DVec3::new(
            if k & 1 == 0 { b.min.x } else { b.max.x },
            if k & 2 == 0 { b.min.y } else { b.max.y },
            if k & 4 == 0 { b.min.z } else { b.max.z },
        ) - eye;
        DVec3::new(p.dot(right), p.dot(up), p.dot(fwd))
    });
    // Frustum planes, each as "outside when f(corner) > 0".
    let scale = |c: &DVec3| if perspective { c.z } else { 1.0 };
    let outside = [
        corners.iter().all(|c| c.z < 0.0),
        corners.iter().all(|c| c.x > aspect * scale(c)),
        corners.iter().all(|c| -c.x > aspect * scale(c)),
        corners.iter().all(|c| c.y > s * scale(c)),
        corners.iter().all(|c| -c.y > s * scale(c)),
    ];
    if outside.contains(&true) {
        return BoxProjection::Outside;
    }
    if perspective && corners.iter().any(|c| c.z <= 0.0) {
        return BoxProjection::Unbounded;
    }
    let (mut x0, mut y0, mut x1, mut y1) =
        (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for c in &corners {
        let (sx, sy) = if perspective { (c.x / c.z, c.y / c.z) } else { (c.x, c.y) };
        // In pixels of the camera's samples (off the centres where it samples so).
        let px = (sx / aspect + 1.0) * 0.5 * w - camera.pixel_offset()[0];
        let py = (1.0 - sy / s) * 0.5 * h - camera.pixel_offset()[1];
        x0 = x0.min(px);
        x1 = x1.max(px);
        y0 = y0.min(py);
        y1 = y1.max(py);
    }
    BoxProjection::Rect { x0, y0, x1, y1 }
}

/// Whether some ray of `camera` starts below the lowest sample of the field `cells` measure,
/// and so may see the solid's bottom face, which only boxes reaching the floor hold
/// ([`HybridCells::set_floor_everywhere`]).
pub fn bottom_visible(cells: &HybridCells, camera: &Camera) -> bool {
    let floor = cells.world_bounds().min.z;
    let lowest_origin = match camera.projection() {
        Projection::Perspective { .. } => camera.eye().z,
        Projection::Orthographic { .. } => {
            let s = camera.half_height();
            let aspect = s * camera.width() as f64 / camera.height() as f64;
            camera.eye().z - aspect * camera.right().z.abs() - s * camera.image_up().z.abs()
        }
    };
    lowest_origin < floor
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::{GridGeometry, HeightField, Surface};

    #[test]
    fn projected_areas_are_those_computed_by_hand() {
        // 9 x 9 samples in cells of 5, all 0 but sample (6, 6) at 2.
        let mut samples = vec![0.0f32; 81];
        samples[6 + 6 * 9] = 2.0;
        let field = HeightField::new(9, 9, samples, GridGeometry::unit()).unwrap();
        let cells = HybridCells::new(&field, Surface::Triangles, 5).unwrap();
        // Straight down from 100 above (2.5, 2.5), 90 degrees, 100 x 100 pixels: right is x,
        // up is y, and a point at depth z projects to pixel (50 (1 + x/z), 50 (1 - y/z)).
        let eye = DVec3::new(2.5, 2.5, 100.0);
        let camera =
            Camera::look_at(eye, DVec3::new(2.5, 2.5, 0.0), DVec3::Y, 90.0, 100, 100).unwrap();
        // Cell (0, 0): x, y in [-2, 2] around the eye at depth 100: pixels 49..51 both ways.
        let p = project_box(&camera, &cells.proxy_box(0).unwrap());
        assert!((p.area() - 4.0).abs() < 1e-9, "{p:?}");
        assert_eq!(p.pixels(100, 100), Some(PixelRect { i0: 47, j0: 47, i1: 52, j1: 52 }));
        // Cell (1, 1): x, y in [2, 6], depth 100 (z = 0) to 98 (z = 2): 50 (1 + 2/100) to
        // 50 (1 + 6/98) along each axis.
        let side = 50.0 * (6.0 / 98.0 - 2.0 / 100.0);
        let p = project_box(&camera, &cells.proxy_box(3).unwrap());
        assert!((p.area() - side * side).abs() < 1e-9, "{p:?}");
    }

    #[test]
    fn views_from_below_the_floor_see_the_bottom() {
        let mut samples = vec![5.0f32; 100];
        samples[0] = 1.0;
        let f = HeightField::new(10, 10, samples, GridGeometry::unit()).unwrap();
        let cells = HybridCells::new(&f, Surface::Triangles, 4).unwrap();
        let look = |eye: DVec3, projection| {
            Camera::new(eye, DVec3::new(5.0, 5.0, 3.0), DVec3::Z, projection, 40, 30).unwrap()
        };
        let pinhole = Projection::Perspective { fov_deg: 60.0 };
        assert!(!bottom_visible(&cells, &look(DVec3::new(-5.0, 5.0, 1.0), pinhole)));
        assert!(bottom_visible(&cells, &look(DVec3::new(-5.0, 5.0, 0.99), pinhole)));
        // An orthographic image 4 high, looking level: its lowest rays start 2 below the eye.
        let parallel = Projection::Orthographic { height: 4.0 };
        assert!(bottom_visible(&cells, &look(DVec3::new(-5.0, 5.0, 2.9), parallel)));
        assert!(!bottom_visible(&cells, &look(DVec3::new(-5.0, 5.0, 3.0), parallel)));
    }
}
