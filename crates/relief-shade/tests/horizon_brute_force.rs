//! The horizon engine against a brute force written from the definition: the horizon towards
//! an azimuth is the steepest slope from the observer to any point where the vertical
//! half-plane of that azimuth crosses an edge of any triangle of the `triangles` surface (the
//! profile is linear between such points), every triangle tried.

use proptest::prelude::*;
use relief_core::{GridGeometry, HeightField};
use relief_shade::horizon::{Facing, HorizonEngine, HorizonParams};

/// The triangles of the surface (world x, y, z of each corner), holes' cells left out,
/// `sign` turning the terrain upside down on the same split.
fn triangles(field: &HeightField, sign: f64) -> Vec<[[f64; 3]; 3]> {
    let g = field.geometry();
    let (w, h) = (field.width(), field.height());
    let vertex = |c: usize, r: usize| {
        [c as f64 * g.dx, r as f64 * g.dy, sign * field.sample(c, r) as f64 * g.z_scale]
    };
    let mut out = Vec::new();
    for r in 0..h.saturating_sub(1) {
        for c in 0..w.saturating_sub(1) {
            if [(c, r), (c + 1, r), (c, r + 1), (c + 1, r + 1)]
                .iter()
                .any(|&(c, r)| field.is_hole(c, r))
            {
                continue;
            }
            let (p00, p10, p01, p11) =
                (vertex(c, r), vertex(c + 1, r), vertex(c, r + 1), vertex(c + 1, r + 1));
            let main = field.sample(c, r) + field.sample(c + 1, r + 1)
                <= field.sample(c + 1, r) + field.sample(c, r + 1);
            if main {
                out.push([p00, p10, p11]);
                out.push([p00, p11, p01]);
            } else {
                out.push([p00, p10, p01]);
                out.push([p10, p11, p01]);
            }
        }
    }
    out
}

/// The brute-force horizon angle (radians) from sample (`col`, `row`) towards `azimuth_deg`.
fn brute_horizon(
    field: &HeightField,
    tris: &[[[f64; 3]; 3]],
    sign: f64,
    col: usize,
    row: usize,
    azimuth_deg: f64,
    params: &HorizonParams,
) -> f64 {
    let g = field.geometry();
    let p = [col as f64 * g.dx, row as f64 * g.dy];
    let z0 = sign * field.sample(col, row) as f64 * g.z_scale + params.observer_height;
    // Due north, east, south and west exactly (sin 180° is not 0 in floating point).
    let d = match azimuth_deg {
        0.0 => [0.0, 1.0],
        90.0 => [1.0, 0.0],
        180.0 => [0.0, -1.0],
        270.0 => [-1.0, 0.0],
        _ => [azimuth_deg.to_radians().sin(), azimuth_deg.to_radians().cos()],
    };
    let cross = |v: &[f64; 3]| d[0] * (v[1] - p[1]) - d[1] * (v[0] - p[0]);
    let radius = params.radius.unwrap_or(f64::INFINITY);
    // The profile's points: (distance, height above the observer).
    let mut points: Vec<(f64, f64)> = Vec::new();
    let mut consider = |x: [f64; 3]| {
        let t = (x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1];
        if t > 1e-9 && t <= radius * (1.0 + 1e-12) {
            points.push((t, x[2] - z0));
        }
    };
    for tri in tris {
        for k in 0..3 {
            let (v1, v2) = (tri[k], tri[(k + 1) % 3]);
            let (e1, e2) = (cross(&v1), cross(&v2));
            // Within a rounding of the line counts as on it.
            let on = |e: f64| e.abs() < 1e-12;
            if on(e1) {
                consider(v1);
            }
            if on(e2) {
                consider(v2);
            }
            if (e1 < 0.0 && e2 > 0.0) || (e1 > 0.0 && e2 < 0.0) {
                let f = e1 / (e1 - e2);
                consider([0, 1, 2].map(|i| v1[i] + f * (v2[i] - v1[i])));
            }
        }
        if radius.is_finite() {
            // The profile's end at the radius, where it lies inside this triangle.
            let x = [p[0] + radius * d[0], p[1] + radius * d[1]];
            let (a, b, c) = (tri[0], tri[1], tri[2]);
            let det = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1]);
            let l1 = ((b[1] - c[1]) * (x[0] - c[0]) + (c[0] - b[0]) * (x[1] - c[1])) / det;
            let l2 = ((c[1] - a[1]) * (x[0] - c[0]) + (a[0] - c[0]) * (x[1] - c[1])) / det;
            let l3 = 1.0 - l1 - l2;
            if l1 >= -1e-12 && l2 >= -1e-12 && l3 >= -1e-12 {
                consider([x[0], x[1], l1 * a[2] + l2 * b[2] + l3 * c[2]]);
            }
        }
    }
    let drop = params.refraction.map_or(0.0, |k| (1.0 - k) / (2.0 * EARTH_RADIUS));
    let slope = |(t, g): (f64, f64)| g / t - drop * t;
    let mut best = points.iter().copied().map(slope).fold(f64::NEG_INFINITY, f64::max);
    if drop > 0.0 {
        // The earth's drop bends the profile between its points: sample each piece densely
        // (consecutive points along the line bound a piece inside one triangle), from the
        // sample's own point on.
        points.push((0.0, -params.observer_height));
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        for pair in points.windows(2) {
            let ((t1, g1), (t2, g2)) = (pair[0], pair[1]);
            for k in 1..2000 {
                let f = k as f64 / 2000.0;
                best = best.max(slope((t1 + f * (t2 - t1), g1 + f * (g2 - g1))));
            }
        }
    }
    if best == f64::NEG_INFINITY {
        0.0
    } else {
        best.atan()
    }
}

/// The earth's mean radius the engine uses, metres.
const EARTH_RADIUS: f64 = 6_371_008.8;

/// Numbers in [0, 1) from `seed` (xorshift).
fn noise(seed: u64) -> impl FnMut() -> f32 {
    let mut state = seed | 1;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % 10_000) as f32 / 10_000.0
    }
}

/// A random terrain of one of five kinds: smooth hills, flat, pits, spikes, cliffs; some
/// with holes.
fn terrain() -> impl Strategy<Value = HeightField> {
    (4usize..18, 4usize..18, 0u8..5, any::<u64>(), 0.3f64..3.0, 0.3f64..3.0, prop::bool::ANY)
        .prop_map(|(w, h, kind, seed, dx, dy, holes)| {
            let mut next = noise(seed);
            let samples: Vec<f32> = (0..w * h)
                .map(|k| {
                    let (c, r) = ((k % w) as f32, (k / w) as f32);
                    match kind {
                        0 => (c * 0.7).sin() * 2.0 + (r * 0.4).cos() * 3.0 + next(),
                        1 => 5.0,
                        2 => {
                            if next() < 0.2 {
                                -8.0 * next()
                            } else {
                                0.0
                            }
                        }
                        3 => {
                            if next() < 0.1 {
                                20.0 * next()
                            } else {
                                next() * 0.1
                            }
                        }
                        _ => {
                            if c + 0.5 * r > w as f32 * 0.6 {
                                10.0 + next()
                            } else {
                                next()
                            }
                        }
                    }
                })
                .collect();
            let geometry = GridGeometry { dx, dy, z_scale: 1.3, ..GridGeometry::unit() };
            let field = HeightField::new(w, h, samples, geometry).unwrap();
            if holes {
                let mask = (0..w * h).map(|_| next() < 0.1).collect();
                field.with_holes(mask).unwrap()
            } else {
                field
            }
        })
}

fn check(field: &HeightField, params: &HorizonParams, facing: Facing) -> Result<(), TestCaseError> {
    let sign = if facing == Facing::Up { 1.0 } else { -1.0 };
    let tris = triangles(field, sign);
    let engine = HorizonEngine::new(field, None, params, facing).unwrap();
    let angles = engine.band(0..field.height(), false);
    let level = engine.band(0..field.height(), true);
    for (k, (per_direction, level)) in angles.iter().zip(&level).enumerate() {
        let azimuth = params.azimuth_deg(k);
        for row in 0..field.height() {
            for col in 0..field.width() {
                let got = per_direction[col + row * field.width()];
                let got_level = level[col + row * field.width()];
                if field.is_hole(col, row) {
                    prop_assert!(got.is_nan() && got_level.is_nan());
                    continue;
                }
                let want = brute_horizon(field, &tris, sign, col, row, azimuth, params);
                prop_assert!(
                    (got_level as f64 - want.max(0.0)).abs() < 1e-6,
                    "sample ({col}, {row}) towards {azimuth}, above the horizontal: {got_level} against {want}"
                );
                prop_assert!(
                    (got as f64 - want).abs() < 1e-6,
                    "sample ({col}, {row}) towards {azimuth}: {got} against {want}; {}x{} holes at {:?}", field.width(), field.height(), (0..field.width() * field.height()).filter(|&k| field.is_hole(k % field.width(), k / field.width())).collect::<Vec<_>>()
                );
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn horizons_equal_the_brute_force(
        field in terrain(),
        azimuths in 1u32..13,
        radius in prop::option::of(0.5f64..12.0),
        down in prop::bool::ANY,
        observer_height in 0.0f64..0.5,
    ) {
        let params = HorizonParams { azimuths, observer_height, radius, refraction: None };
        let facing = if down { Facing::Down } else { Facing::Up };
        check(&field, &params, facing)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// With the earth's curvature, on cells hundreds of metres wide where it lowers the far
    /// terrain by metres: the slope peaks inside the profile's linear pieces too.
    #[test]
    fn horizons_over_a_curved_earth_equal_the_brute_force(
        field in terrain().prop_filter("no holes", |f| f.holes().is_none()),
        k in 0.0f64..0.5,
        azimuths in 1u32..6,
    ) {
        let wide = field
            .clone()
            .with_geometry(GridGeometry { dx: 700.0, dy: 450.0, z_scale: 3.0, ..*field.geometry() })
            .unwrap();
        let params = HorizonParams { azimuths, refraction: Some(k), ..HorizonParams::default() };
        check(&wide, &params, Facing::Up)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Lines along grid lines and through cells' corners: 8 and 16 directions on square cells.
    #[test]
    fn horizons_along_the_axes_and_diagonals_equal_the_brute_force(
        field in terrain(),
        sixteen in prop::bool::ANY,
    ) {
        let square = field
            .clone()
            .with_geometry(GridGeometry { dx: 2.0, dy: 2.0, ..*field.geometry() })
            .unwrap();
        let params = HorizonParams { azimuths: if sixteen { 16 } else { 8 }, ..HorizonParams::default() };
        check(&square, &params, Facing::Up)?;
    }
}

/// A rough terrain of `w` x `h` samples: hills of several wavelengths, noise, and spikes and
/// pits here and there, so that horizons are set near and far.
fn large_terrain() -> impl Strategy<Value = HeightField> {
    (40usize..150, 40usize..150, any::<u64>(), 0.5f64..2.0, 0.5f64..2.0).prop_map(
        |(w, h, seed, dx, dy)| {
            let mut next = noise(seed);
            let samples = (0..w * h)
                .map(|k| {
                    let (c, r) = ((k % w) as f32, (k / w) as f32);
                    let hills = (c * 0.05).sin() * 20.0 + (r * 0.13 + c * 0.07).cos() * 8.0;
                    let spike = if next() < 0.01 { 30.0 * next() - 10.0 } else { 0.0 };
                    hills + spike + next()
                })
                .collect();
            let geometry = GridGeometry { dx, dy, z_scale: 1.3, ..GridGeometry::unit() };
            HeightField::new(w, h, samples, geometry).unwrap()
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Lines hundreds of cells long, where the engine skips long stretches at once: every
    /// direction of 40 samples against the brute force (and NaN on the voids it is given).
    #[test]
    fn horizons_of_large_terrains_equal_the_brute_force_at_sampled_points(
        field in large_terrain(),
        azimuths in 5u32..40,
        radius in prop::option::of(5.0f64..120.0),
        down in prop::bool::ANY,
        picks in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0), 40),
    ) {
        let params = HorizonParams { azimuths, radius, ..HorizonParams::default() };
        let (facing, sign) = if down { (Facing::Down, -1.0) } else { (Facing::Up, 1.0) };
        let (w, h) = (field.width(), field.height());
        let void: Vec<bool> = (0..w * h).map(|k| k % 97 == 5).collect();
        let tris = triangles(&field, sign);
        let engine = HorizonEngine::new(&field, Some(&void), &params, facing).unwrap();
        let angles = engine.band(0..h, false);
        let level = engine.band(0..h, true);
        for (k, (angles, level)) in angles.iter().zip(&level).enumerate() {
            let azimuth = params.azimuth_deg(k);
            for &(u, v) in &picks {
                let (col, row) = ((u * w as f64) as usize, (v * h as f64) as usize);
                let index = col + row * w;
                if void[index] {
                    prop_assert!(angles[index].is_nan() && level[index].is_nan());
                    continue;
                }
                let want = brute_horizon(&field, &tris, sign, col, row, azimuth, &params);
                let (got, got_level) = (angles[index] as f64, level[index] as f64);
                prop_assert!(
                    (got - want).abs() < 1e-6 && (got_level - want.max(0.0)).abs() < 1e-6,
                    "{w}x{h}, sample ({col}, {row}) towards {azimuth}: {got} and {got_level}, not {want}"
                );
            }
        }
    }
}

/// A spike 19.7 high a metre from a sample, the line cut at a radius inside its cell: in
/// f32 alone the end's height was 1.3e-6 rad off (found by CI).
#[test]
fn a_spike_at_a_radius_s_end_is_exact() {
    let samples = vec![
        0.06209,
        0.04928,
        0.01957,
        0.083459996,
        0.00831,
        0.04851,
        0.095630005,
        0.01248,
        0.07534,
        0.061720002,
        0.31800002,
        0.083950005,
        0.070599996,
        0.01699,
        0.05251,
        19.748,
        0.062300004,
        0.06067,
        0.07578,
        0.048910003,
    ];
    let geometry = GridGeometry {
        dx: 0.4086539081608555,
        dy: 2.7978915609475585,
        z_scale: 1.3,
        ..GridGeometry::unit()
    };
    let field = HeightField::new(5, 4, samples, geometry).unwrap();
    let params = HorizonParams {
        azimuths: 3,
        radius: Some(1.0352698865378436),
        observer_height: 0.0,
        refraction: None,
    };
    check(&field, &params, Facing::Up).unwrap();
}
