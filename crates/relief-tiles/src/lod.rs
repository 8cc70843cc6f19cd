//! Which tiles a frame needs: view-frustum culling and a bound on the screen-space error
//! (Dick et al. 2009, section 4: 2/3 of a pixel by default).
//!
//! A tile of level `l` stands for the level-0 samples under it with a vertical error of at
//! most its record's `error` (the largest distance from a level-0 sample to the averaged
//! samples over it, summed over the levels in between). Seen by a pinhole camera from at least
//! `d` away, a vertical segment of length `e` spans an angle of at most `e / d`; on the image
//! plane an angle grows by at most `1 / cos^2` of the angle to the image's corner, so the
//! segment covers at most `e / (d * pixel angle) / cos^2(corner)` pixels ([`screen_error`]).
//! A tile is drawn when that bound is at most the tolerance; otherwise its children are
//! considered, down to level 0. A tolerance of 0 asks for level 0 everywhere.

use crate::{TileId, TileStore};
use relief_core::{Aabb, Camera, DVec3, Projection, Surface};

/// The most pixels a vertical error of `error` world units anywhere in `bounds` covers in
/// `camera`'s image (for points in the view; see the module's documentation). Infinite when
/// the eye is inside `bounds` and the error is not zero.
pub fn screen_error(camera: &Camera, error: f64, bounds: &Aabb) -> f64 {
    if error <= 0.0 {
        return 0.0;
    }
    let pixel_at_unit = 2.0 * camera.half_height() / camera.height() as f64;
    match camera.projection() {
        Projection::Orthographic { .. } => error / pixel_at_unit,
        Projection::Perspective { .. } => {
            let nearest = camera.eye().clamp(bounds.min, bounds.max);
            let d = nearest.distance(camera.eye());
            if d == 0.0 {
                return f64::INFINITY;
            }
            let aspect = camera.width() as f64 / camera.height() as f64;
            let tan_corner_sq = camera.half_height().powi(2) * (1.0 + aspect * aspect);
            (error / d) * (1.0 + tan_corner_sq) / pixel_at_unit
        }
    }
}

/// Whether `bounds` lies wholly outside `camera`'s view (behind it or beyond a side of the
/// image); conservative: a box that is not reported outside may still be.
pub fn outside_view(camera: &Camera, bounds: &Aabb) -> bool {
    let (f, r, u) = (camera.forward(), camera.right(), camera.image_up());
    let s = camera.half_height();
    let sx = s * camera.width() as f64 / camera.height() as f64;
    let corners = (0..8).map(|k| {
        let p = DVec3::new(
            if k & 1 == 0 { bounds.min.x } else { bounds.max.x },
            if k & 2 == 0 { bounds.min.y } else { bounds.max.y },
            if k & 4 == 0 { bounds.min.z } else { bounds.max.z },
        );
        let v = p - camera.eye();
        (v.dot(r), v.dot(u), v.dot(f))
    });
    let corners: Vec<(f64, f64, f64)> = corners.collect();
    let all = |test: &dyn Fn(&(f64, f64, f64)) -> bool| corners.iter().all(test);
    match camera.projection() {
        Projection::Perspective { .. } => {
            all(&|c| c.2 <= 0.0)
                || all(&|c| c.0 > c.2 * sx)
                || all(&|c| c.0 < -c.2 * sx)
                || all(&|c| c.1 > c.2 * s)
                || all(&|c| c.1 < -c.2 * s)
        }
        Projection::Orthographic { .. } => {
            all(&|c| c.0 > sx) || all(&|c| c.0 < -sx) || all(&|c| c.1 > s) || all(&|c| c.1 < -s)
        }
    }
}

/// The world box of tile `id` and everything under it: its rectangle from the floor to the
/// highest sample below it.
pub fn tile_bounds(store: &TileStore, id: TileId, surface: Surface) -> Aabb {
    let g = store.geometry();
    let rect = store.layout().rect(id, &g, surface);
    Aabb::new(
        DVec3::new(rect.min[0], rect.min[1], store.floor() as f64 * g.z_scale),
        DVec3::new(rect.max[0], rect.max[1], store.subtree_max(id) as f64 * g.z_scale),
    )
}

/// The tiles `camera` needs at a screen-space error of at most `max_error_px` pixels
/// (0: level 0 everywhere). With `cull`, tiles wholly outside the view are left out (shadow
/// rays may need them: renders with shadows pass `false`). Tiles of nothing but voids are left
/// out. The tiles cover the (visible part of the) raster once each.
pub fn select_tiles(
    store: &TileStore,
    camera: &Camera,
    surface: Surface,
    max_error_px: f64,
    cull: bool,
) -> Vec<TileId> {
    let mut chosen = Vec::new();
    let mut stack = vec![store.layout().root()];
    let z_scale = store.geometry().z_scale;
    while let Some(id) = stack.pop() {
        let Some(record) = store.record(id) else { continue };
        if store.subtree_max(id) < store.floor() {
            continue;
        }
        let bounds = tile_bounds(store, id, surface);
        if cull && outside_view(camera, &bounds) {
            continue;
        }
        let fine_enough = max_error_px > 0.0
            && screen_error(camera, record.error as f64 * z_scale, &bounds) <= max_error_px;
        if id.level == 0 || fine_enough {
            chosen.push(id);
        } else {
            stack.extend(store.layout().children(id));
        }
    }
    chosen.sort();
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Pixel coordinates of `p` in `camera`'s image (perspective), `None` behind the eye.
    fn project(camera: &Camera, p: DVec3) -> Option<(f64, f64)> {
        let v = p - camera.eye();
        let z = v.dot(camera.forward());
        if z <= 0.0 {
            return None;
        }
        let (sx, sy) = (v.dot(camera.right()) / z, v.dot(camera.image_up()) / z);
        let pixel = 2.0 * camera.half_height() / camera.height() as f64;
        Some((sx / pixel, sy / pixel))
    }

    proptest! {
        /// Any vertical error segment inside a box and inside the view covers at most the
        /// pixels the metric says.
        #[test]
        fn the_screen_error_bounds_projected_vertical_errors(
            eye in (-500.0..500.0f64, -500.0..500.0f64, 10.0..400.0f64),
            target in (-100.0..100.0f64, -100.0..100.0f64, -50.0..50.0f64),
            fov in 20.0..100.0f64,
            corner in (-300.0..300.0f64, -300.0..300.0f64, -50.0..50.0f64),
            size in (1.0..100.0f64, 1.0..100.0f64, 0.0..60.0f64),
            at in (0.0..1.0f64, 0.0..1.0f64, 0.0..1.0f64),
            error in 0.01..20.0f64,
        ) {
            let camera = Camera::look_at(
                DVec3::new(eye.0, eye.1, eye.2),
                DVec3::new(target.0, target.1, target.2),
                DVec3::Z,
                fov,
                640,
                360,
            ).unwrap();
            let min = DVec3::new(corner.0, corner.1, corner.2);
            let max = min + DVec3::new(size.0, size.1, size.2 + error);
            let bounds = Aabb::new(min, max);
            let p = DVec3::new(
                min.x + at.0 * size.0,
                min.y + at.1 * size.1,
                min.z + at.2 * size.2,
            );
            let q = p + DVec3::new(0.0, 0.0, error);
            let bound = screen_error(&camera, error, &bounds);
            if let (Some(a), Some(b)) = (project(&camera, p), project(&camera, q)) {
                let half = (320.0, 180.0);
                let inside = |c: (f64, f64)| c.0.abs() <= half.0 && c.1.abs() <= half.1;
                if inside(a) && inside(b) {
                    let moved = ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt();
                    prop_assert!(moved <= bound * (1.0 + 1e-9), "{moved} px > bound {bound}");
                }
            }
        }
    }

    #[test]
    fn boxes_behind_or_beside_the_view_are_outside_it() {
        let camera = Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 60.0, 100, 100).unwrap();
        let unit = |c: DVec3| Aabb::new(c, c + DVec3::ONE);
        assert!(outside_view(&camera, &unit(DVec3::new(-5.0, 0.0, 0.0))));
        assert!(outside_view(&camera, &unit(DVec3::new(5.0, 20.0, 0.0))));
        assert!(!outside_view(&camera, &unit(DVec3::new(5.0, -0.5, -0.5))));
        assert!(!outside_view(&camera, &Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0))));
    }
}
