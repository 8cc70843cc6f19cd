//! The kernel's tests on eight rays at once in AVX2 registers (x86-64 with AVX2 and FMA).

use super::kernel::Kernel;
use super::ray_packet::{CellBox, Lanes, Plane, Quad, RayPacket, LANES, ORDER};
use std::arch::x86_64::*;

/// The [`Kernel`] in AVX2 and FMA instructions.
///
/// Only code compiled with those features may use it: `packet::trace` instantiates the
/// traversal with it inside a `#[target_feature(enable = "avx2,fma")]` function, which it
/// calls only after detecting both features at run time.
pub(crate) struct Avx2;

/// Group `g` of `lanes` (the `Lanes` alignment makes every group 32-byte aligned).
///
/// # Safety
/// The processor must support AVX2 and FMA (the caller runs under
/// `#[target_feature(enable = "avx2,fma")]`, entered after detecting both), and `g` must be
/// one of the groups of `lanes`: `(g + 1) * LANES <= lanes.0.len()`.
#[inline(always)]
unsafe fn load(lanes: &Lanes, g: usize) -> __m256 {
    _mm256_load_ps(lanes.0.as_ptr().add(g * LANES))
}

/// `boundary * inv + offset` for every lane.
///
/// # Safety
/// The processor must support AVX2 and FMA (the caller runs under
/// `#[target_feature(enable = "avx2,fma")]`, entered after detecting both).
#[inline(always)]
unsafe fn cross(boundary: f32, inv: __m256, offset: __m256) -> __m256 {
    _mm256_fmadd_ps(_mm256_set1_ps(boundary), inv, offset)
}

/// The lanes whose ray is inside the footprint for a while (`t_in <= t_out`) and there may
/// pass below `top`.
///
/// # Safety
/// The processor must support AVX2 and FMA (the caller runs under
/// `#[target_feature(enable = "avx2,fma")]`, entered after detecting both), and `g` must be
/// one of the groups of the packet's lanes.
#[inline(always)]
unsafe fn meets(p: &RayPacket, g: usize, t_in: __m256, t_out: __m256, top: f32) -> __m256 {
    let (dz, z_low) = (load(&p.dz, g), load(&p.z_low, g));
    let z_in = _mm256_fmadd_ps(dz, t_in, z_low);
    let z_out = _mm256_fmadd_ps(dz, t_out, z_low);
    _mm256_and_ps(
        _mm256_cmp_ps::<_CMP_LE_OQ>(t_in, t_out),
        _mm256_cmp_ps::<_CMP_LE_OQ>(_mm256_min_ps(z_in, z_out), _mm256_set1_ps(top)),
    )
}

/// The plane's height at local coordinates (u, v).
///
/// # Safety
/// The processor must support AVX2 and FMA (the caller runs under
/// `#[target_feature(enable = "avx2,fma")]`, entered after detecting both).
#[inline(always)]
unsafe fn plane_at(plane: &Plane, u: __m256, v: __m256) -> __m256 {
    let inner = _mm256_fmadd_ps(_mm256_set1_ps(plane.pv), v, _mm256_set1_ps(plane.p0));
    _mm256_fmadd_ps(_mm256_set1_ps(plane.pu), u, inner)
}

/// Adds one step to every active lane of group `g`.
///
/// # Safety
/// The processor must support AVX2 and FMA (the caller runs under
/// `#[target_feature(enable = "avx2,fma")]`, entered after detecting both), and `g` must be
/// one of the groups of the packet's lanes.
#[inline(always)]
unsafe fn count_steps(p: &mut RayPacket, g: usize, active: u8) {
    let bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    let on = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(active as i32), bits), bits);
    let steps = p.steps.0.as_mut_ptr().add(g * LANES) as *mut __m256i;
    _mm256_store_si256(steps, _mm256_sub_epi32(_mm256_load_si256(steps), on));
}

impl Kernel for Avx2 {
    #[inline(always)]
    fn children(p: &mut RayPacket, g: usize, q: &Quad, active: u8) -> [u8; 4] {
        // SAFETY: see the type's documentation; every load stays inside the packet's lanes.
        unsafe {
            count_steps(p, g, active);
            let (inv_x, enter_x, leave_x) =
                (load(&p.inv_x, g), load(&p.enter_x, g), load(&p.leave_x, g));
            let (inv_y, enter_y, leave_y) =
                (load(&p.inv_y, g), load(&p.enter_y, g), load(&p.leave_y, g));
            let (zero, t_end) = (_mm256_setzero_ps(), load(&p.t_end, g));
            let x_in = [
                _mm256_max_ps(cross(q.x[0], inv_x, enter_x), zero),
                _mm256_max_ps(cross(q.x[1], inv_x, enter_x), zero),
            ];
            let x_out = [
                _mm256_min_ps(cross(q.x[1], inv_x, leave_x), t_end),
                _mm256_min_ps(cross(q.x[2], inv_x, leave_x), t_end),
            ];
            let y_in = [cross(q.y[0], inv_y, enter_y), cross(q.y[1], inv_y, enter_y)];
            let y_out = [cross(q.y[1], inv_y, leave_y), cross(q.y[2], inv_y, leave_y)];
            let mut hits = [0u8; 4];
            for (c, &(i, j)) in ORDER.iter().enumerate() {
                let t_in = _mm256_max_ps(x_in[i], y_in[j]);
                let t_out = _mm256_min_ps(x_out[i], y_out[j]);
                hits[c] = _mm256_movemask_ps(meets(p, g, t_in, t_out, q.top[c])) as u8 & active;
            }
            hits
        }
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
        // SAFETY: as in `children`.
        unsafe {
            let (inv_x, inv_y) = (load(&p.inv_x, g), load(&p.inv_y, g));
            let t_in = _mm256_max_ps(
                _mm256_max_ps(cross(b.near_x, inv_x, load(&p.enter_x, g)), _mm256_setzero_ps()),
                cross(b.near_y, inv_y, load(&p.enter_y, g)),
            );
            let t_out = _mm256_min_ps(
                _mm256_min_ps(cross(b.far_x, inv_x, load(&p.leave_x, g)), load(&p.t_end, g)),
                cross(b.far_y, inv_y, load(&p.leave_y, g)),
            );
            let (dz, z_low) = (load(&p.dz, g), load(&p.z_low, g));
            let (z_in, z_out) =
                (_mm256_fmadd_ps(dz, t_in, z_low), _mm256_fmadd_ps(dz, t_out, z_low));
            let u0 = _mm256_sub_ps(load(&p.ox, g), _mm256_set1_ps(corner.0));
            let v0 = _mm256_sub_ps(load(&p.oy, g), _mm256_set1_ps(corner.1));
            let (dx, dy) = (load(&p.dx, g), load(&p.dy, g));
            let (u_in, u_out) = (_mm256_fmadd_ps(dx, t_in, u0), _mm256_fmadd_ps(dx, t_out, u0));
            let (v_in, v_out) = (_mm256_fmadd_ps(dy, t_in, v0), _mm256_fmadd_ps(dy, t_out, v0));
            let mut below = _mm256_setzero_ps();
            for (plane, s) in planes.iter().zip(slack) {
                let above_in = _mm256_sub_ps(z_in, plane_at(plane, u_in, v_in));
                let above_out = _mm256_sub_ps(z_out, plane_at(plane, u_out, v_out));
                let low = _mm256_min_ps(above_in, above_out);
                below = _mm256_or_ps(below, _mm256_cmp_ps::<_CMP_LE_OQ>(low, _mm256_set1_ps(s)));
            }
            _mm256_movemask_ps(below) as u8 & active
        }
    }
}
