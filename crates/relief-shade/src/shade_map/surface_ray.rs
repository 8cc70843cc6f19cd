//! Where a shade map's rays start: on the terrain's surface at a sample, just above it.

use relief_core::{DVec3, HeightField, Ray};

/// How far above its sample point a shade map's ray starts, in cell sizes (the smaller of
/// `dx` and `dy`).
///
/// The rule for rays that start on the surface: the sample point `(x, y, value * z_scale)`
/// is a vertex of the `triangles` surface and the centre of a texel's top for `boxes`; the ray
/// starts `SURFACE_LIFT` cells (plus `1e-9` of the terrain's height range, and `1e-12` of the
/// point's largest coordinate for far-off georeferenced origins) straight above it and runs to infinity. So it does not find the
/// surface it starts on, and the surface still shadows itself: a ray that leaves the point
/// below a neighbouring face's plane meets that face within a few lifts. A sample on the
/// grid's border starts the same distance inside it, so that a ray along the border (the sun
/// due north of the west edge) runs over the surface, not exactly in the plane of the solid's
/// wall. The tracers work in `f64`, whose rounding at the point stays more than a million
/// times smaller.
pub const SURFACE_LIFT: f64 = 1e-6;

/// Lift per metre of the terrain's height range: the solid's walls reach down to its lowest
/// sample, and a tracer's tolerance on such a face grows with its size.
const RELIEF_LIFT: f64 = 1e-9;

/// Relative lift that covers the rounding of large world coordinates.
const COORDINATE_LIFT: f64 = 1e-12;

/// The ray from the surface at sample (`col`, `row`) of `field` in direction `dir` (see
/// [`SURFACE_LIFT`]).
pub fn surface_ray(field: &HeightField, col: usize, row: usize, dir: DVec3) -> Ray {
    Ray::new(surface_origin(field, col, row), dir)
}

/// The origin of every ray from sample (`col`, `row`): its point lifted by [`SURFACE_LIFT`].
pub fn surface_origin(field: &HeightField, col: usize, row: usize) -> DVec3 {
    surface_origin_within(field, col, row, [field.min_sample(), field.max_sample()])
}

/// [`surface_origin`] for a `field` that is a window of a raster whose lowest and highest
/// samples are `span`: the lift is the raster's, so that a window's rays are the raster's.
pub fn surface_origin_within(field: &HeightField, col: usize, row: usize, span: [f32; 2]) -> DVec3 {
    SurfaceLift::new(field, span).origin(field, col, row)
}

/// The part of the lift of [`SURFACE_LIFT`] that is the same for every sample of a field,
/// made once: [`SurfaceLift::origin`] is [`surface_origin_within`], bit for bit.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SurfaceLift {
    /// The cells' and the terrain's range's share of the lift.
    base: f64,
}

impl SurfaceLift {
    /// The lift of `field`'s samples, `span` its raster's lowest and highest samples.
    pub(crate) fn new(field: &HeightField, span: [f32; 2]) -> SurfaceLift {
        let g = field.geometry();
        let relief = (span[1] - span[0]) as f64 * g.z_scale;
        SurfaceLift { base: SURFACE_LIFT * g.dx.min(g.dy) + RELIEF_LIFT * relief }
    }

    /// The lift over world point `point`.
    #[inline(always)]
    pub(crate) fn at(self, point: DVec3) -> f64 {
        self.at_largest(point.abs().max_element())
    }

    /// The lift over a world point whose largest coordinate in magnitude is `largest`.
    #[inline(always)]
    pub(crate) fn at_largest(self, largest: f64) -> f64 {
        self.base + COORDINATE_LIFT * largest
    }

    /// The ray origin of sample (`col`, `row`) of `field`: see [`surface_origin`].
    #[inline]
    pub(crate) fn origin(self, field: &HeightField, col: usize, row: usize) -> DVec3 {
        let g = field.geometry();
        let grid = DVec3::new(col as f64 + 0.5, row as f64 + 0.5, field.sample(col, row) as f64);
        let point = g.point_to_world(grid);
        let lift = self.at(point);
        point
            + DVec3::new(inward(col, field.width(), lift), inward(row, field.height(), lift), lift)
    }
}

/// How far a ray from sample `k` of `n` along one axis starts inside the grid: `lift` on the
/// first, `-lift` on the last, 0 elsewhere (and on a grid one sample wide).
#[inline(always)]
pub(crate) fn inward(k: usize, n: usize, lift: f64) -> f64 {
    match (k, n) {
        (_, 1) => 0.0,
        (0, _) => lift,
        (k, n) if k + 1 == n => -lift,
        _ => 0.0,
    }
}
