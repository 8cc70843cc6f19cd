//! The padded MLHM hierarchy, for the smooth implicit surface (Nilles & Müller 2025, 3.3 and
//! 4.3): level 1 padded by the smoothing radius and rounded outward, every point a smooth
//! surface can pass through inside an interval of every level, zero padding giving the box
//! hierarchy, and rebuilds keeping the padding.

mod common;

use common::hierarchy_checks::{check_bounds, check_f16_is_f32_rounded_outward};
use common::mlhm_reference::{random_mlhm, Rng};
use proptest::prelude::*;
use relief_core::{DVec2, DVec3, Mlhm, MlhmColumn, Precision};
use relief_trace::{MlhmHierarchy, MlhmMode, MlhmNodeLayer};

/// The smallest f32 at or above `exact` (checked, not computed by the library's rounding).
fn f32_at_or_above(exact: f64) -> f32 {
    if exact.is_infinite() {
        return exact as f32;
    }
    let mut v = exact as f32;
    while (v as f64) < exact {
        v = v.next_up();
    }
    while (v.next_down() as f64) >= exact {
        v = v.next_down();
    }
    v
}

/// The largest f32 at or below `exact`.
fn f32_at_or_below(exact: f64) -> f32 {
    -f32_at_or_above(-exact)
}

/// Checks level 1 of `h`, padded by `radius`, against the definition: layer `k` of node
/// `(nx, ny)` is the maxima and minima of layer `k` (folded at the cap) of every cell within
/// `ceil(radius / cell size)` cells of its 2 x 2, each padded by `radius` and rounded outward
/// to the nearest f32 on its side; the sky likewise; and the tops are raised by `radius`.
fn check_padded_level_1(map: &Mlhm, h: &MlhmHierarchy, radius: f64) -> Result<(), String> {
    let ring = (radius / map.cell_size()).ceil() as usize;
    let cap = h.layer_cap(1);
    let (nodes_x, nodes_y) = h.nodes(1);
    let (mut solid_top, mut water_top) = (f32::NEG_INFINITY, f32::NEG_INFINITY);
    for ny in 0..nodes_y {
        for nx in 0..nodes_x {
            let mut merged = vec![MlhmNodeLayer::EMPTY; cap];
            let (mut used, mut sky) = (0, f32::INFINITY);
            for y in (2 * ny).saturating_sub(ring)..(2 * ny + 2 + ring).min(map.height()) {
                for x in (2 * nx).saturating_sub(ring)..(2 * nx + 2 + ring).min(map.width()) {
                    let columns: Vec<MlhmColumn> = map.cell_columns(x, y).collect();
                    for (j, c) in columns.iter().enumerate() {
                        let k = j.min(cap - 1);
                        merged[k] = merged[k].merge(MlhmNodeLayer {
                            water_max: c.water_top(),
                            ceiling_min: c.ceiling,
                            solid_max: c.solid_top(),
                            air_min: c.water_top(),
                        });
                        solid_top = solid_top.max(c.solid_top());
                        water_top = water_top.max(c.water_top());
                    }
                    used = used.max(columns.len().min(cap));
                    sky = sky.min(columns.last().unwrap().water_top());
                }
            }
            if h.layer_count(1, nx, ny) != used {
                return Err(format!("layer count of node ({nx}, {ny})"));
            }
            for (k, m) in merged.iter().take(used).enumerate() {
                let expected = MlhmNodeLayer {
                    water_max: f32_at_or_above(m.water_max as f64 + radius),
                    ceiling_min: f32_at_or_below(m.ceiling_min as f64 - radius),
                    solid_max: f32_at_or_above(m.solid_max as f64 + radius),
                    air_min: f32_at_or_below(m.air_min as f64 - radius),
                };
                let got = h.node_layer(1, nx, ny, k);
                if got != expected {
                    return Err(format!("node ({nx}, {ny}) layer {k}: {got:?}, not {expected:?}"));
                }
            }
            let expected = f32_at_or_below(sky as f64 - radius);
            if h.sky_min(1, nx, ny) != expected {
                return Err(format!("sky of node ({nx}, {ny}): {}", h.sky_min(1, nx, ny)));
            }
        }
    }
    let tops = [
        (MlhmMode::Solids, f32_at_or_above(solid_top as f64 + radius)),
        (MlhmMode::SolidsWater, f32_at_or_above(water_top as f64 + radius)),
    ];
    for (mode, expected) in tops {
        if h.top(mode) != expected as f64 {
            return Err(format!("{mode} top {}, not {expected}", h.top(mode)));
        }
    }
    Ok(())
}

/// The terrain volumes of the cube of half-size `radius` centred at `p` (grid-local metres)
/// that decide whether `p` can be on a smooth surface in each mode: solids, solids + water,
/// and the air in it (the cube's volume over the grid's footprint less solids and water).
fn cube_volumes(map: &Mlhm, p: DVec3, radius: f64) -> (f64, f64, f64) {
    let (min, max) = (p - DVec3::splat(radius), p + DVec3::splat(radius));
    let v = map.material_volumes(min, max);
    let size = DVec2::new(map.width() as f64, map.height() as f64) * map.cell_size();
    let footprint = (max.x.min(size.x) - min.x.max(0.0)).max(0.0)
        * (max.y.min(size.y) - min.y.max(0.0)).max(0.0)
        * (max.z - min.z);
    (v.solid(), v.total(), footprint - v.total())
}

/// Whether `p` (inside the grid's footprint) lies within an interval of the node containing
/// it at every level of `h`, in `mode`; the first level where it does not, otherwise.
fn contained_at_every_level(
    map: &Mlhm,
    h: &MlhmHierarchy,
    p: DVec3,
    mode: MlhmMode,
) -> Result<(), usize> {
    let (x, y) = ((p.x / map.cell_size()) as usize, (p.y / map.cell_size()) as usize);
    let (x, y) = (x.min(map.width() - 1), y.min(map.height() - 1));
    for level in 1..=h.level_count() {
        let inside = h.for_each_interval(level, x >> level, y >> level, mode, |lo, hi| {
            lo <= p.z && p.z <= hi
        });
        if !inside {
            return Err(level);
        }
    }
    Ok(())
}

/// Sample points for the smooth surface's bounds, grid-local, all inside the footprint:
/// random ones over the scene's height range widened by `radius`, and ones just inside the
/// `radius`-shell of a random solid, water or air box (a point of the box pushed, on each axis
/// at random, out past a face by `radius` less a sliver, or kept in the box's range).
fn smooth_sample_points(rng: &mut Rng, map: &Mlhm, radius: f64, count: usize) -> Vec<DVec3> {
    let s = map.cell_size();
    let size = DVec2::new(map.width() as f64, map.height() as f64) * s;
    let (mut z_lo, mut z_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for c in map.raw_columns() {
        z_lo = z_lo.min(c.bedrock as f64);
        z_hi = z_hi.max(c.water_top() as f64);
    }
    let mut points = Vec::with_capacity(count);
    while points.len() < count {
        let p = if rng.chance(0.3) {
            DVec3::new(
                rng.range(0.0, size.x),
                rng.range(0.0, size.y),
                rng.range(z_lo - radius - 1.0, z_hi + radius + 1.0),
            )
        } else {
            let (x, y) = (rng.below(map.width()), rng.below(map.height()));
            let columns: Vec<MlhmColumn> = map.cell_columns(x, y).collect();
            let k = rng.below(columns.len());
            let c = columns[k];
            let floor = if k == 0 { z_lo - 2.0 } else { columns[k - 1].ceiling as f64 };
            let ceiling = if c.ceiling.is_finite() { c.ceiling as f64 } else { z_hi + 2.0 };
            let (solid, water) = (c.solid_top() as f64, c.water_top() as f64);
            let (lo, hi) = match rng.below(3) {
                0 => (floor, solid),
                1 => (solid, water),
                _ => (water, ceiling),
            };
            if hi <= lo {
                continue;
            }
            let ranges =
                [(x as f64 * s, (x + 1) as f64 * s), (y as f64 * s, (y + 1) as f64 * s), (lo, hi)];
            let sliver = radius * [1e-6, 1e-3, 0.1, 0.5][rng.below(4)];
            let coordinates = ranges.map(|(a, b)| match rng.below(3) {
                0 => rng.range(a, b),
                1 => a - radius + sliver,
                _ => b + radius - sliver,
            });
            DVec3::from_array(coordinates)
        };
        if (0.0..size.x).contains(&p.x) && (0.0..size.y).contains(&p.y) {
            points.push(p);
        }
    }
    points
}

/// Checks that every sample point whose cube of half-size `radius` holds terrain lies, in
/// each mode, inside an interval of every level's node above it:
///
/// - solids: where the solid volume is positive (the surface `f >= 0` needs half the cube);
/// - solids + water: where the solid + water volume is positive;
/// - solids + air (rays inside water): where the solid volume is positive, the solid the ray
///   may hit, or where the cube holds some air (solid + water volume below the cube's volume
///   over the grid's footprint), where the solid + water volume may drop below half the cube
///   and the ray leave the water. The void beyond the grid's edges is not air: a cube reaching
///   out of the grid deep under water is not bounded (the tracer leaves the grid there).
///
/// Volumes below `1e-9` of the cube's are taken as rounding noise of the volume sums.
fn check_smooth_points(
    map: &Mlhm,
    hierarchies: &[&MlhmHierarchy],
    radius: f64,
    points: &[DVec3],
) -> Result<(), String> {
    let noise = 1e-9 * (2.0 * radius).powi(3);
    for &p in points {
        let (solid, total, air) = cube_volumes(map, p, radius);
        let needed = [
            (MlhmMode::Solids, solid > noise),
            (MlhmMode::SolidsWater, total > noise),
            (MlhmMode::SolidsAir, solid > noise || air > noise),
        ];
        for (mode, needed) in needed {
            if !needed {
                continue;
            }
            for h in hierarchies {
                if let Err(level) = contained_at_every_level(map, h, p, mode) {
                    return Err(format!(
                        "{mode} {:?}: {p} (solid {solid:e}, solid + water {total:e}, air \
                         {air:e}) outside its node of level {level}",
                        h.precision()
                    ));
                }
            }
        }
    }
    Ok(())
}

/// `map` with up to 4 cells' widths of water added on the top column of half of its cells:
/// water deeper than twice the smoothing radius, whose surface only the padded sky bounds.
fn with_deep_water(rng: &mut Rng, mut map: Mlhm) -> Mlhm {
    let depth = 4.0 * map.cell_size();
    for y in 0..map.height() {
        for x in 0..map.width() {
            if rng.chance(0.5) {
                let mut columns: Vec<MlhmColumn> = map.cell_columns(x, y).collect();
                columns.last_mut().unwrap().water += rng.range(0.0, depth) as f32;
                map.set_cell(x, y, &columns).unwrap();
            }
        }
    }
    map
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// On random maps of 1 to 4 columns a cell (gaps, water), random cell sizes and
    /// smoothing radii of a quarter cell to 3 cells: level 1 is its definition, the
    /// hierarchy stays conservative for the boxes, its f16 bounds are its f32 ones rounded
    /// outward, and every point the smooth surface can reach is inside its nodes' intervals.
    #[test]
    fn padded_bounds_enclose_every_point_near_terrain(
        (width, height) in prop_oneof![(1usize..6, 1usize..6), (1usize..=20, 1usize..=17)],
        max_columns in 1usize..=4,
        cell_size in prop_oneof![Just(1.0), 0.1f64..3.0],
        radius_cells in prop_oneof![Just(1.0), Just(2.0), 0.25f64..=3.0],
        seed in any::<u64>(),
    ) {
        let mut rng = Rng::new(seed);
        let map = random_mlhm(&mut rng, width, height, max_columns, cell_size);
        let map = with_deep_water(&mut rng, map);
        let radius = radius_cells * cell_size;
        let h = MlhmHierarchy::build_padded(&map, radius, Precision::F32);
        let half = MlhmHierarchy::build_padded(&map, radius, Precision::F16);
        prop_assert_eq!((h.padding(), half.padding()), (radius, radius));
        prop_assert_eq!(h.level_count(), MlhmHierarchy::level_count_for(width, height));
        if let Err(e) = check_padded_level_1(&map, &h, radius) {
            prop_assert!(false, "level 1: {}", e);
        }
        for (name, hierarchy) in [("f32", &h), ("f16", &half)] {
            if let Err(e) = check_bounds(&map, hierarchy) {
                prop_assert!(false, "{}: {}", name, e);
            }
        }
        if let Err(e) = check_f16_is_f32_rounded_outward(&h, &half) {
            prop_assert!(false, "{}", e);
        }
        let points = smooth_sample_points(&mut rng, &map, radius, 200);
        if let Err(e) = check_smooth_points(&map, &[&h, &half], radius, &points) {
            prop_assert!(false, "{}", e);
        }
    }
}

#[test]
fn zero_padding_is_the_box_hierarchy_and_rebuilds_keep_the_padding() {
    let mut rng = Rng::new(7);
    let map = random_mlhm(&mut rng, 19, 13, 4, 0.7);
    for precision in [Precision::F32, Precision::F16] {
        let boxes = MlhmHierarchy::build_with_precision(&map, precision);
        assert_eq!(boxes.padding(), 0.0);
        assert_eq!(MlhmHierarchy::build_padded(&map, 0.0, precision), boxes);
        let padded = MlhmHierarchy::build_padded(&map, 1.3, precision);
        assert_eq!(padded.padding(), 1.3);
        assert_ne!(padded, boxes);
        // In place, and from scratch when the grid changes.
        let mut rebuilt = MlhmHierarchy::build_padded(&map, 1.3, precision);
        rebuilt.rebuild(&random_mlhm(&mut rng, 19, 13, 4, 0.7));
        rebuilt.rebuild(&map);
        assert_eq!(rebuilt, padded);
        let mut rebuilt =
            MlhmHierarchy::build_padded(&random_mlhm(&mut rng, 5, 3, 2, 0.7), 1.3, precision);
        rebuilt.rebuild(&map);
        assert_eq!(rebuilt, padded);
        assert_eq!(rebuilt.top(MlhmMode::SolidsAir), f64::INFINITY);
    }
}

#[test]
fn padding_rounds_outward_in_f32_and_f16() {
    // 1000.3 + 0.01 is no f32: the padded maximum is the f32 above, the padded minimum the
    // f32 below 1000.3 - 0.01; at f16, 1000.5 and 1000.0. (4 layer slots: 2 at level 1, so
    // the upper column does not fold into layer 0.)
    let mut map = Mlhm::new(2, 2, 4, 1.0).unwrap();
    map.set_cell(
        0,
        0,
        &[
            MlhmColumn::new(1000.3, 0.0, 0.0, 1000.3),
            MlhmColumn::new(1001.0, 0.0, 0.0, f32::INFINITY),
        ],
    )
    .unwrap();
    let h = MlhmHierarchy::build_padded(&map, 0.01, Precision::F32);
    let layer = h.node_layer(1, 0, 0, 0);
    assert!(layer.solid_max as f64 >= 1000.3f32 as f64 + 0.01);
    assert!((layer.solid_max.next_down() as f64) < 1000.3f32 as f64 + 0.01);
    assert!(layer.ceiling_min as f64 <= 1000.3f32 as f64 - 0.01);
    assert!((layer.ceiling_min.next_up() as f64) > 1000.3f32 as f64 - 0.01);
    assert_eq!(h.top(MlhmMode::Solids), f32_at_or_above(1001.0 + 0.01) as f64);
    let half = MlhmHierarchy::build_padded(&map, 0.01, Precision::F16);
    let layer = half.node_layer(1, 0, 0, 0);
    assert_eq!((layer.solid_max, layer.ceiling_min), (1000.5, 1000.0));
    // Huge paddings saturate to infinities at f16, stay finite at f32.
    let far = MlhmHierarchy::build_padded(&map, 1e6, Precision::F16);
    let layer = far.node_layer(1, 0, 0, 0);
    assert_eq!((layer.solid_max, layer.ceiling_min), (f32::INFINITY, f32::NEG_INFINITY));
    let far = MlhmHierarchy::build_padded(&map, 1e6, Precision::F32);
    assert!(far.node_layer(1, 0, 0, 0).solid_max.is_finite());
}

#[test]
#[should_panic(expected = "smoothing radius")]
fn negative_padding_panics() {
    MlhmHierarchy::build_padded(&Mlhm::new(2, 2, 1, 1.0).unwrap(), -1.0, Precision::F32);
}
