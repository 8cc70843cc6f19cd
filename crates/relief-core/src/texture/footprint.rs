//! A pixel's footprint on the terrain, for texture filtering: where the rays through its edges
//! meet the tangent plane at its hit (Dick et al. 2009, section 3.3).
//!
//! The paper projects the two texel vectors of the photo onto the tangent plane at the hit,
//! then into screen space, and expresses the pixel's two unit vectors in that basis: to first
//! order, the pixel's footprint in texel space. Here the same parallelogram is found from the
//! other side: the rays through the middles of the pixel's left and right edges (and of its
//! top and bottom edges) are intersected with the tangent plane, and the differences of the
//! points they reach, seen from above (the photo is draped orthographically), span the
//! footprint. For a plane the two agree to first order in the pixel's size; the rays handle a
//! perspective footprint exactly, however grazing the view.

use crate::{Camera, DVec2, DVec3};

/// The footprint of one pixel on the terrain's tangent plane at its hit, seen from above: the
/// parallelogram the photo draped over the terrain must be averaged over for that pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundFootprint {
    /// World position of the hit.
    pub centre: DVec3,
    /// World (x, y) step across the pixel along the image's x axis: from the point the ray
    /// through the middle of its left edge meets the tangent plane to the right edge's.
    /// Non-finite when one of those rays does not meet the plane (it runs parallel to it or
    /// away from it): the footprint reaches the horizon.
    pub along_x: DVec2,
    /// The same along the image's y axis, from the pixel's top edge to its bottom edge.
    pub along_y: DVec2,
}

impl GroundFootprint {
    /// A footprint of no extent at `centre` (a point sample).
    pub fn point(centre: DVec3) -> Self {
        GroundFootprint { centre, along_x: DVec2::ZERO, along_y: DVec2::ZERO }
    }
}

/// The footprint of pixel `(i, j)` of `camera`, whose ray hits the terrain at `hit`, on the
/// plane through `hit` with slope `slope` (`dz/dx`, `dz/dy`).
///
/// ```
/// use relief_core::{Camera, DVec2, DVec3, Projection};
/// use relief_core::texture::ground_footprint;
/// // Straight down from 100 m with a 90 degree field of view over 2 x 2 pixels: each pixel
/// // covers 100 m of flat ground.
/// let camera = Camera::new(
///     DVec3::new(0.0, 0.0, 100.0), DVec3::ZERO, DVec3::Y,
///     Projection::Perspective { fov_deg: 90.0 }, 2, 2,
/// ).unwrap();
/// let hit = camera.ray(1, 1).at(100.0 * 1.5f64.sqrt());
/// let footprint = ground_footprint(&camera, 1, 1, hit, DVec2::ZERO);
/// assert!((footprint.along_x - DVec2::new(100.0, 0.0)).length() < 1e-9);
/// assert!((footprint.along_y - DVec2::new(0.0, -100.0)).length() < 1e-9);
/// ```
pub fn ground_footprint(
    camera: &Camera,
    i: u32,
    j: u32,
    hit: DVec3,
    slope: DVec2,
) -> GroundFootprint {
    let (sx, sy) = (camera.screen_x(i), camera.screen_y(j));
    // Screen coordinates advance 2 half_height / H per pixel (see Camera::screen_x).
    let half = camera.half_height() / camera.height() as f64;
    let normal = DVec3::new(-slope.x, -slope.y, 1.0);
    let on_plane = |sx: f64, sy: f64| -> DVec2 {
        let ray = camera.ray_through(sx, sy);
        let facing = normal.dot(ray.dir);
        let t = normal.dot(hit - ray.origin) / facing;
        if facing == 0.0 || !t.is_finite() || t <= 0.0 {
            return DVec2::splat(f64::INFINITY);
        }
        ray.at(t).truncate()
    };
    GroundFootprint {
        centre: hit,
        along_x: on_plane(sx + half, sy) - on_plane(sx - half, sy),
        along_y: on_plane(sx, sy - half) - on_plane(sx, sy + half),
    }
}

/// The slope (`dz/dx`, `dz/dy`) of the plane perpendicular to `normal`. A vertical face (a
/// wall of the `boxes` surface, or of the solid) has none: its slope is capped at 1000, so
/// that its footprint is long but finite.
pub fn slope_from_normal(normal: DVec3) -> DVec2 {
    const STEEPEST: f64 = 1000.0;
    let horizontal = normal.truncate();
    if normal.z.abs() * STEEPEST > horizontal.length() {
        -horizontal / normal.z
    } else {
        -horizontal.normalize_or_zero() * STEEPEST
    }
}

/// What a frame's footprints are computed from: per pixel, how far its ray went to the hit and
/// the normal there (a renderer's G-buffer).
pub trait PixelHits {
    /// The frame's width and height in pixels.
    fn size(&self) -> (usize, usize);

    /// The distance along pixel `(i, j)`'s ray to its hit: not finite for a miss, `None`
    /// outside the frame.
    fn hit_distance(&self, i: u32, j: u32) -> Option<f32>;

    /// The unit normal of pixel `(i, j)`'s hit (a pixel inside the frame).
    fn hit_normal(&self, i: u32, j: u32) -> DVec3;
}

/// The footprint of pixel `(i, j)` of the frame `hits`, which `camera` saw, on the tangent
/// plane of slope `slope_at(hit)` (or, where it gives none, the plane of the hit's normal);
/// `None` for a miss. The hit is rebuilt from the eye and the stored distance, as the deferred
/// pass does.
pub fn pixel_ground_footprint<H: PixelHits + ?Sized>(
    hits: &H,
    camera: &Camera,
    i: u32,
    j: u32,
    slope_at: &dyn Fn(DVec3) -> Option<DVec2>,
) -> Option<GroundFootprint> {
    let distance = hits.hit_distance(i, j)? as f64;
    if !distance.is_finite() {
        return None;
    }
    let hit = camera.ray(i, j).at(distance);
    let slope = slope_at(hit).unwrap_or_else(|| slope_from_normal(hits.hit_normal(i, j)));
    Some(ground_footprint(camera, i, j, hit, slope))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Projection;

    #[test]
    fn slopes_of_normals_and_walls() {
        let n = DVec3::new(-0.6, 0.0, 0.8);
        assert!((slope_from_normal(n) - DVec2::new(0.75, 0.0)).length() < 1e-12);
        assert_eq!(slope_from_normal(DVec3::Z), DVec2::ZERO);
        assert_eq!(slope_from_normal(DVec3::new(0.0, -1.0, 0.0)), DVec2::new(0.0, 1000.0));
    }

    /// A camera `height` above the plane z = 0 looking north, `elevation` degrees down, over
    /// a 101 x 101 image whose middle pixel looks along the view direction.
    fn grazing(height: f64, elevation_deg: f64) -> Camera {
        let e = elevation_deg.to_radians();
        Camera::new(
            DVec3::new(0.0, 0.0, height),
            DVec3::new(0.0, height / e.tan(), 0.0),
            DVec3::Z,
            Projection::Perspective { fov_deg: 30.0 },
            101,
            101,
        )
        .unwrap()
    }

    #[test]
    fn a_grazing_view_of_a_plane_has_the_analytic_footprint() {
        let (height, elevation) = (50.0, 4.0f64);
        let camera = grazing(height, elevation);
        let e = elevation.to_radians();
        let hit = camera.ray(50, 50).at(height / e.sin());
        assert!(hit.z.abs() < 1e-9, "the middle pixel's ray reaches the plane at {hit}");
        let footprint = ground_footprint(&camera, 50, 50, hit, DVec2::ZERO);
        // Half a pixel on the screen plane at unit distance.
        let h = (15f64).to_radians().tan() / 101.0;
        // Across the view the rays f +- h r (r level) reach the plane at the same depth
        // along f: the footprint is 2 h times the distance wide.
        let minor = 2.0 * h * height / e.sin();
        // Along the view, the rays f +- h u' (u' = (0, sin e, cos e)) reach the ground at
        // y = height (cos e + k sin e) / (sin e - k cos e).
        let y = |k: f64| height * (e.cos() + k * e.sin()) / (e.sin() - k * e.cos());
        let major = y(h) - y(-h);
        assert!((footprint.along_x - DVec2::new(minor, 0.0)).length() < 1e-9 * minor);
        assert!((footprint.along_y - DVec2::new(0.0, -major)).length() < 1e-9 * major);
        // In texels of 0.25 x 0.5 m: the principal axes are the two steps, the major one
        // along the view, about 1 / sin(e) = 14 times the minor one (in metres).
        let texel = DVec2::new(0.25, 0.5);
        let in_texels = crate::texture::TexelFootprint {
            centre: hit.truncate() / texel,
            along_x: footprint.along_x / texel,
            along_y: footprint.along_y / texel,
        };
        let axes = in_texels.axes();
        assert!((axes.major.length() - major / 0.5).abs() < 1e-9 * major);
        assert!(axes.major.x.abs() < 1e-9 * major, "major axis along y: {}", axes.major);
        assert!((axes.minor - minor / 0.25).abs() < 1e-9 * minor);
        assert!((major / minor - 1.0 / e.sin()).abs() < 0.01 / e.sin());
    }

    #[test]
    fn rays_that_miss_the_plane_give_an_endless_footprint() {
        // Looking level: the pixel's upper half sees the sky above the plane z = 0.
        let camera = Camera::new(
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.0, 10.0, 1.0),
            DVec3::Z,
            Projection::Perspective { fov_deg: 40.0 },
            3,
            3,
        )
        .unwrap();
        let f = ground_footprint(&camera, 1, 1, DVec3::new(0.0, 8.0, 0.0), DVec2::ZERO);
        assert!(!f.along_y.is_finite());
    }
}
