//! Automatic framing: the camera that shows a whole box from a given direction, pinhole or
//! orthographic, at the distance (and, for an orthographic camera, the image height) that
//! fits it.

use crate::{Aabb, Camera, CoreError, Projection};
use glam::DVec3;

/// The projection of a framed camera: a pinhole of a given field of view, or an orthographic
/// camera whose image height is given or fitted to the box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Lens {
    /// A pinhole with this vertical field of view in degrees.
    Perspective {
        /// Vertical field of view in degrees.
        fov_deg: f64,
    },
    /// An orthographic camera with this image height in world units, or (`None`) the smallest
    /// height, plus a 5% margin, at which the whole box is in the image.
    Orthographic {
        /// Vertical extent of the image in world units, if fixed.
        height: Option<f64>,
    },
}

/// How [`Camera::framed`] places a camera around a box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Framing {
    /// The direction from the target towards the eye: a unit vector (within 1e-12 it is taken
    /// as it is; any other length but zero is normalized).
    pub towards_eye: DVec3,
    /// The camera's up vector (not parallel to `towards_eye`).
    pub up: DVec3,
    /// The point looked at, or (`None`) the point that centres the box's image: near the
    /// box's centre.
    pub target: Option<DVec3>,
    /// The eye's distance from the target, or (`None`) the framing's: for a pinhole the
    /// smallest at which every corner of the box is in the image, plus 5%; for an
    /// orthographic camera the distance at which the eye's plane clears every corner of the
    /// box by 5% of its diagonal (so that every ray starts outside it).
    pub distance: Option<f64>,
    /// The projection.
    pub lens: Lens,
}

impl Framing {
    /// The framing of a camera looking towards the compass `azimuth_deg` (clockwise from
    /// north, +y; 90 is east, +x), from `elevation_deg` above the horizon: the eye is on the
    /// far side of the target from the azimuth (azimuth 0 puts it south of the target,
    /// looking north), and looks down at that angle. The image's top is
    /// towards the azimuth: up is z, or, for a view within 1e-6 radians of vertical, the
    /// azimuth's horizontal direction, so a view straight down (90 degrees, then exactly
    /// vertical) with azimuth 0 is a map with north at the top and east on the right.
    pub fn heading(azimuth_deg: f64, elevation_deg: f64, lens: Lens) -> Framing {
        let (az, el) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
        let towards = DVec3::new(az.sin(), az.cos(), 0.0);
        let towards_eye = if elevation_deg.abs() == 90.0 {
            DVec3::new(0.0, 0.0, elevation_deg.signum())
        } else {
            DVec3::new(-towards.x * el.cos(), -towards.y * el.cos(), el.sin())
        };
        let up = if el.cos().abs() < 1e-6 { towards * elevation_deg.signum() } else { DVec3::Z };
        Framing { towards_eye, up, target: None, distance: None, lens }
    }
}

impl Camera {
    /// A three-quarter view from the south-west at 30 degrees elevation that fits `bounds`
    /// into a `width x height` image with a 45 degree vertical field of view.
    pub fn frame(bounds: &Aabb, width: u32, height: u32) -> Result<Self, CoreError> {
        Self::frame_from(bounds, 225.0, 30.0, 45.0, width, height)
    }

    /// Frames `bounds` with a pinhole seen from the compass `azimuth_deg` (0 = north, 90 =
    /// east) at `elevation_deg` above the horizon: the eye sits on that side of the box's
    /// centre, at the smallest distance (plus a 5% margin) at which every corner of the box is
    /// in the image ([`Camera::framed`]). Unlike [`Framing::heading`], the azimuth here is the
    /// side the eye is on: 225 is a view from the south-west, looking north-east.
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
        let lens = Lens::Perspective { fov_deg };
        let framing = Framing { towards_eye, up, target: None, distance: None, lens };
        Self::framed(bounds, &framing, width, height)
    }

    /// The camera of `framing` around `bounds` for a `width x height` image.
    ///
    /// Fails when the framing's direction, distance or lens is unusable (zero or not finite,
    /// not positive, up parallel to the view) or `bounds` is not finite.
    pub fn framed(
        bounds: &Aabb,
        framing: &Framing,
        width: u32,
        height: u32,
    ) -> Result<Self, CoreError> {
        let bad = |msg: String| Err(CoreError::Camera(msg));
        if !(bounds.min.is_finite() && bounds.max.is_finite()) {
            return bad(format!("cannot frame the unbounded box {:?}", bounds));
        }
        let length = framing.towards_eye.length();
        if !(length.is_finite() && length > 0.0) {
            return bad(format!("view direction {} is zero or not finite", framing.towards_eye));
        }
        if let Some(d) = framing.distance {
            if !(d.is_finite() && d > 0.0) {
                return bad(format!("distance {d} from the target must be positive and finite"));
            }
        }
        let towards_eye = if (length - 1.0).abs() < 1e-12 {
            framing.towards_eye
        } else {
            framing.towards_eye / length
        };
        let corners: [DVec3; 8] = std::array::from_fn(|k| {
            DVec3::new(
                if k & 1 == 0 { bounds.min.x } else { bounds.max.x },
                if k & 2 == 0 { bounds.min.y } else { bounds.max.y },
                if k & 4 == 0 { bounds.min.z } else { bounds.max.z },
            )
        });
        match framing.lens {
            Lens::Perspective { fov_deg } => {
                frame_pinhole(bounds, &corners, towards_eye, framing, fov_deg, width, height)
            }
            Lens::Orthographic { height: image_height } => frame_orthographic(
                bounds,
                &corners,
                towards_eye,
                framing,
                image_height,
                width,
                height,
            ),
        }
    }
}

/// [`Camera::framed`] with a pinhole of `fov_deg`.
fn frame_pinhole(
    bounds: &Aabb,
    corners: &[DVec3; 8],
    towards_eye: DVec3,
    framing: &Framing,
    fov_deg: f64,
    width: u32,
    height: u32,
) -> Result<Camera, CoreError> {
    let (up, projection) = (framing.up, Projection::Perspective { fov_deg });
    // Orientation is fixed by the direction; find the distance at which every corner fits,
    // then move the target so the box's image is centred, and fit again. A given target
    // stays: one fit.
    let mut target = framing.target.unwrap_or(bounds.center());
    let mut camera = Camera::new(target + towards_eye, target, up, projection, width, height)?;
    let tan_v = camera.half_height();
    let tan_h = tan_v * width as f64 / height as f64;
    let rounds = if framing.target.is_some() { 1 } else { 4 };
    for _ in 0..rounds {
        let distance = match framing.distance {
            Some(d) => d,
            None => {
                let mut distance: f64 = 0.0;
                for &corner in corners {
                    let c = corner - target;
                    let depth = c.dot(camera.forward());
                    let needed_x = c.dot(camera.right()).abs() / tan_h - depth;
                    let needed_y = c.dot(camera.image_up()).abs() / tan_v - depth;
                    distance = distance.max(needed_x).max(needed_y);
                }
                (distance * 1.05).max(1e-3 * bounds.diagonal().max(1e-9))
            }
        };
        camera =
            Camera::new(target + towards_eye * distance, target, up, projection, width, height)?;
        // A given target stays; so does the box's centre when a given distance puts the eye
        // so close that a corner is not in front of it (its image would not bound the box's).
        let behind = || corners.iter().any(|&c| (c - camera.eye()).dot(camera.forward()) <= 0.0);
        if framing.target.is_some() || behind() {
            break;
        }
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for &corner in corners {
            let v = corner - camera.eye();
            let depth = v.dot(camera.forward());
            let p =
                DVec3::new(v.dot(camera.right()) / depth, v.dot(camera.image_up()) / depth, 0.0);
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let mid = 0.5 * (lo + hi) * distance;
        target += camera.right() * mid.x + camera.image_up() * mid.y;
    }
    Ok(camera)
}

/// [`Camera::framed`] with an orthographic camera of `image_height` (`None`: fitted).
fn frame_orthographic(
    bounds: &Aabb,
    corners: &[DVec3; 8],
    towards_eye: DVec3,
    framing: &Framing,
    image_height: Option<f64>,
    width: u32,
    height: u32,
) -> Result<Camera, CoreError> {
    let up = framing.up;
    let floor = 1e-3 * bounds.diagonal().max(1e-9);
    // The orientation alone, to project the corners onto the image plane.
    let start = framing.target.unwrap_or(bounds.center());
    let probe = Camera::new(
        start + towards_eye,
        start,
        up,
        Projection::Orthographic { height: 1.0 },
        width,
        height,
    )?;
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &corner in corners {
        let c = corner - start;
        let p = DVec3::new(c.dot(probe.right()), c.dot(probe.image_up()), 0.0);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    // The projection is linear: centring the box's image takes one step.
    let (target, half) = match framing.target {
        Some(target) => (target, lo.abs().max(hi.abs())),
        None => {
            let mid = 0.5 * (lo + hi);
            (start + probe.right() * mid.x + probe.image_up() * mid.y, 0.5 * (hi - lo))
        }
    };
    let image_height = image_height.unwrap_or_else(|| {
        let aspect = height as f64 / width as f64;
        (2.0 * half.y.max(half.x * aspect) * 1.05).max(floor)
    });
    let distance = framing.distance.unwrap_or_else(|| {
        let beyond = corners.iter().map(|&c| (c - target).dot(towards_eye)).fold(0.0, f64::max);
        (beyond + 0.05 * bounds.diagonal()).max(floor)
    });
    Camera::new(
        target + towards_eye * distance,
        target,
        up,
        Projection::Orthographic { height: image_height },
        width,
        height,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corners(b: &Aabb) -> impl Iterator<Item = DVec3> + '_ {
        (0..8).map(move |k| {
            DVec3::new(
                if k & 1 == 0 { b.min.x } else { b.max.x },
                if k & 2 == 0 { b.min.y } else { b.max.y },
                if k & 4 == 0 { b.min.z } else { b.max.z },
            )
        })
    }

    #[test]
    fn framing_keeps_every_corner_in_view() {
        let b = Aabb::new(DVec3::new(0.0, 0.0, 0.0), DVec3::new(100.0, 50.0, 10.0));
        let cam = Camera::frame(&b, 160, 90).unwrap();
        for c in corners(&b) {
            let v = c - cam.eye();
            let depth = v.dot(cam.forward());
            let x = v.dot(cam.right()) / depth / (cam.half_height() * 160.0 / 90.0);
            let y = v.dot(cam.image_up()) / depth / cam.half_height();
            assert!(x.abs() <= 1.0 && y.abs() <= 1.0, "corner {c} at ({x}, {y})");
        }
    }

    #[test]
    fn a_heading_of_zero_puts_the_eye_south_looking_north() {
        let lens = Lens::Perspective { fov_deg: 45.0 };
        let north = Framing::heading(0.0, 30.0, lens).towards_eye;
        assert!(north.y < 0.0 && north.x.abs() < 1e-12 && (north.z - 0.5).abs() < 1e-12);
        let east = Framing::heading(90.0, 30.0, lens).towards_eye;
        assert!(east.x < 0.0 && east.y.abs() < 1e-12, "the eye is west, looking east");
        let north_west = Framing::heading(-45.0, 30.0, lens).towards_eye;
        assert!(north_west.x > 0.0 && north_west.y < 0.0, "the eye is south-east");
        let b = Aabb::new(DVec3::ZERO, DVec3::new(40.0, 20.0, 5.0));
        let cam = Camera::framed(&b, &Framing::heading(0.0, 30.0, lens), 64, 48).unwrap();
        assert!(cam.eye().y < b.min.y && cam.forward().y > 0.0);
        assert!(cam.right().x > 0.999, "east on the right: {}", cam.right());
    }

    #[test]
    fn straight_down_is_exactly_vertical_with_the_azimuth_at_the_top() {
        let lens = Lens::Orthographic { height: None };
        let b = Aabb::new(DVec3::ZERO, DVec3::new(40.0, 20.0, 5.0));
        let map = Camera::framed(&b, &Framing::heading(0.0, 90.0, lens), 64, 48).unwrap();
        assert_eq!(map.forward(), -DVec3::Z);
        assert_eq!(map.image_up(), DVec3::Y, "north up");
        assert_eq!(map.right(), DVec3::X, "east right");
        let east_up = Camera::framed(&b, &Framing::heading(90.0, 90.0, lens), 64, 48).unwrap();
        assert!((east_up.image_up() - DVec3::X).length() < 1e-12);
    }

    #[test]
    fn orthographic_framing_fits_the_box_and_starts_every_ray_outside_it() {
        let b = Aabb::new(DVec3::new(-10.0, 5.0, 0.0), DVec3::new(90.0, 55.0, 10.0));
        for (az, el) in [(0.0, 90.0), (30.0, 45.0), (-120.0, 10.0), (200.0, 89.9999999)] {
            let framing = Framing::heading(az, el, Lens::Orthographic { height: None });
            let cam = Camera::framed(&b, &framing, 80, 60).unwrap();
            let Projection::Orthographic { height } = cam.projection() else { panic!() };
            let width = height * 80.0 / 60.0;
            let (mut top, mut side) = (0.0f64, 0.0f64);
            for c in corners(&b) {
                let v = c - cam.eye();
                assert!(v.dot(cam.forward()) > 0.0, "corner {c} in front of the eye's plane");
                let (x, y) =
                    (v.dot(cam.right()) / (width / 2.0), v.dot(cam.image_up()) / (height / 2.0));
                assert!(x.abs() <= 1.0 && y.abs() <= 1.0, "{az},{el}: corner {c} at ({x}, {y})");
                (top, side) = (top.max(y.abs()), side.max(x.abs()));
            }
            // Centred, and tight to 5% along one axis.
            assert!((top.max(side) - 1.0 / 1.05).abs() < 1e-9, "{az},{el}: {top} {side}");
        }
    }

    #[test]
    fn a_given_target_and_distance_are_kept() {
        let b = Aabb::new(DVec3::ZERO, DVec3::new(40.0, 20.0, 5.0));
        let target = DVec3::new(3.0, 4.0, 1.0);
        for lens in [Lens::Perspective { fov_deg: 30.0 }, Lens::Orthographic { height: None }] {
            let framing = Framing {
                target: Some(target),
                distance: Some(50.0),
                ..Framing::heading(10.0, 40.0, lens)
            };
            let cam = Camera::framed(&b, &framing, 32, 32).unwrap();
            assert_eq!(cam.target(), target);
            assert!(((cam.eye() - target).length() - 50.0).abs() < 1e-9);
            // Without a distance, the whole box is still in view around that target.
            let framing = Framing { distance: None, ..framing };
            let cam = Camera::framed(&b, &framing, 32, 32).unwrap();
            assert_eq!(cam.target(), target);
            for c in corners(&b) {
                let r = cam.ray(0, 0);
                let v = c - cam.eye();
                assert!(v.dot(cam.forward()) > 0.0, "{lens:?}: {c} in front ({r:?})");
            }
        }
    }

    #[test]
    fn a_distance_inside_the_view_of_the_box_looks_at_its_centre() {
        // An eye 150 m from the centre of a 256 m square, above it: corners behind the eye.
        let b = Aabb::new(DVec3::new(0.0, 0.0, 5.0), DVec3::new(256.0, 256.0, 32.0));
        let framing = Framing {
            distance: Some(150.0),
            ..Framing::heading(45.0, 35.0, Lens::Perspective { fov_deg: 45.0 })
        };
        let cam = Camera::framed(&b, &framing, 160, 90).unwrap();
        assert!((cam.target() - b.center()).length() < 1e-9, "{}", cam.target());
        assert!(((cam.eye() - b.center()).length() - 150.0).abs() < 1e-9);
    }

    #[test]
    fn unusable_framings_are_refused() {
        let b = Aabb::new(DVec3::ZERO, DVec3::new(4.0, 2.0, 1.0));
        let lens = Lens::Orthographic { height: None };
        let base = Framing::heading(0.0, 45.0, lens);
        for framing in [
            Framing { towards_eye: DVec3::ZERO, ..base },
            Framing { towards_eye: DVec3::NAN, ..base },
            Framing { distance: Some(0.0), ..base },
            Framing { distance: Some(f64::INFINITY), ..base },
            Framing { lens: Lens::Orthographic { height: Some(-1.0) }, ..base },
            Framing { lens: Lens::Perspective { fov_deg: 180.0 }, ..base },
            Framing { up: base.towards_eye, ..base },
        ] {
            assert!(Camera::framed(&b, &framing, 8, 8).is_err(), "{framing:?}");
        }
        let unbounded = Aabb::new(DVec3::ZERO, DVec3::new(f64::INFINITY, 1.0, 1.0));
        assert!(Camera::framed(&unbounded, &base, 8, 8).is_err());
    }
}
