//! The exact far field (`--far exact`), relief's own option beside the paper's levels of
//! precision: the exact first hit between the nearest ray-cast proxy box and the rasterized
//! near field's depth.

use crate::{Hit, Tracer};
use relief_core::Ray;

/// The exact first hit of `ray` in `[t0, t1]` (within the ray's own range), or `None`.
///
/// `t0` is a lower bound on where the ray can first meet a ray-cast cell (the nearest entry
/// into a ray-cast cell's proxy box, [`super::box_entry`]), `t1` the rasterized near field's
/// depth along the ray (or +inf where nothing was rasterized): the exact tracer then only
/// searches between them. `tracer` is any exact tracer (the [`crate::MipmapTracer`] in
/// practice); its answer is [`Tracer::intersect`] of the ray restricted to that range, so a
/// ray already inside the solid at `t0` hits at `t0`. An empty or NaN range gives `None`.
pub fn exact_far_hit(tracer: &dyn Tracer, ray: &Ray, t0: f64, t1: f64) -> Option<Hit> {
    let ranged = far_range(ray, t0, t1)?;
    tracer.intersect(&ranged)
}

/// [`exact_far_hit`] for many rays at once through [`Tracer::intersect_batch`] (the mipmap
/// tracer's coherent packets): `hits[k]` is `exact_far_hit(tracer, &rays[k], t0[k], t1[k])`.
/// Pass neighbouring rays together. Panics when the slices differ in length.
pub fn exact_far_hits(
    tracer: &dyn Tracer,
    rays: &[Ray],
    t0: &[f64],
    t1: &[f64],
    hits: &mut [Option<Hit>],
) {
    assert!(
        rays.len() == t0.len() && rays.len() == t1.len() && rays.len() == hits.len(),
        "far-field slices differ in length"
    );
    let mut ranged = Vec::with_capacity(rays.len());
    let mut source = Vec::with_capacity(rays.len());
    for (k, ray) in rays.iter().enumerate() {
        if let Some(r) = far_range(ray, t0[k], t1[k]) {
            ranged.push(r);
            source.push(k);
        }
    }
    let mut found = vec![None; ranged.len()];
    let mut steps = vec![0; ranged.len()];
    tracer.intersect_batch(&ranged, &mut found, &mut steps);
    hits.fill(None);
    for (k, hit) in source.into_iter().zip(found) {
        hits[k] = hit;
    }
}

/// The ray restricted to `[max(t0, t_min), min(t1, t_max)]`, or `None` when that is empty.
fn far_range(ray: &Ray, t0: f64, t1: f64) -> Option<Ray> {
    let (lo, hi) = (t0.max(ray.t_min), t1.min(ray.t_max));
    (lo <= hi).then(|| ray.with_range(lo, hi))
}
