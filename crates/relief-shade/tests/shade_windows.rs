//! A shade map made window by window equals the whole raster's, bit for bit: each window holds
//! its block and the halo the layers need ([`ShadeMapParams::halo_samples`]), and the horizons
//! go on past the window through the whole raster (the far field). Property tests over random
//! terrains (rough, with cliffs and spikes, flat plateaus), block sizes, directions and layers.

use proptest::prelude::*;
use relief_core::{GridGeometry, HeightField, Surface};
use relief_shade::horizon::{FarField, FarSamples, HorizonParams};
use relief_shade::shade_map::{
    shade_map, shade_map_region, ShadeLayer, ShadeMap, ShadeMapParams, ShadeRegion, SunPosition,
};
use relief_trace::{build_tracer, TracerKind};
use std::sync::Arc;

/// A rough terrain with a cliff, a spike and a flat plateau, from `seed`.
fn terrain(width: usize, height: usize, seed: u64) -> Vec<f32> {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut noise = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64 / (1u64 << 31) as f64) as f32
    };
    let (a, b, c) = (noise() * 0.3 + 0.05, noise() * 0.3 + 0.05, noise() * 40.0);
    let mut samples: Vec<f32> = (0..width * height)
        .map(|k| {
            let (x, y) = ((k % width) as f32, (k / width) as f32);
            (x * a).sin() * 8.0 + (y * b + x * 0.02).cos() * 12.0 + (x + y) * 0.05 + c
        })
        .collect();
    for v in samples.iter_mut() {
        *v += noise() * 3.0;
    }
    // A cliff, a spike and a plateau.
    let cliff = (noise() * width as f32) as usize;
    for row in 0..height {
        for col in cliff..width {
            samples[col + row * width] += 25.0;
        }
    }
    let spike = (noise() * (width * height) as f32) as usize;
    samples[spike.min(width * height - 1)] += 80.0;
    let (pc, pr) = ((noise() * width as f32) as usize, (noise() * height as f32) as usize);
    for row in pr..(pr + 9).min(height) {
        for col in pc..(pc + 13).min(width) {
            samples[col + row * width] = 30.0;
        }
    }
    samples
}

/// The map of `samples` made block by block, each block from a window around it.
fn by_windows(
    samples: &[f32],
    width: usize,
    height: usize,
    geometry: GridGeometry,
    params: &ShadeMapParams,
    block: usize,
) -> ShadeMap {
    let span = relief_shade::horizon::block_bounds(samples.iter());
    let halo = params.halo_samples(span, &geometry).expect("a finite reach");
    let far = FarSamples::new(Arc::new(samples.to_vec()), width, height);
    let mut bands: Vec<Vec<f32>> = Vec::new();
    let mut names = Vec::new();
    let mut layers = Vec::new();
    for row0 in (0..height).step_by(block) {
        for col0 in (0..width).step_by(block) {
            let (cols, rows) = (col0..(col0 + block).min(width), row0..(row0 + block).min(height));
            let wc = cols.start.saturating_sub(halo)..(cols.end + halo).min(width);
            let wr = rows.start.saturating_sub(halo)..(rows.end + halo).min(height);
            let window: Vec<f32> = wr
                .clone()
                .flat_map(|r| samples[r * width + wc.start..r * width + wc.end].iter().copied())
                .collect();
            let origin = geometry.origin
                + relief_core::DVec2::new(
                    wc.start as f64 * geometry.dx,
                    wr.start as f64 * geometry.dy,
                );
            let g = GridGeometry { origin, ..geometry };
            let field = Arc::new(HeightField::new(wc.len(), wr.len(), window, g).unwrap());
            let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
            let region = ShadeRegion {
                cols: cols.start - wc.start..cols.end - wc.start,
                rows: rows.start - wr.start..rows.end - wr.start,
                far: Some(FarField { terrain: &far, col0: wc.start, row0: wr.start }),
                raster_span: Some(span),
            };
            let map = shade_map_region(&field, &*tracer, None, params, &region, &|_| {}).unwrap();
            if bands.is_empty() {
                bands = vec![vec![f32::NAN; width * height]; map.bands.len()];
                names = map.bands.iter().map(|b| b.name.clone()).collect();
                layers = map.bands.iter().map(|b| b.layer).collect();
            }
            for (all, band) in bands.iter_mut().zip(&map.bands) {
                for (r, row) in rows.clone().enumerate() {
                    all[row * width + cols.start..row * width + cols.end]
                        .copy_from_slice(&band.values[r * cols.len()..(r + 1) * cols.len()]);
                }
            }
        }
    }
    let bands = bands
        .into_iter()
        .zip(names)
        .zip(layers)
        .map(|((values, name), layer)| relief_shade::shade_map::ShadeBand { layer, name, values })
        .collect();
    ShadeMap { width, height, bands, rays: 0 }
}

fn assert_same_bits(whole: &ShadeMap, windows: &ShadeMap) {
    for (a, b) in whole.bands.iter().zip(&windows.bands) {
        let differ = a
            .values
            .iter()
            .zip(&b.values)
            .enumerate()
            .filter(|(_, (x, y))| x.to_bits() != y.to_bits())
            .map(|(k, (x, y))| (k % whole.width, k / whole.width, *x, *y))
            .take(5)
            .collect::<Vec<_>>();
        assert!(differ.is_empty(), "band {}: (col, row, whole, windows) {differ:?}", a.name);
    }
}

fn whole_map(
    samples: &[f32],
    width: usize,
    height: usize,
    geometry: GridGeometry,
    params: &ShadeMapParams,
) -> ShadeMap {
    let field = Arc::new(HeightField::new(width, height, samples.to_vec(), geometry).unwrap());
    let tracer = build_tracer(field.clone(), Surface::Triangles, TracerKind::Mipmap);
    shade_map(&field, &*tracer, None, params, &|_| {}).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Every layer, made window by window over blocks of any size, equals the whole raster's.
    #[test]
    fn windows_give_the_whole_raster_s_bits(
        seed in any::<u64>(),
        width in 40usize..110,
        height in 40usize..110,
        block in 9usize..40,
        azimuths in 3u32..20,
        dx in prop::sample::select(vec![1.0, 2.5, 10.0]),
        elevation in 20.0f64..70.0,
        radius in prop::option::of(5.0f64..40.0),
    ) {
        let samples = terrain(width, height, seed);
        let geometry = GridGeometry { dx, dy: dx, ..GridGeometry::unit() };
        let params = ShadeMapParams {
            layers: vec![
                ShadeLayer::Horizon,
                ShadeLayer::Sky,
                ShadeLayer::OpennessNeg,
                ShadeLayer::Shadow,
                ShadeLayer::Hillshade,
                ShadeLayer::SkyIllumination,
            ],
            suns: vec![SunPosition { azimuth_deg: 300.0, elevation_deg: elevation }],
            horizon: HorizonParams { azimuths, radius: radius.map(|r| r * dx), ..HorizonParams::default() },
            ..ShadeMapParams::default()
        };
        let whole = whole_map(&samples, width, height, geometry, &params);
        let windows = by_windows(&samples, width, height, geometry, &params, block);
        assert_same_bits(&whole, &windows);
    }
}

/// A long raster whose horizons are set far outside small windows, in every direction.
#[test]
fn far_horizons_are_followed_to_the_raster_s_edge() {
    let (width, height) = (300, 260);
    let samples = terrain(width, height, 7);
    let geometry = GridGeometry { dx: 10.0, dy: 10.0, ..GridGeometry::unit() };
    let params = ShadeMapParams {
        layers: vec![ShadeLayer::Horizon, ShadeLayer::Sky, ShadeLayer::OpennessPos],
        horizon: HorizonParams { azimuths: 32, ..HorizonParams::default() },
        ..ShadeMapParams::default()
    };
    let whole = whole_map(&samples, width, height, geometry, &params);
    let windows = by_windows(&samples, width, height, geometry, &params, 37);
    assert_same_bits(&whole, &windows);
}
