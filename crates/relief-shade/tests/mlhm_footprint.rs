//! Box faces' shading terms are filtered over the pixel's footprint: a gently stepped
//! plateau (steps of a few centimetres, the staircase of a smooth slope in boxes) seen from
//! straight above with pixel centres exactly on cell edges shows no dark lines and the same
//! picture from both tracers; seen from afar, where cells are smaller than pixels, its
//! pixels are free of stipple (the side faces of sub-pixel steps and the shadow slivers they
//! cast no longer light single pixels differently); and a shift of the camera by half a pixel
//! leaves the plateau's picture as it was.

use relief_core::{Camera, DVec2, DVec3, Mlhm, MlhmColumn, Projection};
use relief_shade::mlhm::{render_mlhm, MlhmImage, MlhmPreset, MlhmShading};
use relief_trace::{MlhmHierarchyTracer, MlhmNaiveTracer, MlhmTracer};
use std::sync::Arc;

/// `n` x `n` cells of `cell` metres, rising by `step` metres a cell towards the north-west
/// (the default sun's side): every cell a step above its south-eastern neighbours.
fn stepped_plateau(n: usize, cell: f64, step: f32) -> Arc<Mlhm> {
    let mut map = Mlhm::new(n, n, 1, cell).unwrap();
    for y in 0..n {
        for x in 0..n {
            let top = 5.0 + step * ((n - x) as f32 + y as f32);
            map.set_cell(x, y, &[MlhmColumn::new(top, 0.0, 0.0, f32::INFINITY)]).unwrap();
        }
    }
    map.set_base(4.0);
    Arc::new(map)
}

fn render(tracer: &dyn MlhmTracer, camera: &Camera) -> MlhmImage {
    render_mlhm(tracer, camera, &MlhmShading::new(MlhmPreset::Mid), &|_| {}).unwrap()
}

fn luminance(rgb: [f32; 3]) -> f64 {
    0.2126 * rgb[0] as f64 + 0.7152 * rgb[1] as f64 + 0.0722 * rgb[2] as f64
}

/// The smallest and largest luminance of the pixels whose hit lies at least `margin` metres
/// inside the map's `size` metres square footprint (the plateau, not its walls).
fn plateau_range(image: &MlhmImage, size: f64, margin: f64) -> (f64, f64, usize) {
    let hits = image.gbuffer.exact_hits.as_ref().unwrap();
    let (mut lo, mut hi, mut n) = (f64::INFINITY, f64::NEG_INFINITY, 0);
    for (hit, rgb) in hits.iter().zip(&image.radiance) {
        let p = hit.position;
        if hit.t.is_finite()
            && p.x > margin
            && p.y > margin
            && p.x < size - margin
            && p.y < size - margin
        {
            let l = luminance(*rgb);
            (lo, hi, n) = (lo.min(l), hi.max(l), n + 1);
        }
    }
    (lo, hi, n)
}

/// The largest relative luminance difference between horizontally or vertically
/// neighbouring plateau pixels (as [`plateau_range`] picks them), and their count: stipple
/// shows as single pixels unlike their neighbours; perspective and light change smoothly.
fn largest_step(image: &MlhmImage, width: usize, size: f64, margin: f64) -> (f64, usize) {
    let hits = image.gbuffer.exact_hits.as_ref().unwrap();
    let on = |k: usize| {
        let p = hits[k].position;
        hits[k].t.is_finite()
            && p.x > margin
            && p.y > margin
            && p.x < size - margin
            && p.y < size - margin
    };
    let (mut largest, mut n) = (0.0f64, 0);
    for k in 0..hits.len() {
        for next in [k + 1, k + width] {
            if next < hits.len() && (next != k + 1 || next % width != 0) && on(k) && on(next) {
                let (a, b) = (luminance(image.radiance[k]), luminance(image.radiance[next]));
                let d = (a - b).abs() / a.min(b);
                largest = largest.max(d);
                n += 1;
            }
        }
    }
    (largest, n)
}

#[test]
fn a_stepped_plateau_from_above_has_no_lines_and_is_the_same_from_both_tracers() {
    let map = stepped_plateau(16, 1.0, 0.02);
    // 0.5 m pixels whose centres fall on every cell edge (x = 8.5 + 0.5 i).
    let centre = DVec3::new(8.25, 8.25, 0.0);
    let projection = Projection::Orthographic { height: 16.0 };
    let camera =
        Camera::new(centre + DVec3::Z * 30.0, centre, DVec3::Y, projection, 32, 32).unwrap();
    let hierarchy = render(&MlhmHierarchyTracer::new(map.clone(), DVec2::ZERO), &camera);
    let naive = render(&MlhmNaiveTracer::new(map.clone(), DVec2::ZERO), &camera);
    assert_eq!(hierarchy.radiance, naive.radiance);
    let (lo, hi, n) = plateau_range(&hierarchy, 16.0, 1.0);
    assert!(n > 500, "{n} plateau pixels");
    // A step's shadow is a sliver of 2 cm / tan 35° = 3 cm of a 50 cm pixel: at most a few
    // percent of the light, not a dark line.
    assert!(hi / lo < 1.05, "plateau luminance from {lo} to {hi}");
}

#[test]
fn a_stepped_plateau_from_afar_has_no_stipple_and_stays_under_a_half_pixel_shift() {
    // 16 m square of 12.5 cm cells with 5 mm steps, seen from the south-west 22 m away:
    // about 2 cells a pixel.
    let map = stepped_plateau(128, 0.125, 0.005);
    let tracer = MlhmHierarchyTracer::new(map.clone(), DVec2::ZERO);
    let target = DVec3::new(8.0, 8.0, 5.6);
    let eye = target + DVec3::new(-14.0, -14.0, 10.0);
    let camera = Camera::look_at(eye, target, DVec3::Z, 30.0, 64, 48).unwrap();
    let image = render(&tracer, &camera);
    // The filter reaches a footprint or two: keep clear of the map's edges, which it sees.
    let (step, n) = largest_step(&image, 64, 16.0, 1.5);
    assert!(n > 1000, "{n} pairs of plateau pixels");
    assert!(step < 0.03, "neighbouring plateau pixels differ by {step}");
    let (lo, hi, _) = plateau_range(&image, 16.0, 1.5);
    // Half a pixel to the right: the picture of the plateau moves, but looks the same.
    let right = camera.right() * camera.pixel_footprint((target - eye).length()) * 0.5;
    let shifted = Camera::look_at(eye + right, target + right, DVec3::Z, 30.0, 64, 48).unwrap();
    let (lo2, hi2, _) = plateau_range(&render(&tracer, &shifted), 16.0, 1.5);
    assert!((lo2 / lo - 1.0).abs() < 0.03 && (hi2 / hi - 1.0).abs() < 0.03, "{lo2} {hi2}");
}
