//! The conservative `f32` tests of a group of [`LANES`] rays against the four children of a
//! node or against one cell, in portable code; `avx2.rs` has the same tests in AVX2
//! registers.

use super::ray_packet::{CellBox, Plane, Quad, RayPacket, LANES, ORDER};

/// The tests the packet traversal asks of a group of [`LANES`] rays of a packet.
///
/// Both report bit masks over the group's lanes of the rays among `active` that may meet the
/// solid: they never leave out a ray that does (see [`RayPacket`] for the margins), and the
/// exact cell test decides. Each counts one step for every active ray.
pub(crate) trait Kernel {
    /// For each child of `quad` (in [`ORDER`]), the rays of group `g` that may pass below its
    /// top over its footprint.
    fn children(packet: &mut RayPacket, g: usize, quad: &Quad, active: u8) -> [u8; 4];

    /// The rays of group `g` that may pass below either of the two `planes` of the
    /// `triangles` cell `cell` whose lower corner is `corner`, within `slack[i]` of plane `i`.
    fn below_planes(
        packet: &mut RayPacket,
        g: usize,
        cell: &CellBox,
        corner: (f32, f32),
        planes: &[Plane; 2],
        slack: [f32; 2],
        active: u8,
    ) -> u8;
}

/// The tests lane by lane, for processors without AVX2.
pub(crate) struct Portable;

/// The lowered height of ray `k` at `t`.
#[inline(always)]
fn z_at(p: &RayPacket, k: usize, t: f32) -> f32 {
    p.dz.0[k] * t + p.z_low.0[k]
}

/// Where ray `k` enters and leaves the slab between the entry boundary `near` and the exit
/// boundary `far` along x, clamped to the ray's part in the box.
#[inline(always)]
fn span_x(p: &RayPacket, k: usize, near: f32, far: f32) -> (f32, f32) {
    let inv = p.inv_x.0[k];
    ((near * inv + p.enter_x.0[k]).max(0.0), (far * inv + p.leave_x.0[k]).min(p.t_end.0[k]))
}

/// As [`span_x`], along y (not clamped).
#[inline(always)]
fn span_y(p: &RayPacket, k: usize, near: f32, far: f32) -> (f32, f32) {
    let inv = p.inv_y.0[k];
    (near * inv + p.enter_y.0[k], far * inv + p.leave_y.0[k])
}

impl Kernel for Portable {
    #[inline(always)]
    fn children(p: &mut RayPacket, g: usize, q: &Quad, active: u8) -> [u8; 4] {
        let mut hits = [0u8; 4];
        for lane in (0..LANES).filter(|lane| active >> lane & 1 != 0) {
            let k = g * LANES + lane;
            p.steps.0[k] += 1;
            let x = [span_x(p, k, q.x[0], q.x[1]), span_x(p, k, q.x[1], q.x[2])];
            let y = [span_y(p, k, q.y[0], q.y[1]), span_y(p, k, q.y[1], q.y[2])];
            for (c, &(i, j)) in ORDER.iter().enumerate() {
                let (t_in, t_out) = (x[i].0.max(y[j].0), x[i].1.min(y[j].1));
                if t_in <= t_out && z_at(p, k, t_in).min(z_at(p, k, t_out)) <= q.top[c] {
                    hits[c] |= 1 << lane;
                }
            }
        }
        hits
    }

    #[inline(always)]
    fn below_planes(
        p: &mut RayPacket,
        g: usize,
        b: &CellBox,
        corner: (f32, f32),
        planes: &[Plane; 2],
        slack: [f32; 2],
        active: u8,
    ) -> u8 {
        let mut hits = 0;
        for lane in (0..LANES).filter(|lane| active >> lane & 1 != 0) {
            let k = g * LANES + lane;
            let (x_in, x_out) = span_x(p, k, b.near_x, b.far_x);
            let (y_in, y_out) = span_y(p, k, b.near_y, b.far_y);
            let (t_in, t_out) = (x_in.max(y_in), x_out.min(y_out));
            let (u0, v0) = (p.ox.0[k] - corner.0, p.oy.0[k] - corner.1);
            let above = |plane: &Plane, t: f32| {
                let (u, v) = (p.dx.0[k] * t + u0, p.dy.0[k] * t + v0);
                z_at(p, k, t) - (plane.pu * u + (plane.pv * v + plane.p0))
            };
            let below = planes
                .iter()
                .zip(slack)
                .any(|(plane, s)| above(plane, t_in).min(above(plane, t_out)) <= s);
            if below {
                hits |= 1 << lane;
            }
        }
        hits
    }
}
