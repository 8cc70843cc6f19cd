//! The camera a scene is seen from, as plain values say: an eye and a target, or the framing
//! of the scene's box from a compass direction; pinhole or orthographic.

use crate::error::RenderError;
use relief_core::{Aabb, Camera, DVec3, Framing, Lens, Projection};

/// The vertical field of view when none is given, in degrees.
pub const DEFAULT_FOV_DEG: f64 = 45.0;

/// The compass direction a framed camera looks towards, its elevation above the horizon, and
/// its distance from the target, if given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewAngles {
    /// Degrees clockwise from north (+y), -360..360.
    pub azimuth_deg: f64,
    /// Degrees above the horizon, more than 0 and at most 90.
    pub elevation_deg: f64,
    /// Metres from the target, positive.
    pub distance: Option<f64>,
}

/// Where a camera is and how it sees: `eye` and `target` (with `up`), or the framing of the
/// scene from `view` (default: from the south-west, 30 degrees up), pinhole (`fov_deg`) or
/// orthographic (`ortho`, of `ortho_height` metres, default: the framing's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraOptions {
    /// The image size, pixels.
    pub size: (u32, u32),
    /// The camera's position (with `target`).
    pub eye: Option<DVec3>,
    /// The point looked at (with `eye`, or with `view` instead of the scene's centre).
    pub target: Option<DVec3>,
    /// The up vector with `eye` and `target` [default: +z].
    pub up: Option<DVec3>,
    /// The framing's direction when no eye is given.
    pub view: Option<ViewAngles>,
    /// An orthographic camera.
    pub ortho: bool,
    /// The orthographic image's height, metres.
    pub ortho_height: Option<f64>,
    /// The perspective camera's vertical field of view, degrees [default: 45].
    pub fov_deg: Option<f64>,
}

impl CameraOptions {
    /// The default camera of an image of `width x height` pixels: the framing from the
    /// south-west, 30 degrees up, pinhole.
    pub fn framing(width: u32, height: u32) -> Self {
        CameraOptions {
            size: (width, height),
            eye: None,
            target: None,
            up: None,
            view: None,
            ortho: false,
            ortho_height: None,
            fov_deg: None,
        }
    }
}

/// A camera and what making it changed from what was asked, in words (a note), if anything.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedCamera {
    /// The camera.
    pub camera: Camera,
    /// A note for the user, e.g. that an up vector parallel to the view was replaced.
    pub note: Option<String>,
}

/// The camera `options` give for a scene within `bounds`. An up vector parallel to the view
/// (a camera looking straight down) is replaced by north, with a note saying so.
pub fn place_camera(options: &CameraOptions, bounds: &Aabb) -> Result<PlacedCamera, RenderError> {
    let (w, h) = options.size;
    let fov_deg = options.fov_deg.unwrap_or(DEFAULT_FOV_DEG);
    let lens = match options.ortho {
        true => Lens::Orthographic { height: options.ortho_height },
        false => Lens::Perspective { fov_deg },
    };
    let mut note = None;
    let camera = match (options.eye, options.target) {
        (Some(eye), Some(target)) => {
            let given = options.up.unwrap_or(DVec3::Z);
            let (up, replaced) = Camera::usable_up(eye, target, given);
            if replaced {
                note = Some(format!(
                    "note: up {},{},{} is parallel to the view; using {},{},{} (north at the top \
                     of the image; set --up to choose another)",
                    given.x, given.y, given.z, up.x, up.y, up.z
                ));
            }
            match lens {
                Lens::Perspective { fov_deg } => Camera::look_at(eye, target, up, fov_deg, w, h)?,
                Lens::Orthographic { height } => {
                    // Checks the eye, target and up before framing with them.
                    let probe = Projection::Orthographic { height: height.unwrap_or(1.0) };
                    let camera = Camera::new(eye, target, up, probe, w, h)?;
                    if height.is_some() {
                        camera
                    } else {
                        let framing = Framing {
                            towards_eye: eye - target,
                            up,
                            target: Some(target),
                            distance: Some((eye - target).length()),
                            lens,
                        };
                        let fitted = Camera::framed(bounds, &framing, w, h)?.projection();
                        Camera::new(eye, target, up, fitted, w, h)?
                    }
                }
            }
        }
        _ => match options.view {
            Some(view) => {
                let framing = Framing {
                    target: options.target,
                    distance: view.distance,
                    ..Framing::heading(view.azimuth_deg, view.elevation_deg, lens)
                };
                Camera::framed(bounds, &framing, w, h)?
            }
            None if options.ortho => {
                Camera::framed(bounds, &Framing::heading(45.0, 30.0, lens), w, h)?
            }
            None => Camera::frame_from(bounds, 225.0, 30.0, fov_deg, w, h)?,
        },
    };
    Ok(PlacedCamera { camera, note })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_straight_down_view_gets_north_up_and_a_note() {
        let bounds = Aabb::new(DVec3::ZERO, DVec3::new(10.0, 10.0, 1.0));
        let options = CameraOptions {
            eye: Some(DVec3::new(5.0, 5.0, 100.0)),
            target: Some(DVec3::new(5.0, 5.0, 0.0)),
            ..CameraOptions::framing(16, 9)
        };
        let placed = place_camera(&options, &bounds).unwrap();
        assert!(placed.note.unwrap().contains("parallel to the view"));
        let framed = place_camera(&CameraOptions::framing(16, 9), &bounds).unwrap();
        assert!(framed.note.is_none());
        assert_eq!(framed.camera.width(), 16);
    }
}
