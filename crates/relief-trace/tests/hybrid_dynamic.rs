//! Dynamic height fields: after an edit, the mipmap tracer (its pyramid updated only above
//! the edit) equals a tracer rebuilt from scratch over the edited field, bit for bit.

mod common;

use common::scenes::{ray_for, terrain, ALL_KINDS};
use proptest::prelude::*;
use relief_core::{CoreError, GridGeometry, HeightField, SampleRegion, Surface};
use relief_trace::{MipmapTracer, Tracer};
use std::sync::Arc;

/// Asserts that `tracer` equals a rebuild over its own field: the pyramids and the hits of
/// `rays`, one by one and in packets.
fn assert_like_rebuild(
    tracer: &MipmapTracer,
    rays: &[relief_core::Ray],
) -> Result<(), TestCaseError> {
    let fresh = MipmapTracer::new(Arc::new((**tracer.field()).clone()), tracer.surface());
    prop_assert_eq!(tracer.mipmap(), fresh.mipmap());
    for ray in rays {
        prop_assert_eq!(tracer.intersect(ray), fresh.intersect(ray), "{:?}", ray);
    }
    let (mut a, mut b) = (vec![None; rays.len()], vec![None; rays.len()]);
    tracer.intersect_batch(rays, &mut a, &mut vec![0; rays.len()]);
    fresh.intersect_batch(rays, &mut b, &mut vec![0; rays.len()]);
    prop_assert_eq!(a, b);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn an_edit_then_a_trace_equals_a_rebuild_then_a_trace(
        field in terrain(),
        edits in prop::collection::vec((prop::array::uniform4(0.0f64..1.0), -20.0f32..20.0), 1..5),
        numbers in prop::collection::vec(prop::array::uniform8(0.001f64..0.999), ALL_KINDS.len() * 2),
    ) {
        let rays: Vec<_> = numbers
            .iter()
            .enumerate()
            .map(|(i, u)| ray_for(&field, ALL_KINDS[i % ALL_KINDS.len()], *u))
            .collect();
        for surface in Surface::ALL {
            let mut tracer = MipmapTracer::new(Arc::new(field.clone()), surface);
            for (u, delta) in &edits {
                let (w, h) = (field.width() as f64, field.height() as f64);
                let (c0, r0) = ((u[0] * w) as usize, (u[1] * h) as usize);
                let region = SampleRegion::new(c0, r0, c0 + 1 + (u[2] * 6.0) as usize, r0 + 1 + (u[3] * 6.0) as usize);
                // A brush that lifts the middle and lowers the rim (the range may change or not).
                let (mid_c, mid_r) = ((region.col0 + region.col1) / 2, (region.row0 + region.row1) / 2);
                tracer.edit(|f| f.edit_region(region, |c, r, v| {
                    if c == mid_c && r == mid_r { v + delta } else { v - 0.1 * delta }
                })).unwrap();
                assert_like_rebuild(&tracer, &rays)?;
            }
            // A whole-field rewrite (a simulation step).
            tracer.edit(|f| {
                let next = f.samples().iter().map(|v| v * 0.5).collect();
                f.replace_samples(next)?;
                Ok(SampleRegion::whole(f.width(), f.height()))
            }).unwrap();
            assert_like_rebuild(&tracer, &rays)?;
        }
    }
}

#[test]
fn edits_of_a_shared_field_copy_it_and_failed_edits_leave_a_consistent_tracer() {
    let samples = (0..12 * 9).map(|k| ((k * 13) % 7) as f32).collect();
    let field = Arc::new(HeightField::new(12, 9, samples, GridGeometry::unit()).unwrap());
    let mut tracer = MipmapTracer::new(field.clone(), Surface::Triangles);
    // Within the range: only the pyramid above the edit changes.
    let region =
        tracer.edit(|f| f.edit_region(SampleRegion::new(3, 3, 5, 4), |_, _, v| 6.0 - v)).unwrap();
    assert_eq!(region, SampleRegion::new(3, 3, 5, 4));
    assert_eq!(field.sample(4, 3), 2.0, "the other owner keeps its field");
    assert_eq!(tracer.field().sample(4, 3), 4.0);
    let fresh = MipmapTracer::new(tracer.field().clone(), Surface::Triangles);
    assert_eq!(tracer.mipmap(), fresh.mipmap());
    // A failing edit changes nothing and is reported.
    let before = tracer.mipmap().clone();
    let err = tracer.edit(|f| f.edit_region(SampleRegion::whole(12, 9), |_, _, _| f32::NAN));
    assert!(matches!(err, Err(CoreError::NonFiniteSample { .. })));
    assert_eq!(tracer.mipmap(), &before);
    // A closure that swaps in another field: the tracer follows it.
    let other = HeightField::new(5, 4, vec![2.0; 20], GridGeometry::unit()).unwrap();
    tracer
        .edit(|f| {
            *f = other.clone();
            Ok(SampleRegion::default())
        })
        .unwrap();
    assert_eq!(tracer.mipmap(), MipmapTracer::new(Arc::new(other), Surface::Triangles).mipmap());
}
