//! Stamping brushes against brute force: only samples within the radius change, the returned
//! region covers every change, raise then lower restores the field, and smoothing reads the
//! field as it was before the stamp.

use proptest::prelude::*;
use relief_core::{DVec2, GridGeometry, HeightField, SampleRegion};
use relief_sim::{stamp, Brush, BrushKind};

fn field(width: usize, height: usize, seed: u64, g: GridGeometry) -> HeightField {
    let samples = (0..width * height)
        .map(|i| {
            let h = (i as u64 + 1).wrapping_mul(seed | 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            (h >> 40) as f32 / (1u64 << 24) as f32 * 20.0 - 5.0
        })
        .collect();
    HeightField::new(width, height, samples, g).unwrap()
}

/// Squared world distance from sample (col, row) to `centre`.
fn distance2(g: &GridGeometry, col: usize, row: usize, centre: DVec2) -> f64 {
    let x = g.origin.x + (col as f64 + 0.5) * g.dx;
    let y = g.origin.y + (row as f64 + 0.5) * g.dy;
    (x - centre.x).powi(2) + (y - centre.y).powi(2)
}

fn kind() -> impl Strategy<Value = BrushKind> {
    prop_oneof![
        Just(BrushKind::Raise),
        Just(BrushKind::Lower),
        Just(BrushKind::Smooth),
        Just(BrushKind::Flatten)
    ]
}

fn geometry() -> impl Strategy<Value = GridGeometry> {
    (0.5f64..3.0, 0.5f64..3.0, 0.25f64..4.0, -10.0f64..10.0, -10.0f64..10.0).prop_map(
        |(dx, dy, z_scale, ox, oy)| GridGeometry { dx, dy, z_scale, origin: DVec2::new(ox, oy) },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn only_samples_within_the_radius_change(
        width in 1usize..20, height in 1usize..20, seed in any::<u64>(), g in geometry(),
        kind in kind(), fx in -0.3f64..1.3, fy in -0.3f64..1.3, radius in 0.2f64..12.0,
        strength in 0.0f64..1.0,
    ) {
        let mut f = field(width, height, seed, g);
        let before = f.clone();
        let centre = DVec2::new(
            g.origin.x + fx * width as f64 * g.dx,
            g.origin.y + fy * height as f64 * g.dy,
        );
        let brush = Brush { kind, centre, radius, strength };
        let region = stamp(&mut f, &brush).unwrap();
        let mut changed = SampleRegion::default();
        for row in 0..height {
            for col in 0..width {
                if f.sample(col, row) != before.sample(col, row) {
                    prop_assert!(distance2(&g, col, row, centre) < radius * radius,
                        "({col}, {row}) changed outside the radius");
                    prop_assert!(region.contains(col, row), "({col}, {row}) outside {region:?}");
                    changed = changed.union(&SampleRegion::new(col, row, col + 1, row + 1));
                }
            }
        }
        // The region stays near the disc: no more than a sample beyond its bounding box.
        let g2 = f.geometry();
        prop_assert!(region.len() as f64
            <= (2.0 * radius / g2.dx + 2.0) * (2.0 * radius / g2.dy + 2.0) + 1e-9);
    }

    #[test]
    fn raise_then_lower_restores(
        width in 1usize..16, height in 1usize..16, seed in any::<u64>(), g in geometry(),
        fx in 0.0f64..1.0, fy in 0.0f64..1.0, radius in 0.2f64..12.0, strength in 0.0f64..50.0,
    ) {
        let mut f = field(width, height, seed, g);
        let before = f.clone();
        let centre = DVec2::new(
            g.origin.x + fx * width as f64 * g.dx,
            g.origin.y + fy * height as f64 * g.dy,
        );
        let raise = Brush { kind: BrushKind::Raise, centre, radius, strength };
        let a = stamp(&mut f, &raise).unwrap();
        let b = stamp(&mut f, &Brush { kind: BrushKind::Lower, ..raise }).unwrap();
        prop_assert_eq!(a, b);
        let lift = (strength / g.z_scale) as f32;
        for (x, y) in f.samples().iter().zip(before.samples()) {
            // Two f32 roundings of values up to |y| + lift.
            let tolerance = 2.0 * f32::EPSILON * (y.abs() + lift);
            prop_assert!((x - y).abs() <= tolerance, "{x} vs {y} (lift {lift})");
        }
    }

    #[test]
    fn smoothing_matches_brute_force_from_the_old_field(
        width in 1usize..14, height in 1usize..14, seed in any::<u64>(), g in geometry(),
        fx in 0.0f64..1.0, fy in 0.0f64..1.0, radius in 0.2f64..12.0, strength in 0.0f64..=1.0,
    ) {
        let mut f = field(width, height, seed, g);
        let before = f.clone();
        let centre = DVec2::new(
            g.origin.x + fx * width as f64 * g.dx,
            g.origin.y + fy * height as f64 * g.dy,
        );
        let brush = Brush { kind: BrushKind::Smooth, centre, radius, strength };
        stamp(&mut f, &brush).unwrap();
        for row in 0..height {
            for col in 0..width {
                let t = 1.0 - distance2(&g, col, row, centre) / (radius * radius);
                let w = if t > 0.0 { strength * t * t } else { 0.0 };
                let old = before.sample(col, row);
                let expected = if w == 0.0 {
                    old
                } else {
                    let (mut sum, mut n) = (0.0f64, 0.0f64);
                    for y in row.saturating_sub(1)..(row + 2).min(height) {
                        for x in col.saturating_sub(1)..(col + 2).min(width) {
                            sum += f64::from(before.sample(x, y));
                            n += 1.0;
                        }
                    }
                    (f64::from(old) + w * (sum / n - f64::from(old))) as f32
                };
                prop_assert_eq!(f.sample(col, row), expected, "({}, {})", col, row);
            }
        }
    }
}

#[test]
fn flatten_keeps_the_centre_sample_and_levels_towards_it() {
    let g = GridGeometry::unit();
    let mut f = field(21, 21, 7, g);
    let before = f.clone();
    let centre = DVec2::new(10.5, 10.5);
    let brush = Brush { kind: BrushKind::Flatten, centre, radius: 6.0, strength: 1.0 };
    stamp(&mut f, &brush).unwrap();
    let target = before.sample(10, 10);
    assert_eq!(f.sample(10, 10), target);
    // Weight 1 at the centre sample, (1 - 1/36)² one sample east of it.
    let w = (1.0f64 - 1.0 / 36.0).powi(2);
    let old = f64::from(before.sample(11, 10));
    assert_eq!(f.sample(11, 10), (old + w * (f64::from(target) - old)) as f32);
}

#[test]
fn holes_stay_holes() {
    let g = GridGeometry::unit();
    let mut holes = vec![false; 25];
    holes[12] = true;
    let mut f = field(5, 5, 3, g).with_holes(holes).unwrap();
    // The lowest sample that is not a hole, found here rather than asked of the field.
    let lowest_valid = |f: &HeightField| {
        let valid = (0..25).filter(|&i| !f.is_hole(i % 5, i / 5));
        valid.map(|i| f.sample(i % 5, i / 5)).fold(f32::INFINITY, f32::min)
    };
    // A hole holds the field's lowest sample, as HeightField says.
    let hole_value = f.sample(2, 2);
    assert_eq!(hole_value, lowest_valid(&f));
    for kind in [BrushKind::Raise, BrushKind::Smooth, BrushKind::Flatten] {
        let before = f.clone();
        let brush = Brush { kind, centre: DVec2::new(2.5, 2.5), radius: 3.0, strength: 1.0 };
        stamp(&mut f, &brush).unwrap();
        assert!(f.is_hole(2, 2), "{kind:?}");
        // The brush changed the samples around the hole...
        let changed = (0..25).filter(|&i| f.samples()[i] != before.samples()[i]).count();
        assert!(changed > 1, "{kind:?} changed {changed} samples");
        // ...but not the hole: it still holds the lowest valid sample, whatever that is now.
        assert_eq!(f.sample(2, 2), lowest_valid(&f), "{kind:?}");
        assert_eq!(f.sample(2, 2), f.min_sample(), "{kind:?}");
        if kind == BrushKind::Raise {
            // Every sample lies within the radius: the lowest valid sample rose, and the hole
            // followed it up, not by the brush's whole metre (its weight is 1 at the hole).
            let now = f.sample(2, 2);
            assert!(now > hole_value && now != hole_value + 1.0, "{hole_value} -> {now}");
        }
    }
}
