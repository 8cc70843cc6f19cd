//! What `relief render` and `relief view` draw, opened from the command line's
//! [`SceneArgs`]: a height field or an MLHM scene with its tracer choice, its shading and the
//! starting camera. Both commands open scenes here, so that a view's frame at rest is the
//! picture `relief render` makes of the same camera.

pub mod height_field;
pub mod mlhm;

use crate::args::SceneArgs;
use anyhow::Result;
use relief_core::{Aabb, Camera, DVec3};

/// The camera given on the command line, or a three-quarter view framing `bounds`. An up
/// vector parallel to the view (a camera looking straight down) is replaced by north, with a
/// note saying so.
pub fn camera(args: &SceneArgs, bounds: &Aabb) -> Result<Camera> {
    let (w, h) = args.size;
    let camera = match (args.eye, args.target) {
        (Some(eye), Some(target)) => {
            let given = args.up.unwrap_or(DVec3::Z);
            let (up, replaced) = Camera::usable_up(eye, target, given);
            if replaced {
                eprintln!(
                    "note: up {},{},{} is parallel to the view; using {},{},{} (north at the top \
                     of the image; set --up to choose another)",
                    given.x, given.y, given.z, up.x, up.y, up.z
                );
            }
            Camera::look_at(eye, target, up, args.fov, w, h)?
        }
        _ => Camera::frame_from(bounds, 225.0, 30.0, args.fov, w, h)?,
    };
    Ok(camera)
}
