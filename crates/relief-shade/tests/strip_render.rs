//! The one-pass strip render gives the two-pass render's picture byte for byte.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use relief_core::{Camera, GridGeometry, HeightField, Surface};
use relief_shade::{
    render_gbuffer, render_to_srgb8, shade_to_srgb8, sun_shadow_sweep, Albedo, KeptHits,
    RgbTexture, ShadingParams,
};
use relief_trace::{build_tracer, TracerKind};

fn terrain() -> Arc<HeightField> {
    let (w, h) = (41, 29);
    let samples = (0..w * h)
        .map(|k| {
            let (x, y) = ((k % w) as f32, (k / w) as f32);
            2.5 * (x * 0.37).sin() * (y * 0.21).cos()
                + 0.08 * y
                + ((x * 5.0 + y * 11.0) % 7.0) * 0.15
        })
        .collect();
    let geometry = GridGeometry { dx: 25.0, dy: 25.0, z_scale: 50.0, ..GridGeometry::unit() };
    Arc::new(HeightField::new(w, h, samples, geometry).unwrap())
}

#[test]
fn the_strip_render_is_the_two_pass_render() {
    let checker: Vec<u8> = (0..4 * 4)
        .flat_map(|k| if (k % 4 + k / 4) % 2 == 0 { [210, 170, 110] } else { [30, 80, 50] })
        .collect();
    let texture = Albedo::Texture(RgbTexture::from_srgb8(4, 4, &checker).unwrap());
    let field = terrain();
    // Heights that are and are not a multiple of the strip, one under a strip; shadows on
    // and off; the default ramp and a texture.
    let cases = [
        (Surface::Triangles, (75, 47), true, None),
        (Surface::Triangles, (64, 32), false, None),
        (Surface::Boxes, (53, 9), true, Some(texture.clone())),
        (Surface::Boxes, (40, 35), false, Some(texture)),
    ];
    let mut swept = 0;
    for (surface, (w, h), shadows, albedo) in cases {
        let bounds = field.world_bounds(surface);
        let tracer = build_tracer(field.clone(), surface, TracerKind::Mipmap);
        let camera = Camera::frame(&bounds, w, h).unwrap();
        let mut params = ShadingParams::for_terrain(&bounds).unwrap();
        params.sun.elevation_deg = 18.0;
        params.shadows = shadows;
        if let Some(albedo) = albedo {
            params.albedo = albedo;
        }
        let (gbuffer, primary) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
        let (want, shadow) = shade_to_srgb8(&gbuffer, &*tracer, &camera, &params).unwrap();
        let pixels = AtomicU64::new(0);
        let progress = |n: u64| {
            pixels.fetch_add(n, Ordering::Relaxed);
        };
        for (threads, depth, normals) in [(1, true, false), (2, false, true), (2, false, false)] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pixels.store(0, Ordering::Relaxed);
            let keep = KeptHits { depth, normals };
            let got = pool
                .install(|| {
                    render_to_srgb8(&*tracer, &*tracer, &camera, &bounds, &params, keep, &progress)
                })
                .unwrap();
            let case = format!("{surface} {w}x{h} shadows {shadows}, {threads} threads");
            assert!(got.rgb == want, "{case}: the pictures differ");
            assert_eq!(got.stats.primary, primary, "{case}");
            assert_eq!(got.stats.shadow, shadow, "{case}");
            assert_eq!(pixels.load(Ordering::Relaxed), u64::from(w * h), "{case}");
            assert!(got.stats.trace_ms >= 0.0 && got.stats.shade_ms >= 0.0);
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(got.depth.map(|d| bits(&d)), depth.then(|| bits(&gbuffer.distance)));
            assert_eq!(
                got.normals.map(|n| bits(n.as_flattened())),
                normals.then(|| bits(gbuffer.normal.as_flattened()))
            );
        }
        // The sun's shadow sweep decides the shadow rays as the tracer does.
        if let Some(sweep) = sun_shadow_sweep(&*tracer, &field, surface, &params, (w * h) as usize)
        {
            let keep = KeptHits::default();
            let got = render_to_srgb8(&*tracer, &sweep, &camera, &bounds, &params, keep, &|_| {})
                .unwrap();
            assert!(got.rgb == want, "{surface} {w}x{h} with the sweep: the pictures differ");
            assert_eq!((got.stats.shadow.rays, got.stats.shadow.hits), (shadow.rays, shadow.hits));
            swept += 1;
        }
        assert!(primary.hits > 0 && primary.hits < primary.rays, "a real scene");
        assert_eq!(shadow.hits > 0, shadows, "some pixels are in shadow");
    }
    assert_eq!(swept, 1, "the sweep is built for the triangles with shadows only");
}

#[test]
fn bad_parameters_are_refused() {
    let field = terrain();
    let bounds = field.world_bounds(Surface::Triangles);
    let tracer = build_tracer(field, Surface::Triangles, TracerKind::Mipmap);
    let camera = Camera::frame(&bounds, 8, 8).unwrap();
    let mut params = ShadingParams::for_terrain(&bounds).unwrap();
    params.exposure = -1.0;
    let keep = KeptHits::default();
    assert!(render_to_srgb8(&*tracer, &*tracer, &camera, &bounds, &params, keep, &|_| {}).is_err());
}
