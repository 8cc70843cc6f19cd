//! A packet's beam: the cone that holds every ray of a packet whose rays leave one point (a
//! tile of camera rays), tested against a node's children once for all the rays, near the
//! top of the pyramid where the rays have not yet parted company.
//!
//! The cone has its apex at the rays' common origin and is bounded by four planes through it,
//! fitted around the rays' directions. A node's child is a column: its footprint, from below
//! the terrain's box up to its maximum. The beam opens a child for every ray of the node unless
//! the column, grown by more than the per-ray tests' margins and roundings, lies wholly outside
//! one of the four planes; then no ray of the packet meets it, and no ray's own test
//! (`Kernel::children`) would open it either. The beam thus opens a superset of what the
//! per-ray tests open: a ray may be carried into a node it does not meet, where its own tests
//! one level down drop it, but no ray is ever left out of a node it may meet, and the exact
//! cell test still decides every hit.
//!
//! The beam pays only while a node is wide compared with the packet's cross-section at the
//! node's distance; below that the per-ray tests cull better ([`Beam::covers`]).

use super::ray_packet::{Quad, RayPacket};
use super::traversal::ORDER;
use relief_core::DVec3;

/// A node is tested by the beam while its side is at least this many times the packet's
/// cross-section at the node's far end.
const WIDE: f64 = 4.0;

/// The cone around a packet's rays, and what its tests need.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Beam {
    /// The rays' common origin, in cell space.
    apex: DVec3,
    /// Inward normals of the five planes through the apex (four sides, and one across the
    /// axis): every ray's direction `d` has `normal · d >= 0`.
    normals: [DVec3; 5],
    /// How far beyond a child's footprint, in cells, and above its maximum, in height, a ray's
    /// own test may still open it (the margins and roundings of the `f32` lanes, doubled).
    grow_xy: f64,
    /// See `grow_xy`.
    grow_z: f64,
    /// Below the terrain's box, and below any height the per-ray tests look at.
    bottom: f64,
    /// The cone's width: the packet's cross-section at distance 1 from the apex.
    width: f64,
}

impl Beam {
    /// The beam of the rays of `p` over a terrain whose box is `[z_min, z_max]` in height, or
    /// `None` when they do not share their origin, or spread too widely for a narrow cone.
    pub fn of(p: &RayPacket, z_min: f64) -> Option<Beam> {
        let rays = &p.rays[..p.len];
        let apex = rays.first()?.origin;
        if rays.iter().any(|r| r.origin != apex || r.t_min.is_nan() || r.t_min < 0.0) {
            return None;
        }
        let axis =
            rays.iter().map(|r| r.dir.normalize_or_zero()).sum::<DVec3>().normalize_or_zero();
        if axis == DVec3::ZERO {
            return None;
        }
        let u = axis.any_orthonormal_vector();
        let v = axis.cross(u);
        // The rays' tangents along u and v, seen along the axis.
        let (mut u_lo, mut u_hi, mut v_lo, mut v_hi) =
            (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for r in rays {
            let along = r.dir.dot(axis);
            if along <= 1e-3 * r.dir.length() {
                return None;
            }
            let (tu, tv) = (r.dir.dot(u) / along, r.dir.dot(v) / along);
            (u_lo, u_hi) = (u_lo.min(tu), u_hi.max(tu));
            (v_lo, v_hi) = (v_lo.min(tv), v_hi.max(tv));
        }
        let width = (u_hi - u_lo).max(v_hi - v_lo);
        if width.is_nan() || width >= 0.5 {
            return None;
        }
        // Widened by a relative hair, so that every ray lies strictly inside despite rounding.
        let pad = 1e-9 * (1.0 + u_lo.abs().max(u_hi.abs()).max(v_lo.abs()).max(v_hi.abs()));
        let (u_lo, u_hi, v_lo, v_hi) = (u_lo - pad, u_hi + pad, v_lo - pad, v_hi + pad);
        // The four sides, and the plane through the apex across the axis: the cone lies in
        // front of it (every ray's direction has a positive component along the axis).
        let normals = [u - u_lo * axis, u_hi * axis - u, v - v_lo * axis, v_hi * axis - v, axis];
        // How much lower than the ray each lane's height may be: the height margin of
        // `RayPacket::push`, then the f32 rounding of a few operations on heights and times.
        let mut grow_z: f64 = 0.0;
        for (k, r) in rays.iter().enumerate() {
            let entry = r.origin.z + r.dir.z * p.clips[k].t_enter;
            let rounding =
                (p.z_low.0[k] as f64).abs() + (p.dz.0[k] as f64 * p.t_end.0[k] as f64).abs();
            grow_z = grow_z.max(entry - p.z_low.0[k] as f64 + rounding * 1e-6);
        }
        let grow_xy = 4.0 * p.margin_xy as f64 + 1e-6 * (1.0 + apex.x.abs() + apex.y.abs());
        let bottom = z_min - 2.0 * grow_z - 1.0 - z_min.abs();
        Some(Beam { apex, normals, grow_xy, grow_z: 2.0 * grow_z, bottom, width })
    }

    /// Whether the node whose children `quad` spans is wide enough, against the packet's
    /// cross-section where it may cross the node, for the beam to test its children.
    #[inline(always)]
    pub fn covers(&self, q: &Quad) -> bool {
        let side = (q.x[2] - q.x[0]).abs().min((q.y[2] - q.y[0]).abs()) as f64;
        let far = |a: f32, b: f32, e: f64| (a as f64 - e).abs().max((b as f64 - e).abs());
        let dx = far(q.x[0], q.x[2], self.apex.x);
        let dy = far(q.y[0], q.y[2], self.apex.y);
        let dz = (self.apex.z - self.bottom).abs();
        let reach = (dx * dx + dy * dy + dz * dz).sqrt();
        side >= WIDE * self.width * reach
    }

    /// For each child of `quad` (in [`ORDER`]), whether some ray of the packet may pass below
    /// its top over its footprint as the per-ray test computes it: `false` only where that
    /// test fails for every ray of the packet.
    #[inline(always)]
    pub fn children(&self, q: &Quad) -> [bool; 4] {
        let bounds = |b: [f32; 3], i: usize, e: f64| {
            let (a, b) = (b[i] as f64, b[i + 1] as f64);
            (a.min(b) - self.grow_xy - e, a.max(b) + self.grow_xy - e)
        };
        let mut open = [false; 4];
        for (c, &(i, j)) in ORDER.iter().enumerate() {
            let x = bounds(q.x, i, self.apex.x);
            let y = bounds(q.y, j, self.apex.y);
            let z = (self.bottom - self.apex.z, q.top[c] as f64 + self.grow_z - self.apex.z);
            if z.1.is_nan() || z.0 > z.1 {
                // An empty child (outside the grid or over holes: its top is minus infinity).
                continue;
            }
            open[c] = self.normals.iter().all(|n| {
                // The column's corner farthest along the normal, relative to the apex.
                let corner = |n: f64, (lo, hi): (f64, f64)| if n > 0.0 { hi } else { lo };
                let (cx, cy, cz) = (corner(n.x, x), corner(n.y, y), corner(n.z, z));
                let reach = n.x * cx + n.y * cy + n.z * cz;
                let scale = (n.x * cx).abs() + (n.y * cy).abs() + (n.z * cz).abs();
                reach >= -1e-9 * scale
            });
        }
        open
    }
}
