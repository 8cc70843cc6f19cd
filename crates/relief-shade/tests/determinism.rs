//! Renders are bit-identical whatever the thread count; progress adds up to the image.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use relief_core::{Camera, GridGeometry, HeightField, Surface};
use relief_shade::{
    render_gbuffer, shade, tonemap_to_srgb8, Albedo, GBuffer, RgbTexture, ShadeError,
    ShadingParams, TraceStats,
};
use relief_trace::{build_tracer, TracerKind};

fn terrain() -> Arc<HeightField> {
    let (w, h) = (33, 27);
    let samples = (0..w * h)
        .map(|k| {
            let (x, y) = ((k % w) as f32, (k / w) as f32);
            3.0 * (x * 0.31).sin() * (y * 0.23).cos() + 0.1 * x + ((x * 7.0 + y * 13.0) % 5.0) * 0.2
        })
        .collect();
    let geometry = GridGeometry { dx: 30.0, dy: 30.0, z_scale: 40.0, ..GridGeometry::unit() };
    Arc::new(HeightField::new(w, h, samples, geometry).unwrap())
}

/// G-buffer, radiance, image bytes and both stats of a full render on `threads` threads.
fn render(
    threads: usize,
    surface: Surface,
    albedo: Option<Albedo>,
) -> (GBuffer, Vec<[f32; 3]>, Vec<u8>, [TraceStats; 2]) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let field = terrain();
        let bounds = field.world_bounds(surface);
        let tracer = build_tracer(field, surface, TracerKind::Mipmap);
        let camera = Camera::frame(&bounds, 71, 45).unwrap();
        let pixels = AtomicU64::new(0);
        let progress = |n: u64| {
            pixels.fetch_add(n, Ordering::Relaxed);
        };
        let (g, primary) = render_gbuffer(&*tracer, &camera, &bounds, &progress).unwrap();
        assert_eq!(pixels.load(Ordering::Relaxed), 71 * 45);
        let mut params = ShadingParams::for_terrain(&bounds).unwrap();
        params.sun.elevation_deg = 20.0;
        if let Some(albedo) = albedo {
            params.albedo = albedo;
        }
        let (radiance, shadows) = shade(&g, &*tracer, &camera, &params).unwrap();
        let bytes = tonemap_to_srgb8(&radiance, params.exposure).unwrap();
        (g, radiance, bytes, [primary, shadows])
    })
}

fn bits(v: &[[f32; 3]]) -> Vec<u32> {
    v.iter().flatten().map(|x| x.to_bits()).collect()
}

#[test]
fn one_and_two_threads_give_identical_renders() {
    let checker: Vec<u8> = (0..8 * 8)
        .flat_map(|k| if (k % 8 + k / 8) % 2 == 0 { [200, 180, 120] } else { [40, 90, 40] })
        .collect();
    let texture = Albedo::Texture(RgbTexture::from_srgb8(8, 8, &checker).unwrap());
    for (surface, albedo) in [(Surface::Triangles, None), (Surface::Boxes, Some(texture))] {
        let (g1, r1, b1, s1) = render(1, surface, albedo.clone());
        let (g2, r2, b2, s2) = render(2, surface, albedo);
        let dist_bits = |g: &GBuffer| g.distance.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(dist_bits(&g1), dist_bits(&g2));
        assert_eq!(
            g1.normals_hw3().iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            g2.normals_hw3().iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(bits(&r1), bits(&r2));
        assert_eq!(b1, b2);
        assert_eq!(s1, s2);
        // A real scene: some sky, some terrain, some shadow.
        assert!(s1[0].hits > 0 && s1[0].hits < s1[0].rays, "{surface}: {:?}", s1[0]);
        assert!(s1[1].hits > 0, "{surface}: some pixels are in shadow");
        assert!(r1.iter().flatten().all(|c| c.is_finite() && *c >= 0.0));
    }
}

#[test]
fn shading_refuses_bad_parameters_and_mismatched_buffers() {
    let field = terrain();
    let bounds = field.world_bounds(Surface::Boxes);
    let tracer = build_tracer(field, Surface::Boxes, TracerKind::Naive);
    let camera = Camera::frame(&bounds, 8, 6).unwrap();
    let (g, _) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
    let ok = ShadingParams::for_terrain(&bounds).unwrap();
    assert!(shade(&g, &*tracer, &camera, &ok).is_ok());
    let bad = [
        ShadingParams { fog_density: -1.0, ..ok.clone() },
        ShadingParams { exposure: f64::NAN, ..ok.clone() },
        ShadingParams { albedo: Albedo::Uniform([0.1, f32::INFINITY, 0.1]), ..ok.clone() },
    ];
    for params in &bad {
        assert!(matches!(shade(&g, &*tracer, &camera, params), Err(ShadeError::Parameter { .. })));
    }
    let other = Camera::frame(&bounds, 6, 8).unwrap();
    assert!(matches!(shade(&g, &*tracer, &other, &ok), Err(ShadeError::Mismatch(_))));
    let mut broken = g.clone();
    broken.normal.truncate(3);
    assert!(matches!(shade(&broken, &*tracer, &camera, &ok), Err(ShadeError::Mismatch(_))));
}
