//! The fixed views of a height field that `relief bench` and the performance measurements
//! trace, so that every measurement of relief (and of Embree beside it) sees the same rays.

use relief_core::{Camera, CoreError, DVec3, HeightField, Surface};

/// The names of [`benchmark_views`], in its order.
pub const BENCHMARK_VIEWS: [&str; 4] = ["three-quarter", "flight", "top-down", "cover"];

/// The benchmark's views of `field` at `width x height` pixels, named as in
/// [`BENCHMARK_VIEWS`]: a three-quarter overview, a low flight over the ground, top-down, and
/// the terrain covering the whole image.
///
/// ```
/// use relief_bench::{benchmark_views, BENCHMARK_VIEWS};
/// use relief_core::{GridGeometry, HeightField};
/// let field = HeightField::new(8, 8, vec![1.0; 64], GridGeometry::unit()).unwrap();
/// let views = benchmark_views(&field, 64, 36).unwrap();
/// assert_eq!(views.iter().map(|(name, _)| *name).collect::<Vec<_>>(), BENCHMARK_VIEWS);
/// ```
pub fn benchmark_views(
    field: &HeightField,
    width: u32,
    height: u32,
) -> Result<Vec<(&'static str, Camera)>, CoreError> {
    let (w, h) = (width, height);
    let bounds = field.world_bounds(Surface::Boxes);
    let size = bounds.max - bounds.min;
    let overview = Camera::frame_from(&bounds, 225.0, 30.0, 45.0, w, h)?;
    // Flight: from the south-west quarter towards the north-east, a little above the ground.
    let (col, row) = (field.width() / 5, field.height() / 5);
    let ground = field.sample(col, row) as f64 * field.geometry().z_scale;
    let eye = DVec3::new(
        bounds.min.x + 0.2 * size.x,
        bounds.min.y + 0.2 * size.y,
        ground + 0.03 * size.x.max(size.y),
    );
    let target = DVec3::new(bounds.min.x + 0.8 * size.x, bounds.min.y + 0.8 * size.y, ground);
    let flight = Camera::look_at(eye, target, DVec3::Z, 60.0, w, h)?;
    let centre = bounds.center();
    let above = DVec3::new(centre.x, centre.y, bounds.max.z + 1.2 * size.x.max(size.y));
    let top_down =
        Camera::look_at(above, DVec3::new(centre.x, centre.y, bounds.min.z), DVec3::Y, 45.0, w, h)?;
    let cover = cover_view(field, w, h)?;
    let [a, b, c, d] = BENCHMARK_VIEWS;
    Ok(vec![(a, overview), (b, flight), (c, top_down), (d, cover)])
}

/// The terrain filling the whole image (as in Baboud et al.'s Table 1): looking at its centre
/// from the south-west, 70 degrees up, with a 30 degree field of view, so every ray looks down
/// at least 45 degrees; as far as possible while every corner ray still reaches the lowest
/// level inside the triangles' footprint.
fn cover_view(field: &HeightField, w: u32, h: u32) -> Result<Camera, CoreError> {
    let b = field.world_bounds(Surface::Triangles);
    let target = DVec3::new(0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y), b.min.z);
    let (az, el) = (225f64.to_radians(), 70f64.to_radians());
    let towards_eye = DVec3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin());
    let unit = Camera::look_at(target + towards_eye, target, DVec3::Z, 30.0, w, h)?;
    // Where the corner rays of the camera at distance 1 meet the lowest level, relative to the
    // target; the footprint grows linearly with the distance.
    let mut distance = f64::INFINITY;
    for (i, j) in [(0, 0), (w - 1, 0), (0, h - 1), (w - 1, h - 1)] {
        let ray = unit.ray(i, j);
        let offset = ray.at((b.min.z - ray.origin.z) / ray.dir.z) - target;
        for axis in 0..2 {
            let (d, centre) = (offset[axis], target[axis]);
            let room = if d > 0.0 { b.max[axis] - centre } else { centre - b.min[axis] };
            if d != 0.0 {
                distance = distance.min(room / d.abs());
            }
        }
    }
    Camera::look_at(target + towards_eye * distance * 0.999, target, DVec3::Z, 30.0, w, h)
}
