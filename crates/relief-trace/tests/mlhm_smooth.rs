//! The smooth implicit-surface tracer: the volume function against brute-force integration,
//! the adaptive march (with and without the padded hierarchy, both back-tracking variants,
//! f32 and f16 bounds) against a dense fixed-step march on random MLHMs and rays in all three
//! modes. A flat map, options, soft shadows and materials are in `mlhm_smooth_surface.rs`.

mod common;

use common::mlhm_reference::{clip, random_mlhm, random_ray, Rng, MLHM_RAY_KINDS};
use proptest::prelude::*;
use relief_core::{DVec2, DVec3, Mlhm, MlhmColumn, Precision, Ray};
use relief_trace::{
    MlhmBacktrack, MlhmField, MlhmImplicit, MlhmMaterial, MlhmMode, MlhmSmoothOptions,
    MlhmSmoothTracer, MlhmTracer,
};
use std::sync::Arc;

/// What fills a point of `map` (grid-local metres), looked up column by column: `None`
/// outside the grid's footprint.
fn material_at(map: &Mlhm, p: DVec3) -> Option<MlhmMaterial> {
    let s = map.cell_size();
    let (fx, fy) = ((p.x / s).floor(), (p.y / s).floor());
    if fx < 0.0 || fy < 0.0 || fx >= map.width() as f64 || fy >= map.height() as f64 {
        return None;
    }
    let (x, y) = (fx as usize, fy as usize);
    let mut floor = f64::NEG_INFINITY;
    for k in 0..map.layer_count(x, y) {
        let c = map.column(x, y, k);
        let bedrock = c.bedrock as f64;
        let solid = (c.bedrock + c.sand) as f64;
        let water = (c.bedrock + c.sand + c.water) as f64;
        if p.z >= floor && p.z < bedrock {
            return Some(MlhmMaterial::Bedrock);
        }
        if p.z >= bedrock && p.z < solid {
            return Some(MlhmMaterial::Sand);
        }
        if p.z >= solid && p.z < water {
            return Some(MlhmMaterial::Water);
        }
        if p.z >= water && p.z < c.ceiling as f64 {
            return Some(MlhmMaterial::Air);
        }
        floor = c.ceiling as f64;
    }
    Some(MlhmMaterial::Air)
}

/// The volumes of solid, solid + water and air in the cube of half-size `radius` around `p`
/// by the midpoint rule on `n`³ sub-cubes.
fn midpoint_volumes(map: &Mlhm, p: DVec3, radius: f64, n: usize) -> [f64; 3] {
    let h = 2.0 * radius / n as f64;
    let mut counts = [0usize; 3];
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let q = p - radius + DVec3::new(i as f64, j as f64, k as f64) * h + 0.5 * h;
                match material_at(map, q) {
                    Some(MlhmMaterial::Bedrock | MlhmMaterial::Sand) => {
                        counts[0] += 1;
                        counts[1] += 1;
                    }
                    Some(MlhmMaterial::Water) => counts[1] += 1,
                    Some(MlhmMaterial::Air) => counts[2] += 1,
                    None => {}
                }
            }
        }
    }
    counts.map(|c| c as f64 * h * h * h)
}

/// A random map whose every height is a multiple of 1/16 m (so that, with cells, cube
/// centres and radii on the same lattice, the midpoint rule on 1/16 m sub-cubes is exact).
fn lattice_mlhm(rng: &mut Rng, width: usize, height: usize, cell_size: f64) -> Mlhm {
    let q = |rng: &mut Rng, lo: f64, hi: f64| (rng.range(lo, hi) * 16.0).round() as f32 / 16.0;
    let mut map = Mlhm::new(width, height, 4, cell_size).unwrap();
    for y in 0..height {
        for x in 0..width {
            let n = 1 + rng.below(4);
            let mut columns = Vec::new();
            let mut floor = q(rng, -1.0, 1.0);
            for k in 0..n {
                let bedrock = floor + q(rng, 0.0, 1.5);
                let sand = if rng.chance(0.6) { q(rng, 0.0, 1.0) } else { 0.0 };
                let water = if rng.chance(0.5) { q(rng, 0.0, 1.0) } else { 0.0 };
                let mut c = MlhmColumn::new(bedrock, sand, water, f32::INFINITY);
                if k + 1 < n {
                    c.ceiling = c.water_top() + q(rng, 0.0, 1.5);
                    floor = c.ceiling;
                }
                columns.push(c);
            }
            map.set_cell(x, y, &columns).unwrap();
        }
    }
    map
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// (a) V(p), for every field, is the volume found by brute-force integration.
    #[test]
    fn volumes_equal_brute_force_integration(
        seed in any::<u64>(),
        width in 1usize..=4,
        height in 1usize..=4,
        half_cells in any::<bool>(),
        radius_sixteenths in 2usize..=12,
    ) {
        let mut rng = Rng::new(seed);
        let s = if half_cells { 0.5 } else { 1.0 };
        let map = lattice_mlhm(&mut rng, width, height, s);
        let radius = radius_sixteenths as f64 / 16.0;
        let implicit = MlhmImplicit::new(radius).unwrap();
        let n = 2 * radius_sixteenths; // sub-cubes of 1/16 m
        for _ in 0..6 {
            // Centres on the 1/16 m lattice, some beyond the grid's edges.
            let lattice = |rng: &mut Rng, lo: f64, hi: f64| (rng.range(lo, hi) * 16.0).round() / 16.0;
            let p = DVec3::new(
                lattice(&mut rng, -0.5, width as f64 * s + 0.5),
                lattice(&mut rng, -0.5, height as f64 * s + 0.5),
                lattice(&mut rng, -1.5, 5.0),
            );
            let [solid, solid_water, air] = midpoint_volumes(&map, p, radius, n);
            let tolerance = 1e-9 * implicit.cube_volume();
            for (field, expected) in [
                (MlhmField::Solid, solid),
                (MlhmField::SolidWater, solid_water),
                (MlhmField::Air, air),
            ] {
                let v = implicit.field_volume(&map, p, field);
                prop_assert!((v - expected).abs() <= tolerance, "{field:?} at {p}: {v} != {expected}");
            }
            let v = implicit.volumes(&map, p);
            prop_assert!((v.solid() - solid).abs() <= tolerance);
            prop_assert!((v.total() - solid_water).abs() <= tolerance);
        }
    }
}

/// The heights between which the field of `mode` changes with height, as the tracer
/// documents them: from 2σ below the lowest bedrock top to σ above the highest solid (water)
/// top, 2σ above the highest water top for solids + air.
fn heights(map: &Mlhm, radius: f64, mode: MlhmMode) -> (f64, f64) {
    let (mut bedrock_min, mut solid_max, mut water_max) =
        (f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for y in 0..map.height() {
        for x in 0..map.width() {
            bedrock_min = bedrock_min.min(map.column(x, y, 0).bedrock as f64);
            for k in 0..map.layer_count(x, y) {
                let c = map.column(x, y, k);
                solid_max = solid_max.max(c.solid_top() as f64);
                water_max = water_max.max(c.water_top() as f64);
            }
        }
    }
    let top = match mode {
        MlhmMode::Solids => solid_max + radius,
        MlhmMode::SolidsWater => water_max + radius,
        MlhmMode::SolidsAir => water_max + 2.0 * radius,
    };
    (bedrock_min - 2.0 * radius, top)
}

/// A dense march of `ray` (unit direction) in steps of `step` metres over its part above the
/// grid's footprint between the [`heights`], with the points the tracer probes beyond them
/// (where the ray enters the footprint beyond them, and where it leaves them through the
/// bottom, or the top for solids + air): the first sample whose mode volume reaches `low`,
/// and the first that exceeds `high`.
#[allow(clippy::too_many_arguments)]
fn dense_march(
    map: &Mlhm,
    origin: DVec2,
    implicit: &MlhmImplicit,
    mode: MlhmMode,
    ray: &Ray,
    step: f64,
    low: f64,
    high: f64,
) -> (Option<f64>, Option<f64>) {
    let s = map.cell_size();
    let corner = DVec2::new(map.width() as f64, map.height() as f64) * s + origin;
    let (bottom, top) = heights(map, implicit.radius(), mode);
    let inf = f64::INFINITY;
    let Some((enter, exit)) = clip(ray, origin.extend(-inf), corner.extend(inf)) else {
        return (None, None);
    };
    let slab = clip(&ray.with_range(enter, exit), origin.extend(bottom), corner.extend(top));
    let probe_above = mode == MlhmMode::SolidsAir;
    let mut samples = Vec::new();
    let z = ray.at(enter).z;
    if (z < bottom || (probe_above && z > top)) && slab.is_none_or(|(t0, _)| enter < t0) {
        samples.push(enter);
    }
    if let Some((t0, t1)) = slab {
        let n = ((t1 - t0) / step).floor() as u64;
        samples.extend((0..=n).map(|i| t0 + i as f64 * step));
        samples.push(t1);
        let leaves = ray.dir.z < 0.0 || (probe_above && ray.dir.z > 0.0);
        if t1 < exit && leaves {
            samples.push(t1);
        }
    }
    let (mut first_low, mut first_high) = (None, None);
    for t in samples {
        let v = implicit.sample(map, ray.at(t) - origin.extend(0.0), mode).volume;
        if first_low.is_none() && v >= low {
            first_low = Some(t);
        }
        if v > high {
            first_high = Some(t);
            break;
        }
    }
    (first_low, first_high)
}

/// The smooth tracers under test: marching without the hierarchy, and through it with either
/// back-tracking, at f32 and f16.
fn smooth_tracers(map: &Arc<Mlhm>, origin: DVec2, radius: f64) -> Vec<MlhmSmoothTracer> {
    let options = |hierarchy, backtrack, precision| MlhmSmoothOptions {
        radius: Some(radius),
        hierarchy,
        backtrack,
        precision,
        ..MlhmSmoothOptions::default()
    };
    [
        options(false, MlhmBacktrack::ExitStack, Precision::F32),
        options(true, MlhmBacktrack::ExitStack, Precision::F32),
        options(true, MlhmBacktrack::MissCounter, Precision::F32),
        options(true, MlhmBacktrack::ExitStack, Precision::F16),
    ]
    .into_iter()
    .map(|o| MlhmSmoothTracer::with_options(map.clone(), origin, o).unwrap())
    .collect()
}

fn variant(tracer: &MlhmSmoothTracer) -> String {
    let o = tracer.options();
    if o.hierarchy {
        format!("hierarchy {} {:?}", o.backtrack, o.precision)
    } else {
        "no hierarchy".into()
    }
}

/// Checks every tracer's hit of `ray` in `mode` against a dense march of steps `σ/64`: it
/// stops no later than the first dense point where V exceeds the target, plus the corrective
/// step (the march never steps over such a point), and no earlier than the first where V
/// comes within one dense step's change of the hit volume; it misses only when V never
/// exceeds the target, and hits only where V reaches the hit volume. Also checks the hit's
/// position, normal, material, cell and column, and, for shadow rays from outside the solids,
/// that the light visibility is 0 exactly where the ray hits.
fn check_against_dense_march(
    map: &Mlhm,
    origin: DVec2,
    tracers: &[MlhmSmoothTracer],
    ray: &Ray,
    mode: MlhmMode,
    what: &str,
) -> Result<(), TestCaseError> {
    let implicit = *tracers[0].implicit();
    let dense = implicit.radius() / 64.0;
    let side = 2.0 * implicit.radius();
    // The most V changes over one dense step along this ray.
    let lipschitz = side * side * ray.dir.abs().element_sum();
    let low = implicit.hit_volume() - lipschitz * dense;
    let high = implicit.target() * (1.0 + 1e-9);
    let correction = implicit.step(implicit.target() - implicit.hit_volume());
    let (first_low, first_high) = dense_march(map, origin, &implicit, mode, ray, dense, low, high);
    let start = ray.origin - origin.extend(0.0);
    let outside = !implicit.is_inside(implicit.field_volume(map, start, MlhmField::Solid));
    for tracer in tracers {
        let hit = tracer.intersect_mode(ray, mode);
        let what = format!("{} {mode} {what} {ray:?}", variant(tracer));
        if mode == MlhmMode::Solids && outside {
            let mut steps = 0;
            let visibility = tracer.light_visibility(ray, &mut steps);
            prop_assert!((0.0..=1.0).contains(&visibility), "{what}");
            prop_assert_eq!(visibility == 0.0, hit.is_some(), "{}", what);
            prop_assert!(steps > 0);
        }
        if let Some(t_high) = first_high {
            let Some(hit) = hit else {
                return Err(TestCaseError::fail(format!(
                    "{what}: missed, V exceeds the target at {t_high}"
                )));
            };
            prop_assert!(
                hit.hit.t <= t_high + correction + 1e-9,
                "{what}: hit at {} past {t_high}",
                hit.hit.t
            );
        }
        let Some(hit) = hit else { continue };
        let Some(t_low) = first_low else {
            return Err(TestCaseError::fail(format!(
                "{what}: hit at {} where V stays below the hit volume",
                hit.hit.t
            )));
        };
        prop_assert!(
            hit.hit.t >= t_low - dense - 1e-9,
            "{what}: hit at {} before {t_low}",
            hit.hit.t
        );
        prop_assert!((hit.hit.position - ray.at(hit.hit.t)).length() < 1e-9);
        let n = hit.hit.normal;
        prop_assert!((n.length() - 1.0).abs() < 1e-9, "{what}: normal {n}");
        prop_assert!(n.dot(ray.dir) <= 1e-12, "{what}: normal {n}");
        let expected = match mode {
            MlhmMode::Solids => [MlhmMaterial::Bedrock, MlhmMaterial::Sand].as_slice(),
            MlhmMode::SolidsWater => {
                &[MlhmMaterial::Bedrock, MlhmMaterial::Sand, MlhmMaterial::Water]
            }
            MlhmMode::SolidsAir => &[MlhmMaterial::Bedrock, MlhmMaterial::Sand, MlhmMaterial::Air],
        };
        prop_assert!(expected.contains(&hit.material), "{what}");
        let (cx, cy) = hit.cell;
        prop_assert!(cx < map.width() && cy < map.height());
        prop_assert!(hit.column < map.layer_count(cx, cy));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// (b) The adaptive march never steps over the surface (see
    /// [`check_against_dense_march`]), on random maps of 1 to 4 columns a cell with gaps and
    /// water, for rays of every kind, in all three modes, without the hierarchy and through
    /// it: this also checks that the padded bounds enclose the surface.
    #[test]
    fn marching_never_steps_over_the_surface(
        seed in any::<u64>(),
        width in 1usize..=11,
        height in 1usize..=11,
        half_cells in any::<bool>(),
        radius_index in 0usize..3,
    ) {
        let mut rng = Rng::new(seed);
        let s = if half_cells { 0.5 } else { 1.0 };
        let map = Arc::new(random_mlhm(&mut rng, width, height, 4, s));
        let origin = DVec2::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0));
        let radius = [0.5, 1.0, 1.5][radius_index] * s;
        let tracers = smooth_tracers(&map, origin, radius);
        for kind in MLHM_RAY_KINDS {
            for _ in 0..2 {
                let ray = random_ray(&mut rng, &map, origin, kind);
                for mode in MlhmMode::ALL {
                    check_against_dense_march(&map, origin, &tracers, &ray, mode, &format!("{kind:?}"))?;
                }
            }
        }
    }
}

/// Cells of 40 columns, thin slabs between thin gaps, some holding water: level-1 nodes of
/// more intervals than the tracer marches apart, which it marches over their hull.
#[test]
fn tall_stacks_of_columns_march_like_short_ones() {
    let mut rng = Rng::new(7);
    let mut map = Mlhm::new(6, 5, 40, 1.0).unwrap();
    for y in 0..5 {
        for x in 0..6 {
            let mut columns = Vec::new();
            let mut floor = rng.range(-0.5, 0.5) as f32;
            for k in 0..40 {
                let bedrock = floor + rng.range(0.2, 1.5) as f32;
                let water = if rng.chance(0.3) { rng.range(0.0, 0.5) as f32 } else { 0.0 };
                let mut c = MlhmColumn::new(bedrock, 0.0, water, f32::INFINITY);
                if k < 39 {
                    c.ceiling = c.water_top() + rng.range(0.3, 2.5) as f32;
                    floor = c.ceiling;
                }
                columns.push(c);
            }
            map.set_cell(x, y, &columns).unwrap();
        }
    }
    let map = Arc::new(map);
    let tracers = smooth_tracers(&map, DVec2::ZERO, 0.5);
    assert!(tracers[1].hierarchy().unwrap().layer_cap(1) > 16);
    for kind in MLHM_RAY_KINDS {
        for _ in 0..6 {
            let ray = random_ray(&mut rng, &map, DVec2::ZERO, kind);
            for mode in MlhmMode::ALL {
                check_against_dense_march(
                    &map,
                    DVec2::ZERO,
                    &tracers,
                    &ray,
                    mode,
                    &format!("{kind:?}"),
                )
                .unwrap();
            }
        }
    }
}
