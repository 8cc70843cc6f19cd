//! The one-pass strip render gives the two-pass render's picture byte for byte.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use relief_core::{Camera, GridGeometry, HeightField, Surface};
use relief_shade::{
    render_gbuffer, render_marked_to_srgb8, render_to_srgb8, shade_to_srgb8, sun_shadow_sweep,
    Albedo, KeptHits, PixelMask, RgbTexture, ShadingParams, StripTracers,
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

#[test]
fn a_marked_render_draws_the_marked_pixels_as_the_whole_render_does() {
    let field = terrain();
    for (surface, (w, h), shadows) in
        [(Surface::Triangles, (75, 47), true), (Surface::Boxes, (53, 40), false)]
    {
        let bounds = field.world_bounds(surface);
        let tracer = build_tracer(field.clone(), surface, TracerKind::Mipmap);
        let camera = Camera::frame(&bounds, w, h).unwrap();
        let mut params = ShadingParams::for_terrain(&bounds).unwrap();
        params.sun.elevation_deg = 18.0;
        params.shadows = shadows;
        let keep = KeptHits { depth: true, normals: true };
        let whole =
            render_to_srgb8(&*tracer, &*tracer, &camera, &bounds, &params, keep, &|_| {}).unwrap();
        // Scattered pixels, a run across a tile's edge, and a whole corner tile.
        let marked = |i: usize, j: usize| {
            (i * 7 + j * 13).is_multiple_of(23)
                || (j == 20 && (10..40).contains(&i))
                || (i < 16 && j < 16)
        };
        let mask = PixelMask::from_fn(w as usize, h as usize, marked);
        let tracers = StripTracers { primary: &*tracer, shadow: &*tracer };
        let got = render_marked_to_srgb8(tracers, &camera, &bounds, &params, keep, &mask, &|_| {})
            .unwrap();
        let (depth, normals) = (got.depth.unwrap(), got.normals.unwrap());
        for k in 0..(w * h) as usize {
            let (i, j) = (k % w as usize, k / w as usize);
            if marked(i, j) {
                let case = format!("{surface} pixel ({i}, {j})");
                assert_eq!(got.rgb[k], whole.rgb[k], "{case}");
                assert_eq!(
                    depth[k].to_bits(),
                    whole.depth.as_ref().unwrap()[k].to_bits(),
                    "{case}"
                );
                assert_eq!(normals[k], whole.normals.as_ref().unwrap()[k], "{case}");
            }
        }
        assert!(
            got.stats.primary.rays < whole.stats.primary.rays / 2,
            "only the marked are traced"
        );
        // A mask of another size is refused.
        let other = PixelMask::from_fn(w as usize + 1, h as usize, marked);
        assert!(render_marked_to_srgb8(tracers, &camera, &bounds, &params, keep, &other, &|_| {})
            .is_err());
    }
}
