//! Rasterized height-field cells equal the exact tracer: the meshes of random fields (with
//! holes, both surfaces), meshed as several regions and drawn into one target, against
//! `NaiveTracer` on every pixel of random cameras, low ones inside the terrain's bounding box
//! and orthographic ones included.

use proptest::prelude::*;
use relief_core::{
    Camera, DVec2, DVec3, GridGeometry, HeightField, Projection, SampleRegion, Surface,
};
use relief_mesh::{height_field_mesh, Culling, RasterTarget, Rasterizer};
use relief_trace::{NaiveTracer, Tracer};
use std::sync::Arc;

/// A random field: small integer heights (flat areas, equal diagonal sums: the ties of the
/// surface's rules) or arbitrary ones, holes, a random geometry.
fn field_strategy() -> impl Strategy<Value = HeightField> {
    (2usize..9, 2usize..9, any::<bool>(), 0u32..4).prop_flat_map(|(w, h, integers, hole_odds)| {
        let heights = if integers {
            prop::collection::vec((0u8..4).prop_map(f32::from), w * h).boxed()
        } else {
            prop::collection::vec(-2.0f32..3.0, w * h).boxed()
        };
        let holes = prop::collection::vec((0u32..10).prop_map(move |r| r < hole_odds), w * h);
        let geometry = (0.5..2.0f64, 0.5..2.0f64, 0.3..2.0f64, -5.0..5.0f64, -5.0..5.0f64);
        (heights, holes, geometry).prop_filter_map("all holes", move |(samples, holes, g)| {
            let geometry =
                GridGeometry { dx: g.0, dy: g.1, z_scale: g.2, origin: DVec2::new(g.3, g.4) };
            HeightField::new(w, h, samples, geometry).ok()?.with_holes(holes).ok()
        })
    })
}

/// Random cuts of `0..n` into consecutive ranges.
fn cuts(n: usize, seeds: &[usize]) -> Vec<(usize, usize)> {
    let mut points: Vec<usize> = seeds.iter().map(|s| s % (n + 1)).chain([0, n]).collect();
    points.sort_unstable();
    points.dedup();
    points.windows(2).map(|p| (p[0], p[1])).collect()
}

/// The whole field's mesh as several regions: texel blocks for boxes, blocks of squares
/// (regions overlapping by one sample) for triangles.
fn regions(field: &HeightField, surface: Surface, seeds: &[usize]) -> Vec<SampleRegion> {
    let (w, h) = (field.width(), field.height());
    let (nx, ny) = match surface {
        Surface::Boxes => (w, h),
        Surface::Triangles => (w - 1, h - 1),
    };
    let overlap = (surface == Surface::Triangles) as usize;
    let (half, rest) = seeds.split_at(seeds.len() / 2);
    let mut out = Vec::new();
    for (c0, c1) in cuts(nx, half) {
        for (r0, r1) in cuts(ny, rest) {
            out.push(SampleRegion::new(c0, r0, c1 + overlap, r1 + overlap));
        }
    }
    out
}

struct Comparison {
    pixels: usize,
    compared: usize,
    mismatches: Vec<String>,
}

fn compare(
    field: HeightField,
    surface: Surface,
    seeds: &[usize],
    camera: &Camera,
    culling: Culling,
) -> Comparison {
    let mut target = RasterTarget::for_camera(camera);
    let rasterizer = Rasterizer::with_tile_size(16).unwrap().with_culling(culling);
    let mut id = 0;
    for region in regions(&field, surface, seeds) {
        let mesh = height_field_mesh(&field, surface, region).unwrap();
        rasterizer.draw(camera, &mesh, id, &mut target).unwrap();
        id += mesh.triangle_count() as u32;
    }
    let tracer = NaiveTracer::new(Arc::new(field), surface);
    let mut result = Comparison { pixels: 0, compared: 0, mismatches: Vec::new() };
    for j in 0..camera.height() {
        for i in 0..camera.width() {
            result.pixels += 1;
            let ray = camera.ray(i, j);
            let exact = tracer.intersect(&ray);
            // A ray starting inside the solid hits at 0: the mesh has no such pixel.
            if exact.is_some_and(|h| h.t == 0.0) {
                continue;
            }
            result.compared += 1;
            let drawn = target.get(i as usize, j as usize).map(|(d, _)| d as f64);
            match (exact, drawn) {
                (None, None) => {}
                (Some(hit), Some(d)) if (d - hit.t).abs() <= 1e-4 * hit.t => {}
                (exact, drawn) => result.mismatches.push(format!(
                    "pixel ({i}, {j}): exact {:?} drawn {drawn:?}",
                    exact.map(|h| h.t)
                )),
            }
        }
    }
    result
}

fn camera_strategy() -> impl Strategy<Value = (DVec3, DVec3, Option<f64>)> {
    (
        (-0.3..1.3f64, -0.3..1.3f64, -0.5..2.0f64),
        (0.0..1.0f64, 0.0..1.0f64, 0.0..1.0f64),
        prop_oneof![3 => (30.0..100.0f64).prop_map(Some), 1 => Just(None)],
    )
        .prop_map(|(e, t, fov)| (DVec3::from(e), DVec3::from(t), fov))
}

/// A camera with eye and target given as fractions of the field's bounding box.
fn place(
    field: &HeightField,
    surface: Surface,
    (e, t, fov): (DVec3, DVec3, Option<f64>),
) -> Option<Camera> {
    let b = field.world_bounds(surface);
    let size = (b.max - b.min).max(DVec3::splat(1.0));
    let (eye, target) = (b.min + e * size, b.min + t * size);
    let projection = match fov {
        Some(fov_deg) => Projection::Perspective { fov_deg },
        None => Projection::Orthographic { height: 1.5 * size.length() },
    };
    Camera::new(eye, target, DVec3::Z, projection, 48, 36).ok()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// "Rasterized cells equal the exact tracer": hit or miss the same on every pixel, the
    /// distance to 1e-4 relative.
    ///
    /// The exceptions allowed are exact ties that rounding decides differently in the two
    /// computations: a pixel centre within rounding of a silhouette edge, or a ray grazing a
    /// face along its plane (both are measure-zero events for generic cameras; the integer
    /// heights here make flat faces and shared planes common). They are bounded by 0.2% of the
    /// pixels compared over all cases, and 1% in any one case; in 1200 cases (2 million
    /// pixels) run while writing this test, none occurred.
    #[test]
    fn rasterized_cells_equal_the_exact_tracer(
        field in field_strategy(),
        triangles in any::<bool>(),
        seeds in prop::collection::vec(0usize..16, 0..6),
        view in camera_strategy(),
        cull in any::<bool>(),
    ) {
        let surface = if triangles { Surface::Triangles } else { Surface::Boxes };
        let Some(camera) = place(&field, surface, view) else { return Ok(()); };
        // Seen from outside the closed, outward-wound solid, culling back faces changes nothing.
        let eye_inside = camera.fov_deg().is_some()
            && NaiveTracer::new(Arc::new(field.clone()), surface)
                .intersect(&camera.ray(0, 0))
                .is_some_and(|h| h.t == 0.0);
        let culling = if cull && !eye_inside { Culling::BackFaces } else { Culling::None };
        let result = compare(field, surface, &seeds, &camera, culling);
        prop_assert!(result.mismatches.len() * 100 <= result.compared,
            "{} of {} pixels differ: {:?}", result.mismatches.len(), result.compared, result.mismatches);
        let total = TOTALS.fetch_add(result.compared, std::sync::atomic::Ordering::Relaxed) + result.compared;
        let wrong = WRONG.fetch_add(result.mismatches.len(), std::sync::atomic::Ordering::Relaxed)
            + result.mismatches.len();
        prop_assert!(wrong * 500 <= total.max(5000), "{wrong} of {total} pixels differ so far");
        prop_assert!(result.pixels == 48 * 36);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// The meshes of adjacent regions close the solid without a crack or a doubled pixel: a
    /// ray from outside crosses the closed surface an even number of times, so every pixel
    /// whose ray starts outside the solid is covered an even number of times (the fill rule
    /// gives a pixel on a shared edge to one side only; a crack or a double would make it odd).
    #[test]
    fn region_meshes_close_the_solid(
        field in field_strategy(),
        triangles in any::<bool>(),
        seeds in prop::collection::vec(0usize..16, 0..6),
        view in camera_strategy(),
    ) {
        let surface = if triangles { Surface::Triangles } else { Surface::Boxes };
        let Some(camera) = place(&field, surface, view) else { return Ok(()); };
        let rasterizer = Rasterizer::with_tile_size(16).unwrap();
        let mut counts = vec![0u32; 48 * 36];
        for region in regions(&field, surface, &seeds) {
            let mesh = height_field_mesh(&field, surface, region).unwrap();
            for (total, c) in counts.iter_mut().zip(rasterizer.coverage_counts(&camera, &mesh)) {
                *total += c;
            }
        }
        let tracer = NaiveTracer::new(Arc::new(field), surface);
        let mut odd = Vec::new();
        for j in 0..36u32 {
            for i in 0..48u32 {
                let count = counts[(i + 48 * j) as usize];
                if count % 2 == 1 && !tracer.intersect(&camera.ray(i, j)).is_some_and(|h| h.t == 0.0) {
                    odd.push((i, j, count));
                }
            }
        }
        prop_assert!(odd.is_empty(), "pixels covered an odd number of times: {:?}", odd);
    }
}

static TOTALS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
static WRONG: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

#[test]
fn a_region_outside_the_grid_is_refused() {
    let field = HeightField::new(3, 3, vec![0.0; 9], GridGeometry::unit()).unwrap();
    assert!(height_field_mesh(&field, Surface::Boxes, SampleRegion::new(0, 0, 4, 3)).is_err());
    let empty =
        height_field_mesh(&field, Surface::Triangles, SampleRegion::new(1, 1, 2, 3)).unwrap();
    assert!(empty.is_empty());
}
