//! The camera of relief's conventions: a pinhole or an orthographic projection, one ray per
//! pixel. Automatic framing of a scene is in `framing.rs`.

use crate::{CoreError, Ray};
use glam::DVec3;

/// How a camera's pixels map to rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// A pinhole at the eye: every ray starts at the eye; `fov_deg` is the vertical field of
    /// view in degrees (strictly between 0 and 180).
    Perspective {
        /// Vertical field of view in degrees.
        fov_deg: f64,
    },
    /// Parallel rays along the view direction, starting on the plane through the eye
    /// perpendicular to it; `height` is the image's vertical extent on that plane, in world
    /// units (metres), positive.
    Orthographic {
        /// Vertical extent of the image in world units.
        height: f64,
    },
}

/// A camera producing one ray per pixel of a `width x height` image.
///
/// forward = normalize(target - eye); right = normalize(forward x up); up' = right x forward.
/// Pixel (i, j), i the column from the left and j the row from the top, has the screen
/// coordinates sx = (2 (i + 0.5) / W - 1) * s * W / H and sy = (1 - 2 (j + 0.5) / H) * s, where
/// s is half the image's height:
///
/// - [`Projection::Perspective`]: s = tan(fov / 2); the ray starts at the eye and looks along
///   normalize(forward + sx * right + sy * up').
/// - [`Projection::Orthographic`]: s = height / 2 (world units); the ray starts at
///   eye + sx * right + sy * up', on the plane through the eye perpendicular to forward, and
///   looks along forward.
///
/// Either way the direction is a unit vector, so a hit's ray parameter `t` is its distance from
/// the ray's origin (the eye, or the point on the eye's plane): the depth relief writes.
///
/// A camera may sample its pixels off their centres ([`Camera::with_pixel_offset`]): every
/// pixel's ray then passes `(dx, dy)` pixels right of and below its centre, `i + 0.5 + dx` and
/// `j + 0.5 + dy` in the formulas above. Anti-aliasing takes its samples so.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    eye: DVec3,
    target: DVec3,
    up: DVec3,
    projection: Projection,
    width: u32,
    height: u32,
    forward: DVec3,
    right: DVec3,
    true_up: DVec3,
    /// Half the image's height: `tan(fov / 2)` at unit distance for a pinhole, `height / 2`
    /// world units for an orthographic camera.
    half_height: f64,
    /// Where each pixel's ray passes, in pixels right of and below its centre.
    pixel_offset: [f64; 2],
}

impl Camera {
    /// The pinhole camera at `eye` looking at `target`, with `up` and a vertical field of view
    /// in degrees.
    pub fn look_at(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        fov_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, CoreError> {
        Self::new(eye, target, up, Projection::Perspective { fov_deg }, width, height)
    }

    /// The camera at `eye` looking at `target`, with `up` and `projection`.
    ///
    /// Fails when a point is not finite, the eye is the target, `up` is zero or parallel to
    /// the view, the image has no pixels, or the projection's field of view is not strictly
    /// between 0 and 180 degrees (its orthographic height not positive and finite).
    pub fn new(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        projection: Projection,
        width: u32,
        height: u32,
    ) -> Result<Self, CoreError> {
        let bad = |msg: String| Err(CoreError::Camera(msg));
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return bad("eye, target and up must be finite".into());
        }
        let half_height = match projection {
            Projection::Perspective { fov_deg } => {
                if !(fov_deg.is_finite() && fov_deg > 0.0 && fov_deg < 180.0) {
                    return bad(format!(
                        "field of view {fov_deg} must be between 0 and 180 degrees"
                    ));
                }
                (fov_deg.to_radians() / 2.0).tan()
            }
            Projection::Orthographic { height } => {
                if !(height.is_finite() && height > 0.0) {
                    return bad(format!(
                        "orthographic height {height} must be a positive, finite length"
                    ));
                }
                height / 2.0
            }
        };
        if width == 0 || height == 0 {
            return bad(format!("image size {width}x{height} has no pixels"));
        }
        let to_target = target - eye;
        if to_target.length() == 0.0 {
            return bad("eye and target are the same point".into());
        }
        let forward = to_target.normalize();
        let side = forward.cross(up);
        if up.length() == 0.0 || side.length() <= 1e-9 * up.length() {
            return bad(format!("up {up} is zero or parallel to the view direction"));
        }
        let right = side.normalize();
        let true_up = right.cross(forward);
        Ok(Camera {
            eye,
            target,
            up,
            projection,
            width,
            height,
            forward,
            right,
            true_up,
            half_height,
            pixel_offset: [0.0, 0.0],
        })
    }

    /// The up vector to give [`Camera::look_at`] for a camera at `eye` looking at `target`:
    /// `up` itself, or, where `up` is parallel to the view (a camera looking straight down or
    /// up with the default up `0,0,1`), north `0,1,0`, which puts north at the top of the
    /// image (or, for a view along the north axis, `0,0,1`). The flag says whether `up` was
    /// replaced.
    pub fn usable_up(eye: DVec3, target: DVec3, up: DVec3) -> (DVec3, bool) {
        let forward = (target - eye).normalize_or_zero();
        let parallel = |u: DVec3| forward.cross(u).length() <= 1e-9 * u.length();
        if forward == DVec3::ZERO || up.length() == 0.0 || !parallel(up) {
            return (up, false);
        }
        if parallel(DVec3::Y) {
            (DVec3::Z, true)
        } else {
            (DVec3::Y, true)
        }
    }

    /// The ray through the centre of pixel (i, j), with a unit direction (see [`Camera`]).
    #[inline]
    pub fn ray(&self, i: u32, j: u32) -> Ray {
        self.ray_through(self.screen_x(i), self.screen_y(j))
    }

    /// `sx` of pixel column `i`: `(2 (i + 0.5 + dx) / W - 1) * s * W / H`, `dx` the
    /// [`Camera::pixel_offset`] (0 unless asked for). A renderer that traces many pixels of the
    /// same columns and rows computes it once per column and passes it to
    /// [`Camera::ray_through`], which then gives exactly [`Camera::ray`].
    #[inline]
    pub fn screen_x(&self, i: u32) -> f64 {
        let (w, h) = (self.width as f64, self.height as f64);
        (2.0 * (i as f64 + 0.5 + self.pixel_offset[0]) / w - 1.0) * self.half_height * w / h
    }

    /// `sy` of pixel row `j`: `(1 - 2 (j + 0.5 + dy) / H) * s` (see [`Camera::screen_x`]).
    #[inline]
    pub fn screen_y(&self, j: u32) -> f64 {
        (1.0 - 2.0 * (j as f64 + 0.5 + self.pixel_offset[1]) / self.height as f64)
            * self.half_height
    }

    /// The same camera sampling each pixel `(dx, dy)` pixels right of and below its centre
    /// (each in `[-0.5, 0.5]`: a point of the pixel); `(0, 0)` is the centre, where every
    /// camera samples unless told otherwise.
    ///
    /// Fails when an offset is not finite or leaves the pixel.
    pub fn with_pixel_offset(self, dx: f64, dy: f64) -> Result<Camera, CoreError> {
        if !((-0.5..=0.5).contains(&dx) && (-0.5..=0.5).contains(&dy)) {
            return Err(CoreError::Camera(format!(
                "pixel offset ({dx}, {dy}) must lie in the pixel, each between -0.5 and 0.5"
            )));
        }
        Ok(Camera { pixel_offset: [dx, dy], ..self })
    }

    /// Where each pixel's ray passes, in pixels right of and below its centre: `[dx, dy]`
    /// ([`Camera::with_pixel_offset`]).
    pub fn pixel_offset(&self) -> [f64; 2] {
        self.pixel_offset
    }

    /// The ray of screen coordinates `(sx, sy)`: from the eye along
    /// `normalize(forward + sx * right + sy * up')` for a pinhole, from
    /// `eye + sx * right + sy * up'` along `forward` for an orthographic camera.
    #[inline]
    pub fn ray_through(&self, sx: f64, sy: f64) -> Ray {
        match self.projection {
            Projection::Perspective { .. } => {
                let dir = (self.forward + sx * self.right + sy * self.true_up).normalize();
                Ray::new(self.eye, dir)
            }
            Projection::Orthographic { .. } => {
                Ray::new(self.eye + sx * self.right + sy * self.true_up, self.forward)
            }
        }
    }

    /// The width of a pixel where its ray has travelled `t` (the G-buffer's footprint, for
    /// texture filtering): `t * 2 tan(fov / 2) / H` for a pinhole, growing with the distance;
    /// `height / H` for an orthographic camera, the same at every distance.
    #[inline]
    pub fn pixel_footprint(&self, t: f64) -> f64 {
        match self.projection {
            Projection::Perspective { .. } => t * (2.0 * self.half_height / self.height as f64),
            Projection::Orthographic { height } => height / self.height as f64,
        }
    }

    /// Eye position: the pinhole, or the centre of an orthographic camera's image plane.
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// The point looked at.
    pub fn target(&self) -> DVec3 {
        self.target
    }

    /// The up vector as given.
    pub fn up(&self) -> DVec3 {
        self.up
    }

    /// The projection.
    pub fn projection(&self) -> Projection {
        self.projection
    }

    /// Vertical field of view in degrees of a pinhole camera; `None` for an orthographic one.
    pub fn fov_deg(&self) -> Option<f64> {
        match self.projection {
            Projection::Perspective { fov_deg } => Some(fov_deg),
            Projection::Orthographic { .. } => None,
        }
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Unit viewing direction.
    pub fn forward(&self) -> DVec3 {
        self.forward
    }

    /// Unit vector to the image's right: `normalize(forward x up)`.
    pub fn right(&self) -> DVec3 {
        self.right
    }

    /// Unit vector to the image's top: `right x forward` (up made perpendicular to the view).
    pub fn image_up(&self) -> DVec3 {
        self.true_up
    }

    /// Half the image's height: `tan(fov / 2)` for a pinhole (at unit distance), `height / 2`
    /// world units for an orthographic camera.
    pub fn half_height(&self) -> f64 {
        self.half_height
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_of_odd_image_looks_forward() {
        let cam = Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 60.0, 3, 3).unwrap();
        let r = cam.ray(1, 1);
        assert!((r.dir - DVec3::X).length() < 1e-12);
        // Top-left pixel looks left (+y, since right = x cross z = -y) and up.
        let tl = cam.ray(0, 0).dir;
        assert!(tl.y > 0.0 && tl.z > 0.0);
    }

    #[test]
    fn refuses_degenerate_cameras() {
        assert!(Camera::look_at(DVec3::ZERO, DVec3::ZERO, DVec3::Z, 45.0, 4, 4).is_err());
        assert!(Camera::look_at(DVec3::ZERO, DVec3::Z, DVec3::Z, 45.0, 4, 4).is_err());
        assert!(Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 180.0, 4, 4).is_err());
        assert!(Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 45.0, 0, 4).is_err());
    }

    #[test]
    fn a_camera_looking_straight_down_has_north_at_the_top() {
        let (eye, target) = (DVec3::new(10.0, 10.0, 10.0), DVec3::new(10.0, 10.0, 0.0));
        let (up, replaced) = Camera::usable_up(eye, target, DVec3::Z);
        assert!(replaced);
        let cam = Camera::look_at(eye, target, up, 45.0, 9, 9).unwrap();
        let (top, bottom) = (cam.ray(4, 0).dir, cam.ray(4, 8).dir);
        assert!(top.y > 0.0 && bottom.y < 0.0, "north at the top: {top} {bottom}");
        let (left, right) = (cam.ray(0, 4).dir, cam.ray(8, 4).dir);
        assert!(left.x < 0.0 && right.x > 0.0, "east on the right: {left} {right}");
        // Looking up, and along the north axis with up = north, give usable cameras too.
        let (up, _) = Camera::usable_up(DVec3::ZERO, DVec3::Z, DVec3::Z);
        assert!(Camera::look_at(DVec3::ZERO, DVec3::Z, up, 45.0, 4, 4).is_ok());
        let (up, replaced) = Camera::usable_up(DVec3::ZERO, DVec3::Y, DVec3::Y);
        assert!(replaced && Camera::look_at(DVec3::ZERO, DVec3::Y, up, 45.0, 4, 4).is_ok());
        // A usable up is kept.
        assert_eq!(Camera::usable_up(DVec3::ZERO, DVec3::X, DVec3::Z), (DVec3::Z, false));
    }

    #[test]
    fn orthographic_rays_start_on_the_eyes_plane_and_look_forward() {
        let (eye, target) = (DVec3::new(1.0, 2.0, 30.0), DVec3::new(11.0, 2.0, 0.0));
        let ortho = Projection::Orthographic { height: 6.0 };
        let cam = Camera::new(eye, target, DVec3::Z, ortho, 4, 3).unwrap();
        let (forward, right, up) = (cam.forward(), cam.right(), cam.image_up());
        for j in 0..3 {
            for i in 0..4 {
                let r = cam.ray(i, j);
                assert_eq!(r.dir, forward);
                // On the plane through the eye perpendicular to forward ...
                assert!((r.origin - eye).dot(forward).abs() < 1e-12);
                // ... at sx = (2 (i + 0.5) / W - 1) * (h / 2) * W / H, sy = (1 - 2 (j + 0.5) / H) * h / 2.
                let sx = (2.0 * (i as f64 + 0.5) / 4.0 - 1.0) * 3.0 * 4.0 / 3.0;
                let sy = (1.0 - 2.0 * (j as f64 + 0.5) / 3.0) * 3.0;
                assert!((r.origin - (eye + sx * right + sy * up)).length() < 1e-12);
            }
        }
        // Neighbouring pixels are h / H apart, across and down; the footprint is the same.
        assert!(((cam.ray(1, 0).origin - cam.ray(0, 0).origin).length() - 2.0).abs() < 1e-12);
        assert!(((cam.ray(0, 1).origin - cam.ray(0, 0).origin).length() - 2.0).abs() < 1e-12);
        assert_eq!(cam.pixel_footprint(1.0), 2.0);
        assert_eq!(cam.pixel_footprint(1e6), 2.0);
        assert_eq!(cam.fov_deg(), None);
        assert_eq!(cam.projection(), ortho);
        // The top-left pixel is up and to the left (right = forward x z points to -y).
        let tl = cam.ray(0, 0).origin - eye;
        assert!(tl.dot(up) > 0.0 && tl.y > 0.0);
    }

    #[test]
    fn a_pinhole_footprint_grows_with_the_distance() {
        let cam = Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 90.0, 8, 4).unwrap();
        assert!((cam.pixel_footprint(2.0) - 2.0 * 2.0 / 4.0).abs() < 1e-12);
        assert_eq!(cam.fov_deg(), Some(90.0));
        assert!(cam.ray(0, 0).origin == DVec3::ZERO && cam.ray(7, 3).origin == DVec3::ZERO);
    }

    #[test]
    fn an_offset_camera_samples_each_pixel_off_its_centre() {
        let cam = Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 60.0, 6, 4).unwrap();
        assert_eq!(cam.pixel_offset(), [0.0, 0.0]);
        let shifted = cam.with_pixel_offset(0.5, -0.25).unwrap();
        assert_eq!(shifted.pixel_offset(), [0.5, -0.25]);
        // Half a pixel to the right is half way to the next column's centre; a quarter up,
        // a quarter of the way to the row above.
        let halfway = |a: f64, b: f64| (a + b) / 2.0;
        assert!((shifted.screen_x(2) - halfway(cam.screen_x(2), cam.screen_x(3))).abs() < 1e-12);
        let quarter = cam.screen_y(1) + (cam.screen_y(0) - cam.screen_y(1)) / 4.0;
        assert!((shifted.screen_y(1) - quarter).abs() < 1e-12);
        for bad in [0.51, -0.6, f64::NAN, f64::INFINITY] {
            assert!(cam.with_pixel_offset(bad, 0.0).is_err());
            assert!(cam.with_pixel_offset(0.0, bad).is_err());
        }
    }

    #[test]
    fn refuses_orthographic_nonsense() {
        for height in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let ortho = Projection::Orthographic { height };
            assert!(Camera::new(DVec3::ZERO, DVec3::X, DVec3::Z, ortho, 4, 4).is_err());
        }
    }
}
