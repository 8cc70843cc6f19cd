//! Which octree nodes a camera cannot see: boxes wholly behind the eye or beyond one side of
//! the image.

use relief_core::{Camera, DVec3};

/// Whether the box `lo`..`hi` lies wholly outside the camera's view: all its corners behind
/// the eye, or beyond one side of the image.
pub(crate) fn outside_view(camera: &Camera, lo: DVec3, hi: DVec3) -> bool {
    let half_h = camera.half_height();
    let half_w = half_h * camera.width() as f64 / camera.height() as f64;
    let perspective = camera.fov_deg().is_some();
    let mut outside = [true; 5];
    for c in 0..8 {
        let p = DVec3::new(
            if c & 1 == 0 { lo.x } else { hi.x },
            if c & 2 == 0 { lo.y } else { hi.y },
            if c & 4 == 0 { lo.z } else { hi.z },
        );
        let d = p - camera.eye();
        let (x, y, z) = (d.dot(camera.right()), d.dot(camera.image_up()), d.dot(camera.forward()));
        let scale = if perspective { z.max(0.0) } else { 1.0 };
        let checks = [
            z < 0.0,
            x > scale * half_w,
            x < -scale * half_w,
            y > scale * half_h,
            y < -scale * half_h,
        ];
        for (o, check) in outside.iter_mut().zip(checks) {
            *o &= check;
        }
    }
    outside.iter().any(|&o| o)
}
