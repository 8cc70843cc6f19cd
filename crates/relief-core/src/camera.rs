//! The pinhole camera of relief's conventions, and automatic framing of a scene.

use crate::{Aabb, CoreError, Ray};
use glam::DVec3;

/// A pinhole camera producing one ray per pixel of a `width x height` image.
///
/// forward = normalize(target - eye); right = normalize(forward x up); up' = right x forward.
/// Pixel (i, j), i the column from the left and j the row from the top, looks along
/// normalize(forward + sx * right + sy * up') with t = tan(fov / 2),
/// sx = (2 (i + 0.5) / W - 1) * t * W / H and sy = (1 - 2 (j + 0.5) / H) * t.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    eye: DVec3,
    target: DVec3,
    up: DVec3,
    fov_deg: f64,
    width: u32,
    height: u32,
    forward: DVec3,
    right: DVec3,
    true_up: DVec3,
    tan_half: f64,
}

impl Camera {
    /// The camera at `eye` looking at `target`, with `up` and a vertical field of view in degrees.
    pub fn look_at(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        fov_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, CoreError> {
        let bad = |msg: String| Err(CoreError::Camera(msg));
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return bad("eye, target and up must be finite".into());
        }
        if !(fov_deg.is_finite() && fov_deg > 0.0 && fov_deg < 180.0) {
            return bad(format!("field of view {fov_deg} must be between 0 and 180 degrees"));
        }
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
        let tan_half = (fov_deg.to_radians() / 2.0).tan();
        Ok(Camera { eye, target, up, fov_deg, width, height, forward, right, true_up, tan_half })
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

    /// A three-quarter view from the south-west at 30 degrees elevation that fits `bounds`
    /// into a `width x height` image with a 45 degree vertical field of view.
    pub fn frame(bounds: &Aabb, width: u32, height: u32) -> Result<Self, CoreError> {
        Self::frame_from(bounds, 225.0, 30.0, 45.0, width, height)
    }

    /// Frames `bounds` seen from the compass `azimuth_deg` (0 = north, 90 = east) at
    /// `elevation_deg` above the horizon: the eye sits on that side of the box's centre, at the
    /// smallest distance (plus a 5% margin) at which every corner of the box is in the image.
    pub fn frame_from(
        bounds: &Aabb,
        azimuth_deg: f64,
        elevation_deg: f64,
        fov_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, CoreError> {
        let (az, el) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
        let towards_eye = DVec3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin());
        let up = if el.cos().abs() < 1e-6 { DVec3::Y } else { DVec3::Z };
        let corners: [DVec3; 8] = std::array::from_fn(|k| {
            DVec3::new(
                if k & 1 == 0 { bounds.min.x } else { bounds.max.x },
                if k & 2 == 0 { bounds.min.y } else { bounds.max.y },
                if k & 4 == 0 { bounds.min.z } else { bounds.max.z },
            )
        });
        // Orientation is fixed by the direction; find the distance at which every corner fits,
        // then move the target so the box's image is centred, and fit again.
        let mut target = bounds.center();
        let mut camera = Camera::look_at(target + towards_eye, target, up, fov_deg, width, height)?;
        let tan_v = camera.tan_half;
        let tan_h = tan_v * width as f64 / height as f64;
        for _ in 0..4 {
            let mut distance: f64 = 0.0;
            for corner in corners {
                let c = corner - target;
                let depth = c.dot(camera.forward);
                let needed_x = c.dot(camera.right).abs() / tan_h - depth;
                let needed_y = c.dot(camera.true_up).abs() / tan_v - depth;
                distance = distance.max(needed_x).max(needed_y);
            }
            let distance = (distance * 1.05).max(1e-3 * bounds.diagonal().max(1e-9));
            camera = Camera::look_at(
                target + towards_eye * distance,
                target,
                up,
                fov_deg,
                width,
                height,
            )?;
            let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
            for corner in corners {
                let v = corner - camera.eye;
                let depth = v.dot(camera.forward);
                let p = DVec3::new(v.dot(camera.right) / depth, v.dot(camera.true_up) / depth, 0.0);
                lo = lo.min(p);
                hi = hi.max(p);
            }
            let mid = 0.5 * (lo + hi) * distance;
            target += camera.right * mid.x + camera.true_up * mid.y;
        }
        Ok(camera)
    }

    /// The ray through the centre of pixel (i, j), with a unit direction.
    #[inline]
    pub fn ray(&self, i: u32, j: u32) -> Ray {
        self.ray_through(self.screen_x(i), self.screen_y(j))
    }

    /// `sx` of pixel column `i`: `(2 (i + 0.5) / W - 1) * t * W / H`. A renderer that traces
    /// many pixels of the same columns and rows computes it once per column and passes it to
    /// [`Camera::ray_through`], which then gives exactly [`Camera::ray`].
    #[inline]
    pub fn screen_x(&self, i: u32) -> f64 {
        let (w, h) = (self.width as f64, self.height as f64);
        (2.0 * (i as f64 + 0.5) / w - 1.0) * self.tan_half * w / h
    }

    /// `sy` of pixel row `j`: `(1 - 2 (j + 0.5) / H) * t` (see [`Camera::screen_x`]).
    #[inline]
    pub fn screen_y(&self, j: u32) -> f64 {
        (1.0 - 2.0 * (j as f64 + 0.5) / self.height as f64) * self.tan_half
    }

    /// The ray along `normalize(forward + sx * right + sy * up')`.
    #[inline]
    pub fn ray_through(&self, sx: f64, sy: f64) -> Ray {
        let dir = (self.forward + sx * self.right + sy * self.true_up).normalize();
        Ray::new(self.eye, dir)
    }

    /// Eye position.
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

    /// Vertical field of view in degrees.
    pub fn fov_deg(&self) -> f64 {
        self.fov_deg
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
    fn framing_keeps_every_corner_in_view() {
        let b = Aabb::new(DVec3::new(0.0, 0.0, 0.0), DVec3::new(100.0, 50.0, 10.0));
        let cam = Camera::frame(&b, 160, 90).unwrap();
        for k in 0..8 {
            let c = DVec3::new(
                if k & 1 == 0 { 0.0 } else { 100.0 },
                if k & 2 == 0 { 0.0 } else { 50.0 },
                if k & 4 == 0 { 0.0 } else { 10.0 },
            );
            let v = c - cam.eye();
            let depth = v.dot(cam.forward);
            let x = v.dot(cam.right) / depth / (cam.tan_half * 160.0 / 90.0);
            let y = v.dot(cam.true_up) / depth / cam.tan_half;
            assert!(x.abs() <= 1.0 && y.abs() <= 1.0, "corner {c} at ({x}, {y})");
        }
    }
}
