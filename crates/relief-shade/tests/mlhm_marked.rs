//! The MLHM renderer's pass of marked pixels (what adaptive anti-aliasing samples again)
//! draws each of them as the whole picture does.

use relief_core::{Camera, DVec2, DVec3};
use relief_shade::mlhm::{render_mlhm, render_mlhm_marked, MlhmPreset, MlhmShading};
use relief_shade::PixelMask;
use relief_trace::MlhmHierarchyTracer;
use std::sync::Arc;

#[test]
fn a_marked_render_gives_the_marked_pixels_the_whole_render_s_radiance() {
    let map = Arc::new(relief_sim::carved_scene(relief_sim::CarvedScene::Combined, 32, 4).unwrap());
    let tracer = MlhmHierarchyTracer::new(map, DVec2::ZERO);
    let eye = DVec3::new(-20.0, -30.0, 60.0);
    let camera =
        Camera::look_at(eye, DVec3::new(128.0, 128.0, 0.0), DVec3::Z, 45.0, 40, 30).unwrap();
    let shading = MlhmShading::new(MlhmPreset::High);
    let whole = render_mlhm(&tracer, &camera, &shading, &|_| {}).unwrap();
    let marked = |i: usize, j: usize| (i * 5 + j * 3).is_multiple_of(11) || (i > 30 && j > 20);
    let mask = PixelMask::from_fn(40, 30, marked);
    let got = render_mlhm_marked(&tracer, &camera, &shading, &mask, None, &|_| {}).unwrap();
    // Again into the G-buffer of that pass: the same image.
    let reused = Some(got.gbuffer.clone());
    let again = render_mlhm_marked(&tracer, &camera, &shading, &mask, reused, &|_| {}).unwrap();
    assert_eq!(again.radiance, got.radiance);
    for k in 0..40 * 30 {
        if marked(k % 40, k / 40) {
            assert_eq!(got.radiance[k], whole.radiance[k], "pixel {k}");
            assert_eq!(got.gbuffer.distance[k], whole.gbuffer.distance[k], "pixel {k}");
        } else {
            assert_eq!(got.radiance[k], [0.0; 3], "pixel {k} is not drawn");
        }
    }
    assert!(got.counts.primary.rays < whole.counts.primary.rays / 2);
    let other = PixelMask::from_fn(30, 40, marked);
    assert!(render_mlhm_marked(&tracer, &camera, &shading, &other, None, &|_| {}).is_err());
}
