//! The `f32` shading kernel: the same bytes at every lane width, and within one 8-bit step
//! per channel of the `f64` pass over random terrains, cameras, suns and materials.

use std::sync::Arc;

use relief_core::{Camera, DVec3, GridGeometry, HeightField, Projection, Surface};
use relief_shade::{
    render_gbuffer, render_to_srgb8, shade, shade_to_srgb8, tonemap_to_srgb8, Albedo, ColourMap,
    GgxSpecular, HeightColourMap, HypsometricRamp, KeptHits, LaneWidth, RgbTexture, ShadingKernel,
    ShadingParams, Sun,
};
use relief_trace::{build_tracer, TracerKind};

/// A small deterministic generator (64-bit LCG, high bits out).
struct Random(u64);

impl Random {
    /// A number in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        self.0 =
            self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A number in `[lo, hi)`.
    fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// True with probability `p`.
    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
}

/// A random terrain of a few octaves of waves, with a cliff and a flat plateau.
fn random_terrain(random: &mut Random) -> Arc<HeightField> {
    let (w, h) = (33 + (random.unit() * 24.0) as usize, 29 + (random.unit() * 24.0) as usize);
    let waves: Vec<[f64; 4]> = (0..4)
        .map(|_| {
            [
                random.between(0.05, 0.6),
                random.between(0.05, 0.6),
                random.between(0.0, 6.0),
                random.between(0.2, 3.0),
            ]
        })
        .collect();
    let cliff = random.between(0.2, 0.8) * w as f64;
    let samples = (0..w * h)
        .map(|k| {
            let (x, y) = ((k % w) as f64, (k / w) as f64);
            let mut z: f64 =
                waves.iter().map(|[fx, fy, p, a]| a * (fx * x + fy * y + p).sin()).sum();
            if x > cliff {
                z += 4.0;
            }
            if (x - 0.3 * w as f64).abs() < 3.0 && (y - 0.6 * h as f64).abs() < 3.0 {
                z = 6.0;
            }
            z as f32
        })
        .collect();
    let geometry = GridGeometry {
        dx: random.between(5.0, 40.0),
        dy: random.between(5.0, 40.0),
        z_scale: random.between(10.0, 80.0),
        ..GridGeometry::unit()
    };
    Arc::new(HeightField::new(w, h, samples, geometry).unwrap())
}

/// Random shading parameters the kernel covers, for a terrain of `bounds`.
fn random_params(random: &mut Random, bounds: &relief_core::Aabb) -> ShadingParams {
    let mut params = ShadingParams::for_terrain(bounds).unwrap();
    params.sun = Sun {
        azimuth_deg: random.between(0.0, 360.0),
        elevation_deg: random.between(-10.0, 90.0),
        irradiance: random.between(0.5, 6.0),
    };
    params.shadows = random.chance(0.6);
    params.specular = random
        .chance(0.8)
        .then(|| GgxSpecular { roughness: random.between(0.2, 1.0), f0: random.between(0.0, 0.3) });
    params.fog_density *= random.between(0.0, 20.0);
    params.exposure = random.between(0.3, 3.0);
    if random.chance(0.2) {
        let c = [0.0; 3].map(|_: f32| random.between(0.0, 1.0) as f32);
        params.albedo = Albedo::Uniform(c);
    } else if random.chance(0.3) {
        let ramp = HypsometricRamp {
            steep_rock: false,
            ..HypsometricRamp::new(bounds.min.z, bounds.max.z).unwrap()
        };
        params.albedo = Albedo::Hypsometric(ramp);
    } else if random.chance(0.4) {
        // A named map, bathymetry among them, its sea level anywhere in the heights.
        let map = ColourMap::ALL[random.between(0.0, ColourMap::ALL.len() as f64) as usize];
        let (lo, hi) = (bounds.min.z, bounds.max.z);
        let sea_level = random.between(lo, hi);
        params.albedo = Albedo::Mapped(HeightColourMap::new(map, lo, hi, sea_level).unwrap());
    }
    params
}

/// A random camera around `bounds`: from outside or inside, looking anywhere near the
/// terrain, rolled; a pinhole with any field of view, or one time in four orthographic.
fn random_camera(random: &mut Random, bounds: &relief_core::Aabb, w: u32, h: u32) -> Camera {
    let (min, size) = (bounds.min, bounds.max - bounds.min);
    let point = |random: &mut Random, lo: f64, hi: f64| {
        min + DVec3::new(random.between(lo, hi), random.between(lo, hi), random.between(lo, hi))
            * size
    };
    let eye = point(random, -0.5, 1.5) + DVec3::Z * size.z * random.between(0.0, 3.0);
    let target = point(random, 0.0, 1.0);
    let up = DVec3::new(random.between(-0.5, 0.5), random.between(-0.5, 0.5), 1.0);
    let projection = if random.chance(0.25) {
        Projection::Orthographic { height: bounds.diagonal() * random.between(0.05, 1.0) }
    } else {
        Projection::Perspective { fov_deg: random.between(15.0, 100.0) }
    };
    Camera::new(eye, target, up, projection, w, h).unwrap()
}

#[test]
fn every_lane_width_gives_the_portable_bytes() {
    let mut random = Random(7);
    let field = random_terrain(&mut random);
    let bounds = field.world_bounds(Surface::Triangles);
    let mut checked = 0;
    for case in 0..40 {
        let (w, h) = (61, 23);
        let camera = random_camera(&mut random, &bounds, w, h);
        let params = random_params(&mut random, &bounds);
        let kernel = ShadingKernel::new(&camera, &params).expect("the kernel covers the case");
        let portable = kernel.clone().with_width(LaneWidth::Portable).unwrap();
        // Random G-buffer rows: misses, hits near and far, normals of any length and way.
        let n = w as usize;
        for row in [0, 11, 22] {
            let distance: Vec<f32> = (0..n)
                .map(|_| {
                    if random.chance(0.2) {
                        f32::INFINITY
                    } else {
                        random.between(0.0, 3.0 * bounds.diagonal()) as f32
                    }
                })
                .collect();
            let normal: Vec<[f32; 3]> = (0..n)
                .map(|_| {
                    if random.chance(0.05) {
                        [0.0; 3]
                    } else {
                        [0.0; 3].map(|_: f32| random.between(-1.0, 1.0) as f32)
                    }
                })
                .collect();
            let visibility: Vec<f32> =
                (0..n).map(|_| if random.chance(0.7) { 1.0 } else { 0.0 }).collect();
            let mut want = vec![[0u8; 3]; n];
            portable.shade_row(row, 0, &distance, &normal, &visibility, &mut want);
            for width in [LaneWidth::Avx2, LaneWidth::Avx512] {
                let Ok(kernel) = kernel.clone().with_width(width) else {
                    if case == 0 && row == 0 {
                        println!("skipped {}: this processor does not run it", width.name());
                    }
                    continue;
                };
                // Runs starting at every column, so that every lane of a width sees pixels.
                for first in [0, 1, 5, 17] {
                    let mut got = vec![[0u8; 3]; n - first];
                    kernel.shade_row(
                        row,
                        first,
                        &distance[first..],
                        &normal[first..],
                        &visibility[first..],
                        &mut got,
                    );
                    let mut alone = vec![[0u8; 3]; n - first];
                    portable.shade_row(
                        row,
                        first,
                        &distance[first..],
                        &normal[first..],
                        &visibility[first..],
                        &mut alone,
                    );
                    assert!(
                        got == alone,
                        "case {case}, row {row} from {first}: {} differs",
                        width.name()
                    );
                    checked += 1;
                }
                let mut got = vec![[0u8; 3]; n];
                kernel.shade_row(row, 0, &distance, &normal, &visibility, &mut got);
                assert!(got == want, "case {case}, row {row}: {} differs", width.name());
            }
            assert!(want.iter().any(|p| *p != want[0]), "a picture, not one colour");
        }
    }
    println!("{checked} runs compared with the portable path");
}

#[test]
fn the_f32_picture_is_within_one_step_of_the_f64_one() {
    let mut random = Random(2026);
    let (mut channels, mut moved, mut hits, mut coloured) = (0u64, 0u64, 0u64, 0);
    for case in 0..48 {
        let field = random_terrain(&mut random);
        let surface = if random.chance(0.5) { Surface::Triangles } else { Surface::Boxes };
        let bounds = field.world_bounds(surface);
        let tracer = build_tracer(field.clone(), surface, TracerKind::Mipmap);
        let (w, h) = (48 + (random.unit() * 40.0) as u32, 24 + (random.unit() * 30.0) as u32);
        let camera = if random.chance(0.3) {
            Camera::frame(&bounds, w, h).unwrap()
        } else {
            random_camera(&mut random, &bounds, w, h)
        };
        let mut params = random_params(&mut random, &bounds);
        assert!(
            ShadingKernel::new(&camera, &params).is_some(),
            "case {case}: the kernel covers it"
        );
        let (mut gbuffer, primary) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
        // One case in four, each pixel's own colour (as the stacks meshes store theirs).
        let per_pixel = random.chance(0.25);
        if per_pixel {
            params.albedo = Albedo::GBufferColour { fallback: [0.3; 3] };
            for m in &mut gbuffer.material {
                *m = [0.0; 4].map(|_: f32| random.between(0.0, 1.0) as f32);
            }
        }
        let precise = ShadingParams { precise: true, ..params.clone() };
        let (fast, fast_shadow) = shade_to_srgb8(&gbuffer, &*tracer, &camera, &params).unwrap();
        let (slow, slow_shadow) = shade_to_srgb8(&gbuffer, &*tracer, &camera, &precise).unwrap();
        assert_eq!(fast_shadow, slow_shadow, "case {case}: the same shadow rays");
        for (k, (a, b)) in fast.iter().zip(&slow).enumerate() {
            for ch in 0..3 {
                let step = a[ch].abs_diff(b[ch]);
                assert!(step <= 1, "case {case}, pixel {k}: {a:?} against {b:?} ({params:?})");
                moved += u64::from(step);
            }
        }
        channels += 3 * fast.len() as u64;
        hits += primary.hits;
        if per_pixel {
            coloured += 1;
            continue;
        }
        // The one-pass render takes the same kernel.
        let keep = KeptHits::default();
        let strip =
            render_to_srgb8(&*tracer, &*tracer, &camera, &bounds, &params, keep, &|_| {}).unwrap();
        assert!(strip.rgb == fast, "case {case}: the strip render is the two-pass one");
    }
    assert!(hits > 0 && coloured > 0, "{coloured} cases of per-pixel colours");
    println!("{moved} of {channels} channels moved by one step ({coloured} cases coloured)");
}

#[test]
fn the_kernel_leaves_what_it_does_not_cover_to_the_f64_pass() {
    let field = random_terrain(&mut Random(3));
    let bounds = field.world_bounds(Surface::Triangles);
    let camera = Camera::frame(&bounds, 32, 24).unwrap();
    let params = ShadingParams::for_terrain(&bounds).unwrap();
    assert!(ShadingKernel::new(&camera, &params).is_some());
    assert!(ShadingKernel::new(&camera, &ShadingParams::default()).is_some());
    let no_gloss = ShadingParams { specular: None, ..params.clone() };
    assert!(ShadingKernel::new(&camera, &no_gloss).is_some());
    let precise = ShadingParams { precise: true, ..params.clone() };
    assert!(ShadingKernel::new(&camera, &precise).is_none());
    let mirror = ShadingParams {
        specular: Some(GgxSpecular { roughness: 0.1, f0: 0.04 }),
        ..params.clone()
    };
    assert!(ShadingKernel::new(&camera, &mirror).is_none());
    let texture = RgbTexture::from_srgb8(1, 1, &[100, 120, 140]).unwrap();
    let textured = ShadingParams { albedo: Albedo::Texture(texture), ..params.clone() };
    assert!(ShadingKernel::new(&camera, &textured).is_none());
    let colours =
        ShadingParams { albedo: Albedo::GBufferColour { fallback: [0.5; 3] }, ..params.clone() };
    assert!(ShadingKernel::new(&camera, &colours).is_some());
    let eye = camera.eye();
    let orthographic = Camera::new(
        eye,
        camera.target(),
        DVec3::Z,
        Projection::Orthographic { height: 100.0 },
        32,
        24,
    )
    .unwrap();
    assert!(ShadingKernel::new(&orthographic, &params).is_some());
    assert_eq!(LaneWidth::Portable.lanes(), 8);
    assert!(LaneWidth::Portable.is_available() && LaneWidth::detect().is_available());
}

#[test]
fn precise_shading_is_the_f64_pass_byte_for_byte() {
    let mut random = Random(11);
    let field = random_terrain(&mut random);
    let bounds = field.world_bounds(Surface::Triangles);
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    for _ in 0..6 {
        let camera = random_camera(&mut random, &bounds, 57, 31);
        let params = ShadingParams { precise: true, ..random_params(&mut random, &bounds) };
        let (gbuffer, _) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
        let (radiance, _) = shade(&gbuffer, &*tracer, &camera, &params).unwrap();
        let want = tonemap_to_srgb8(&radiance, params.exposure).unwrap();
        let (got, _) = shade_to_srgb8(&gbuffer, &*tracer, &camera, &params).unwrap();
        assert!(got.concat() == want, "precise is the f64 pass, tone-mapped");
    }
}
