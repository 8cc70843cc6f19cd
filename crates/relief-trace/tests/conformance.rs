//! Every exact tracer of relief-trace through the conformance suite: the naive and max-mipmap
//! tracers (single rays, and batches through the mipmap's packets with each SIMD kernel), the
//! safety tracer, and the MLHM box tracers over an MLHM built from the height field.

use relief_core::{Aabb, DVec3, HeightField, Mlhm, MlhmColumn, Ray, Surface};
use relief_trace::conformance::{Check, Floor, Suite};
use relief_trace::safety::FinalTest;
use relief_trace::{
    Hit, MipmapTracer, MlhmBacktrack, MlhmHierarchyTracer, MlhmNaiveTracer, NaiveTracer,
    SafetyOptions, SafetyShapes, SafetyTracer, Simd, Tracer,
};
use std::sync::Arc;

#[test]
fn naive_tracer_conforms() {
    Suite::new()
        .run(|field, surface| Some(Box::new(NaiveTracer::new(field.clone(), surface)) as _))
        .assert_conforms();
}

#[test]
fn mipmap_tracer_and_its_packets_conform_with_every_kernel() {
    for simd in [Simd::Portable, Simd::detect()] {
        Suite::new()
            .run(|field, surface| {
                Some(Box::new(MipmapTracer::new(field.clone(), surface).with_simd(simd)) as _)
            })
            .assert_conforms();
    }
}

#[test]
fn safety_tracer_conforms() {
    for options in [SafetyOptions::default(), SafetyOptions { reach: 4, ..Default::default() }] {
        Suite::new()
            .run(|field, surface| {
                if surface != Surface::Triangles || field.hole_count() > 0 {
                    return None;
                }
                let shapes = SafetyShapes::build(field, options, &|_, _| {}).ok()?;
                let tracer =
                    SafetyTracer::new(field.clone(), Arc::new(shapes), FinalTest::Triangles);
                Some(Box::new(tracer.ok()?) as Box<dyn Tracer>)
            })
            .assert_conforms();
    }
}

/// The MLHM of one column per cell standing for `field`'s boxes, when it can: square cells,
/// unit height scale, no holes.
fn mlhm_of(field: &HeightField, surface: Surface) -> Option<Arc<Mlhm>> {
    let g = field.geometry();
    if surface != Surface::Boxes || g.dx != g.dy || g.z_scale != 1.0 || field.hole_count() > 0 {
        return None;
    }
    let mut map = Mlhm::new(field.width(), field.height(), 1, g.dx).ok()?;
    for y in 0..field.height() {
        for x in 0..field.width() {
            let column = MlhmColumn::new(field.sample(x, y), 0.0, 0.0, f32::INFINITY);
            map.set_cell(x, y, &[column]).ok()?;
        }
    }
    Some(Arc::new(map))
}

#[test]
fn mlhm_naive_tracer_conforms() {
    Suite::new()
        .floor(Floor::Unbounded)
        .run(|field, surface| {
            let map = mlhm_of(field, surface)?;
            Some(Box::new(MlhmNaiveTracer::new(map, field.geometry().origin)) as _)
        })
        .assert_conforms();
}

#[test]
fn mlhm_hierarchy_tracer_conforms_with_both_backtracks() {
    for backtrack in [MlhmBacktrack::ExitStack, MlhmBacktrack::MissCounter] {
        Suite::new()
            .floor(Floor::Unbounded)
            .run(|field, surface| {
                let map = mlhm_of(field, surface)?;
                let tracer = MlhmHierarchyTracer::new(map, field.geometry().origin);
                Some(Box::new(tracer.with_backtrack(backtrack)) as _)
            })
            .assert_conforms();
    }
}

/// A naive tracer with one flaw, to show the suite catches it.
struct Flawed {
    inner: NaiveTracer,
    flaw: Check,
}

impl Tracer for Flawed {
    fn name(&self) -> &'static str {
        "flawed"
    }

    fn surface(&self) -> Surface {
        self.inner.surface()
    }

    fn bounds(&self) -> Aabb {
        let b = self.inner.bounds();
        match self.flaw {
            Check::Bounds => Aabb::new(b.min, b.max - DVec3::Z * 0.5 * (b.max.z - b.min.z)),
            _ => b,
        }
    }

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        let hit = self.inner.intersect_counted(ray, steps)?;
        Some(match self.flaw {
            Check::Intersect => Hit { t: hit.t * 1.01 + 1e-3, ..hit },
            Check::Normal => Hit { normal: -hit.normal, ..hit },
            Check::Position => Hit { position: hit.position + DVec3::X, ..hit },
            _ => hit,
        })
    }

    fn occluded_counted(&self, ray: &Ray, steps: &mut u32) -> bool {
        let occluded = self.inner.occluded_counted(ray, steps);
        occluded != (self.flaw == Check::Occluded && ray.t_max.is_finite())
    }

    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], steps: &mut [u32]) {
        for ((ray, hit), steps) in rays.iter().zip(hits.iter_mut()).zip(steps) {
            *hit = self.intersect_counted(ray, steps);
        }
        if self.flaw == Check::IntersectBatch {
            hits.reverse();
        }
    }

    fn occluded_batch(&self, rays: &[Ray], occluded: &mut [bool], steps: &mut [u32]) {
        for ((ray, blocked), steps) in rays.iter().zip(occluded.iter_mut()).zip(steps) {
            *blocked = self.occluded_counted(ray, steps) != (self.flaw == Check::OccludedBatch);
        }
    }
}

#[test]
fn the_suite_catches_each_kind_of_flaw() {
    let flaws = [
        Check::Intersect,
        Check::Position,
        Check::Normal,
        Check::Occluded,
        Check::IntersectBatch,
        Check::OccludedBatch,
        Check::Bounds,
    ];
    for flaw in flaws {
        let report = Suite::new().terrains(10).run(|field, surface| {
            Some(Box::new(Flawed { inner: NaiveTracer::new(field.clone(), surface), flaw }) as _)
        });
        assert!(
            report.failures.iter().any(|f| f.check == flaw),
            "{flaw:?} not caught: {:?}",
            report.failures.first()
        );
    }
}
