//! Exact material volumes of an MLHM in a box ([`Mlhm::material_volumes`],
//! [`Mlhm::solid_volume`]) against an independent midpoint-rule integration over a fine grid
//! of sample points, closed-form cases, additivity and degenerate boxes.

use proptest::prelude::*;
use relief_core::{DVec3, MaterialVolumes, Mlhm, MlhmColumn};

const INF: f32 = f32::INFINITY;

/// A small deterministic generator (SplitMix64), so that a proptest seed gives a whole map.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in `0..n`.
    fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    /// A thickness: zero a third of the time, else up to `max`; a multiple of `quantum` when
    /// one is given.
    fn thickness(&mut self, max: f64, quantum: Option<f64>) -> f32 {
        if self.below(3) == 0 {
            return 0.0;
        }
        match quantum {
            Some(q) => (q * self.below((max / q) as u64 + 1) as f64) as f32,
            None => self.range(0.0, max) as f32,
        }
    }
}

/// A random map of `width x height` cells of `cell_size` metres, 1 to 4 columns a cell, with
/// random (often empty) bedrock, sand, water and air gaps; every value a multiple of
/// `quantum` when one is given.
fn random_mlhm(
    rng: &mut Rng,
    width: usize,
    height: usize,
    cell_size: f64,
    quantum: Option<f64>,
) -> Mlhm {
    random_mlhm_of(rng, width, height, 4, cell_size, quantum)
}

/// As [`random_mlhm`], with 1 to `max_columns` columns a cell.
fn random_mlhm_of(
    rng: &mut Rng,
    width: usize,
    height: usize,
    max_columns: usize,
    cell_size: f64,
    quantum: Option<f64>,
) -> Mlhm {
    let mut map = Mlhm::new(width, height, max_columns, cell_size).unwrap();
    for y in 0..height {
        for x in 0..width {
            let count = 1 + rng.below(max_columns as u64) as usize;
            let mut columns = Vec::with_capacity(count);
            let mut bedrock = match quantum {
                Some(q) => (q * (rng.below((4.0 / q) as u64 + 1) as f64) - 2.0) as f32,
                None => rng.range(-2.0, 2.0) as f32,
            };
            for k in 0..count {
                let sand = rng.thickness(1.0, quantum);
                let water = rng.thickness(1.0, quantum);
                let mut column = MlhmColumn::new(bedrock, sand, water, INF);
                if k + 1 < count {
                    column.ceiling = column.water_top() + rng.thickness(1.5, quantum);
                    bedrock = column.ceiling + rng.thickness(1.5, quantum);
                }
                columns.push(column);
            }
            map.set_cell(x, y, &columns).unwrap();
        }
    }
    map
}

/// What a point holds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Material {
    Bedrock,
    Sand,
    Water,
    Nothing,
}

/// The material at grid-local point `p`, looked up column by column.
fn material_at(map: &Mlhm, p: DVec3) -> Material {
    let s = map.cell_size();
    let (cx, cy) = ((p.x / s).floor(), (p.y / s).floor());
    if cx < 0.0 || cy < 0.0 || cx >= map.width() as f64 || cy >= map.height() as f64 {
        return Material::Nothing;
    }
    let (cx, cy) = (cx as usize, cy as usize);
    let z = p.z;
    let mut floor = f64::NEG_INFINITY;
    for c in map.cell_columns(cx, cy) {
        let ceiling = f64::from(c.ceiling);
        if floor <= z && z < ceiling {
            return if z < f64::from(c.bedrock) {
                Material::Bedrock
            } else if z < f64::from(c.bedrock + c.sand) {
                Material::Sand
            } else if z < f64::from(c.bedrock + c.sand + c.water) {
                Material::Water
            } else {
                Material::Nothing
            };
        }
        floor = ceiling;
    }
    Material::Nothing
}

/// The volumes in the box from `min` to `max` by the midpoint rule with `samples` sample
/// cells along each axis.
fn midpoint_volumes(map: &Mlhm, min: DVec3, max: DVec3, samples: [usize; 3]) -> MaterialVolumes {
    let step = (max - min) / DVec3::new(samples[0] as f64, samples[1] as f64, samples[2] as f64);
    let sample_volume = step.x * step.y * step.z;
    let mut v = MaterialVolumes::default();
    for i in 0..samples[0] {
        for j in 0..samples[1] {
            for k in 0..samples[2] {
                let ijk = DVec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5);
                match material_at(map, min + ijk * step) {
                    Material::Bedrock => v.bedrock += sample_volume,
                    Material::Sand => v.sand += sample_volume,
                    Material::Water => v.water += sample_volume,
                    Material::Nothing => {}
                }
            }
        }
    }
    v
}

/// The largest difference between two volumes, material by material.
fn largest_difference(a: MaterialVolumes, b: MaterialVolumes) -> f64 {
    let d = [a.bedrock - b.bedrock, a.sand - b.sand, a.water - b.water];
    d.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Every volume is finite, >= 0 and at most the part of the box over the grid.
fn check_bounds(map: &Mlhm, min: DVec3, max: DVec3, v: MaterialVolumes) -> Result<(), String> {
    let s = map.cell_size();
    let over = |lo: f64, hi: f64, extent: f64| (hi.min(extent) - lo.max(0.0)).max(0.0);
    let inside = over(min.x, max.x, map.width() as f64 * s)
        * over(min.y, max.y, map.height() as f64 * s)
        * (max.z - min.z);
    let slack = 1e-9 * inside.max(1.0);
    for x in [v.bedrock, v.sand, v.water] {
        if !(x.is_finite() && x >= 0.0) {
            return Err(format!("volume {x} in {v:?}"));
        }
    }
    if v.total() > inside + slack {
        return Err(format!("{v:?} holds more than the box's {inside} over the grid"));
    }
    Ok(())
}

/// `k q` for a random `k` in `lo..=hi`.
fn quantised(rng: &mut Rng, q: f64, lo: i64, hi: i64) -> f64 {
    q * (lo + rng.below((hi - lo + 1) as u64) as i64) as f64
}

/// Two values of `pick`, sorted, distinct.
fn ordered_pair(rng: &mut Rng, mut pick: impl FnMut(&mut Rng) -> f64) -> (f64, f64) {
    loop {
        let (a, b) = (pick(rng), pick(rng));
        if a != b {
            return (a.min(b), a.max(b));
        }
    }
}

/// A random box over a `width x height` grid of `cell_size` metres reaching 1 m beyond it.
fn random_box(rng: &mut Rng, map: &Mlhm) -> (DVec3, DVec3) {
    let s = map.cell_size();
    let (wx, wy) = (map.width() as f64 * s, map.height() as f64 * s);
    let (x0, x1) = ordered_pair(rng, |r| r.range(-1.0, wx + 1.0));
    let (y0, y1) = ordered_pair(rng, |r| r.range(-1.0, wy + 1.0));
    let (z0, z1) = ordered_pair(rng, |r| r.range(-4.0, 12.0));
    (DVec3::new(x0, y0, z0), DVec3::new(x1, y1, z1))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// With cell sizes, column values and box bounds all multiples of a quantum, no sample
    /// cell of the midpoint rule straddles a material boundary, so the rule is exact.
    #[test]
    fn volumes_equal_the_midpoint_rule_on_quantised_maps(
        width in 1usize..=4,
        height in 1usize..=4,
        cell_quanta in 1u32..=6,
        seed in any::<u64>(),
    ) {
        const XY: f64 = 0.125;
        const Z: f64 = 0.25;
        let mut rng = Rng(seed);
        let cell_size = f64::from(cell_quanta) * XY;
        let map = random_mlhm(&mut rng, width, height, cell_size, Some(Z));
        for _ in 0..4 {
            let quanta = |cells: usize| (cells as f64 * cell_size / XY).round() as i64;
            let (x0, x1) = ordered_pair(&mut rng, |r| quantised(r, XY, -4, quanta(width) + 4));
            let (y0, y1) = ordered_pair(&mut rng, |r| quantised(r, XY, -4, quanta(height) + 4));
            let (z0, z1) = ordered_pair(&mut rng, |r| quantised(r, Z, -16, 56));
            let (min, max) = (DVec3::new(x0, y0, z0), DVec3::new(x1, y1, z1));
            let samples = [
                ((x1 - x0) / XY).round() as usize,
                ((y1 - y0) / XY).round() as usize,
                ((z1 - z0) / Z).round() as usize,
            ];
            let expected = midpoint_volumes(&map, min, max, samples);
            let v = map.material_volumes(min, max);
            let box_volume = (max - min).element_product();
            prop_assert!(largest_difference(v, expected) <= 1e-9 * box_volume,
                "{min} {max}: {v:?}, midpoint rule {expected:?}");
            let solid = map.solid_volume(min, max);
            prop_assert!((solid - expected.solid()).abs() <= 1e-9 * box_volume,
                "{min} {max}: solid {solid}, midpoint rule {}", expected.solid());
            check_bounds(&map, min, max, v).map_err(TestCaseError::fail)?;
        }
    }

    /// On any map and box the midpoint rule errs only in sample cells that a material boundary
    /// crosses: within one slab of sample cells along each grid line in the box and along each
    /// of a cell's at most 4 boundaries a column, which bounds the difference.
    #[test]
    fn volumes_agree_with_the_midpoint_rule_on_any_map(
        width in 1usize..=4,
        height in 1usize..=4,
        cell_size in prop_oneof![Just(1.0), Just(0.0625), 0.05f64..2.0],
        seed in any::<u64>(),
    ) {
        const SAMPLES: usize = 96;
        let mut rng = Rng(seed);
        let map = random_mlhm(&mut rng, width, height, cell_size, None);
        for _ in 0..3 {
            let (min, max) = random_box(&mut rng, &map);
            let size = max - min;
            let step = size / SAMPLES as f64;
            let lines_inside = |lo: f64, hi: f64, cells: usize| {
                let inside = |i: &usize| (lo..hi).contains(&(*i as f64 * cell_size));
                (0..=cells).filter(inside).count() as f64
            };
            let bound = lines_inside(min.x, max.x, width) * step.x * size.y * size.z
                + lines_inside(min.y, max.y, height) * step.y * size.x * size.z
                + 4.0 * 4.0 * step.z * size.x * size.y
                + 1e-9 * size.element_product();
            let expected = midpoint_volumes(&map, min, max, [SAMPLES; 3]);
            let v = map.material_volumes(min, max);
            prop_assert!(largest_difference(v, expected) <= bound,
                "{min} {max}: {v:?}, midpoint rule {expected:?}, bound {bound}");
            check_bounds(&map, min, max, v).map_err(TestCaseError::fail)?;
        }
    }

    /// Splitting a box in two along any axis at any point splits every volume.
    #[test]
    fn volumes_add_up_over_a_split_box(
        width in 1usize..=5,
        height in 1usize..=5,
        cell_size in prop_oneof![Just(1.0), 0.05f64..2.0],
        seed in any::<u64>(),
        axis in 0usize..3,
        split in 0.0f64..1.0,
    ) {
        let mut rng = Rng(seed);
        let map = random_mlhm(&mut rng, width, height, cell_size, None);
        for _ in 0..8 {
            let (min, max) = random_box(&mut rng, &map);
            let at = min[axis] + split * (max[axis] - min[axis]);
            let (mut lower_max, mut upper_min) = (max, min);
            lower_max[axis] = at;
            upper_min[axis] = at;
            let whole = map.material_volumes(min, max);
            let parts = map.material_volumes(min, lower_max) + map.material_volumes(upper_min, max);
            let tolerance = 1e-9 * (max - min).element_product().max(1e-3);
            prop_assert!(largest_difference(whole, parts) <= tolerance,
                "{min} {max} split on {axis} at {at}: {whole:?} != {parts:?}");
            let solid_parts = map.solid_volume(min, lower_max) + map.solid_volume(upper_min, max);
            prop_assert!((map.solid_volume(min, max) - solid_parts).abs() <= tolerance);
        }
    }

    /// The solid-only volume is the solid part of the material volumes.
    #[test]
    fn solid_volume_is_the_solid_part_of_the_material_volumes(
        width in 1usize..=5,
        height in 1usize..=5,
        cell_size in 0.05f64..2.0,
        seed in any::<u64>(),
    ) {
        let mut rng = Rng(seed);
        let map = random_mlhm(&mut rng, width, height, cell_size, None);
        for _ in 0..16 {
            let (min, max) = random_box(&mut rng, &map);
            let solid = map.solid_volume(min, max);
            let expected = map.material_volumes(min, max).solid();
            prop_assert!((solid - expected).abs() <= 1e-12 * (max - min).element_product().max(1.0),
                "{min} {max}: {solid} != {expected}");
        }
    }
}

/// A 3 x 3 map of 0.5 m cells, flat at bedrock 0 except cell (1, 1): bedrock to 1 m, sand to
/// 1.5 m, water to 2 m, air to 3 m, then bedrock from 3 m to 5 m with 0.5 m of sand on top.
fn overhang_map() -> Mlhm {
    let mut map = Mlhm::new(3, 3, 2, 0.5).unwrap();
    map.set_cell(1, 1, &[MlhmColumn::new(1.0, 0.5, 0.5, 3.0), MlhmColumn::new(5.0, 0.5, 0.0, INF)])
        .unwrap();
    map
}

#[test]
fn a_box_inside_one_columns_bedrock_holds_its_volume_of_bedrock() {
    let map = overhang_map();
    let (min, max) = (DVec3::new(0.6, 0.55, 3.25), DVec3::new(0.9, 0.95, 4.5));
    let v = map.material_volumes(min, max);
    let volume = (max - min).element_product();
    assert!((v.bedrock - volume).abs() < 1e-15, "{v:?}");
    assert_eq!((v.sand, v.water), (0.0, 0.0));
    assert!((map.solid_volume(min, max) - volume).abs() < 1e-15);
    // The same box in the lowest column's bedrock, far below.
    let (min, max) = (DVec3::new(0.6, 0.55, -1e6), DVec3::new(0.9, 0.95, 0.5));
    let v = map.material_volumes(min, max);
    assert!((v.bedrock - (max - min).element_product()).abs() < 1e-6, "{v:?}");
    // In the air gap there is nothing.
    let v = map.material_volumes(DVec3::new(0.5, 0.5, 2.0), DVec3::new(1.0, 1.0, 3.0));
    assert_eq!(v, MaterialVolumes::ZERO);
}

#[test]
fn every_layer_of_a_column_is_counted_once() {
    let map = overhang_map();
    let area = 0.25;
    let v = map.material_volumes(DVec3::new(0.5, 0.5, 0.0), DVec3::new(1.0, 1.0, 10.0));
    assert_eq!(v, MaterialVolumes { bedrock: area * 3.0, sand: area * 1.0, water: area * 0.5 });
    // Straddling: a quarter of the cell, from 1.25 m (in the sand) to 5.25 m (in the top sand).
    let v = map.material_volumes(DVec3::new(0.25, 0.75, 1.25), DVec3::new(0.75, 1.25, 5.25));
    // The flat cells under the other three quarters of the footprint hold nothing up there.
    let quarter = area / 4.0;
    let expected =
        MaterialVolumes { bedrock: quarter * 2.0, sand: quarter * 0.5, water: quarter * 0.5 };
    assert_eq!(v, expected);
}

#[test]
fn a_flat_map_holds_the_footprint_times_the_height_below_its_surface() {
    let mut map = Mlhm::new(5, 4, 1, 0.3).unwrap();
    for y in 0..4 {
        for x in 0..5 {
            map.set_cell(x, y, &[MlhmColumn::new(1.0, 0.25, 0.5, INF)]).unwrap();
        }
    }
    // Footprint [0.2, 1.1] x [0.45, 1.2] (inside the 1.5 x 1.2 grid), from 0.8 m to 1.6 m.
    let (min, max) = (DVec3::new(0.2, 0.45, 0.8), DVec3::new(1.1, 1.2, 1.6));
    let area = 0.9 * 0.75;
    let v = map.material_volumes(min, max);
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert!(close(v.bedrock, area * 0.2), "{v:?}");
    assert!(close(v.sand, area * 0.25), "{v:?}");
    assert!(close(v.water, area * 0.35), "{v:?}");
    assert!(close(map.solid_volume(min, max), area * 0.45));
    // Reaching beyond the grid on every side: only the grid's 1.5 m x 1.2 m counts.
    let (min, max) = (DVec3::new(-2.0, -0.1, 1.0), DVec3::new(7.0, 1.5, 2.0));
    assert!(close(map.solid_volume(min, max), 1.5 * 1.2 * 0.25));
    let v = map.material_volumes(
        DVec3::new(f64::NEG_INFINITY, -1e300, 0.0),
        DVec3::new(f64::INFINITY, 1e300, 2.0),
    );
    assert!(close(v.total(), 1.5 * 1.2 * 1.75), "{v:?}");
}

#[test]
fn a_box_reaching_down_to_minus_infinity_holds_infinite_bedrock() {
    let map = overhang_map();
    let v =
        map.material_volumes(DVec3::new(0.0, 0.0, f64::NEG_INFINITY), DVec3::new(1.5, 1.5, 4.0));
    assert_eq!(v.bedrock, f64::INFINITY);
    assert_eq!((v.sand, v.water), (0.25 * 0.5, 0.25 * 0.5));
    let v = map.material_volumes(DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.5, 1.5, f64::INFINITY));
    assert_eq!(v, MaterialVolumes { bedrock: 0.25 * 3.0, sand: 0.25 * 1.0, water: 0.25 * 0.5 });
}

#[test]
fn empty_columns_and_gaps_hold_nothing() {
    let mut map = Mlhm::new(1, 1, 4, 1.0).unwrap();
    // A zero-thickness column between two touching ones: bedrock 0..1, then a column with
    // floor 1, bedrock top 1, no sand, no water and ceiling 1, then bedrock 1..2.
    map.set_cell(
        0,
        0,
        &[
            MlhmColumn::new(1.0, 0.0, 0.0, 1.0),
            MlhmColumn::new(1.0, 0.0, 0.0, 1.0),
            MlhmColumn::new(2.0, 0.0, 0.0, INF),
        ],
    )
    .unwrap();
    let v = map.material_volumes(DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 1.0, 3.0));
    assert_eq!(v, MaterialVolumes { bedrock: 2.0, sand: 0.0, water: 0.0 });
}

#[test]
fn degenerate_and_nan_boxes_hold_nothing() {
    let map = overhang_map();
    let (min, max) = (DVec3::new(0.25, 0.25, -1.0), DVec3::new(1.25, 1.25, 6.0));
    assert!(map.material_volumes(min, max).total() > 0.0);
    let mut boxes = vec![(max, min), (min, min)];
    for axis in 0..3 {
        let mut flat = max;
        flat[axis] = min[axis];
        boxes.push((min, flat));
        let mut inverted = max;
        inverted[axis] = min[axis] - 0.1;
        boxes.push((min, inverted));
        for nan_at_min in [true, false] {
            let (mut a, mut b) = (min, max);
            if nan_at_min {
                a[axis] = f64::NAN
            } else {
                b[axis] = f64::NAN
            }
            boxes.push((a, b));
        }
    }
    // Wholly outside the grid, on each side.
    let extent = 1.5;
    boxes.push((DVec3::new(-2.0, 0.0, -1.0), DVec3::new(0.0, 1.0, 6.0)));
    boxes.push((DVec3::new(extent, 0.0, -1.0), DVec3::new(9.0, 1.0, 6.0)));
    boxes.push((DVec3::new(0.0, -2.0, -1.0), DVec3::new(1.0, -1e-9, 6.0)));
    boxes.push((DVec3::new(0.0, extent, -1.0), DVec3::new(1.0, f64::INFINITY, 6.0)));
    boxes.push((DVec3::splat(f64::INFINITY), DVec3::splat(f64::INFINITY)));
    boxes.push((DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::NEG_INFINITY)));
    for (a, b) in boxes {
        assert_eq!(map.material_volumes(a, b), MaterialVolumes::ZERO, "{a} {b}");
        assert_eq!(map.solid_volume(a, b), 0.0, "{a} {b}");
    }
}
