//! The cells of a multi-layered height map placed in the world, as both MLHM tracers see
//! them: rays mapped to cell space, a cell's part of a ray from its integer bounds, and the
//! exact first hit among a cell's boxes. Shared, so the naive and hierarchical tracers compute
//! bit-identical hits.

use super::boxes::{for_each_box, BoxEntry, Layer};
use crate::cell_grid::axis_span;
use crate::{Hit, MlhmHit, MlhmMode};
use relief_core::{Aabb, BoxFace, Clip, DVec2, DVec3, Mlhm, Ray};

/// A world ray in the cell space of `map` placed at `origin` (same parameter `t`), or `None`
/// when it cannot be traced (non-finite, zero or subnormal direction, empty range).
pub(crate) fn ray_to_cells(map: &Mlhm, origin: DVec2, ray: &Ray) -> Option<Ray> {
    let inv_s = 1.0 / map.cell_size();
    let scale = DVec3::new(inv_s, inv_s, 1.0);
    let cell =
        Ray { origin: (ray.origin - origin.extend(0.0)) * scale, dir: ray.dir * scale, ..*ray };
    let ok = cell.origin.is_finite()
        && cell.dir.is_finite()
        && cell.dir != DVec3::ZERO
        && (0..3).all(|a| cell.dir[a] == 0.0 || (1.0 / cell.dir[a]).is_finite())
        && ray.t_min <= ray.t_max
        && !ray.t_min.is_nan();
    ok.then_some(cell)
}

/// The world box over the footprint of `map` placed at `origin`, from the map's
/// [base](Mlhm::base) (minus infinity unless set: the lowest columns reach down forever) up to
/// `top`.
pub(crate) fn world_box(map: &Mlhm, origin: DVec2, top: f64) -> Aabb {
    let size = DVec2::new(map.width() as f64, map.height() as f64) * map.cell_size();
    Aabb::new(origin.extend(map.base() as f64), (origin + size).extend(top))
}

/// A cell's part of the clipped ray.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Segment {
    /// Where the ray enters the cell (within the clip).
    pub(crate) t_enter: f64,
    /// Where it leaves the cell (within the clip).
    pub(crate) t_exit: f64,
    /// Where it crosses the cell's far x boundary (may exceed the clip).
    pub(crate) t_next_x: f64,
    /// Where it crosses the cell's far y boundary (may exceed the clip).
    pub(crate) t_next_y: f64,
    /// The horizontal axis whose face the ray enters through at `t_enter`; `None` when it
    /// starts inside the scene box (or enters it through its top).
    pub(crate) entry: Option<usize>,
}

/// The part of the clipped ray inside cell `(cx, cy)`, from the cell's integer bounds.
#[inline]
pub(crate) fn segment(ray: &Ray, inv: DVec3, clip: &Clip, cx: usize, cy: usize) -> Segment {
    let (x_in, x_out) = axis_span(ray.origin.x, ray.dir.x, inv.x, cx as f64);
    let (y_in, y_out) = axis_span(ray.origin.y, ray.dir.y, inv.y, cy as f64);
    let mut t_enter = clip.t_enter;
    let mut entry = match clip.face {
        BoxFace::X => Some(0),
        BoxFace::Y => Some(1),
        BoxFace::Inside | BoxFace::Z => None,
    };
    if x_in > t_enter {
        t_enter = x_in;
        entry = Some(0);
    }
    if y_in > t_enter {
        t_enter = y_in;
        entry = Some(1);
    }
    let t_exit = clip.t_exit.min(x_out).min(y_out);
    Segment { t_enter, t_exit, t_next_x: x_out, t_next_y: y_out, entry }
}

/// The first hit with the boxes of cell `(cx, cy)` of `map` within `seg` (`ray` in cell space,
/// `inv` its reciprocal direction; `world_ray` gives the hit its world position).
#[allow(clippy::too_many_arguments)]
pub(crate) fn first_hit_in_cell(
    map: &Mlhm,
    world_ray: &Ray,
    ray: &Ray,
    inv: DVec3,
    mode: MlhmMode,
    cx: usize,
    cy: usize,
    seg: &Segment,
) -> Option<MlhmHit> {
    if seg.t_enter > seg.t_exit || seg.t_enter.is_nan() || seg.t_exit.is_nan() {
        return None;
    }
    let mut best: Option<(f64, BoxEntry, Layer)> = None;
    for_each_box(map, cx, cy, mode, |b| {
        if let Some((t, entry)) = b.slab(ray.origin.z, ray.dir.z, inv.z, seg.t_enter, seg.t_exit) {
            if best.is_none_or(|(bt, _, _)| t < bt) {
                let z = (ray.origin.z + t * ray.dir.z).clamp(b.bottom, b.top());
                best = Some((t, entry, b.layer_at(entry, z)));
            }
        }
        false
    });
    let (t, entry, layer) = best?;
    let normal = match entry {
        BoxEntry::Top => DVec3::Z,
        BoxEntry::Bottom => -DVec3::Z,
        BoxEntry::Segment => match seg.entry {
            None => -world_ray.dir.normalize(),
            Some(axis) => {
                let mut n = DVec3::ZERO;
                n[axis] = -ray.dir[axis].signum();
                n
            }
        },
    };
    Some(MlhmHit {
        hit: Hit { t, position: world_ray.at(t), normal },
        material: layer.material,
        cell: (cx, cy),
        column: layer.column,
    })
}
