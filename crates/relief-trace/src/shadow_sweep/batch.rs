//! The walks of a batch of shadow rays, four at a time in AVX2 registers where the processor
//! has them.

use super::*;
use crate::cell_grid::triangle_planes;
use crate::packet::{prefetch, prefetch_address};

impl<T: Tracer> SunShadows<T> {
    /// [`SunShadows::walk`] of every ray of `rays` into `walked`.
    pub(super) fn walk_batch(&self, rays: &[Ray], walked: &mut [Walked], steps: &mut [u32]) {
        let d = self.cell_inv_dir;
        if !(self.fast_triangles && (d.x.is_finite() || d.y.is_finite())) {
            for ((ray, out), steps) in rays.iter().zip(walked.iter_mut()).zip(steps.iter_mut()) {
                *out = self.walk(ray, steps);
            }
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` holds only where the processor has AVX2 (see `with_block`).
            unsafe { self.walk_triangles_avx2(rays, walked, steps) };
            return;
        }
        for ((rays, walked), steps) in
            rays.chunks(LANES).zip(walked.chunks_mut(LANES)).zip(steps.chunks_mut(LANES))
        {
            let mut lanes = [None; LANES];
            for (lane, ray) in lanes.iter_mut().zip(rays) {
                *lane = self.start(ray);
            }
            self.walk_triangles_lanes(&lanes, walked, steps);
            for (out, (lane, ray)) in walked.iter_mut().zip(lanes.iter().zip(rays)) {
                if lane.is_none() {
                    *out = Walked::From(ray.t_min);
                }
            }
        }
    }

    /// [`SunShadows::walk_triangles`] of every ray of `rays`, [`LANES`] at a time in AVX2
    /// registers: the same operations in the same order (no fused multiply-adds), so the same
    /// decisions. A lane whose ray is decided (or has walked its cells) takes the next ray of
    /// the batch, so that the lanes stay busy until the batch runs out; two groups of lanes
    /// advance in turn, so that the processor overlaps one's reads with the other's work.
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn walk_triangles_avx2(&self, rays: &[Ray], walked: &mut [Walked], steps: &mut [u32]) {
        use std::arch::x86_64::*;
        let (cells_x, cells_y) = (self.grid.cells_x() as i32, self.grid.cells_y() as i32);
        let (w, samples) = (self.field.width() as i32, self.field.samples());
        let shift = _mm_cvtsi32_si128(self.block_shift.unwrap_or(0) as i32);
        let (stride_x, stride_y) =
            (_mm_set1_epi32(self.stride_x as i32), _mm_set1_epi32(self.stride_y as i32));
        let margin = _mm256_set1_pd(self.margin);
        let infinity = _mm256_set1_pd(f64::INFINITY);
        let zero = _mm256_setzero_pd();
        let (last_x, last_y) = (_mm_set1_epi32(cells_x - 1), _mm_set1_epi32(cells_y - 1));
        // 64-bit and 32-bit lane masks from four bits.
        let bits64 = _mm256_setr_epi64x(1, 2, 4, 8);
        let bits32 = _mm_setr_epi32(1, 2, 4, 8);
        let mask64 = |m: i32| {
            let v = _mm256_and_si256(_mm256_set1_epi64x(m as i64), bits64);
            _mm256_castsi256_pd(_mm256_cmpeq_epi64(v, bits64))
        };
        let mask32 = |m: i32| _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(m), bits32), bits32);
        let load = |v: &[f64; 4]| _mm256_loadu_pd(v.as_ptr());
        let store = |v: &mut [f64; 4], x: __m256d| _mm256_storeu_pd(v.as_mut_ptr(), x);
        // Every ray has the sun's direction: in cell space as `start` maps it, its reciprocal.
        let d = self.grid.to_cell_space_dir_only(&Ray::new(DVec3::ZERO, self.towards_sun)).dir;
        let inv = self.cell_inv_dir;
        // From a cell to the one AHEAD steps diagonally towards the sun, in samples.
        let toward = |d: f64| (d > 0.0) as i32 - (d < 0.0) as i32;
        let look_ahead = AHEAD * (toward(d.x) + toward(d.y) * w);
        let mut next = 0;
        // Free lanes take the next rays that start over the grid.
        let mut refill = |g: &mut LaneWalks, walked: &mut [Walked]| {
            for k in 0..LANES {
                while g.active >> k & 1 == 0 && next < rays.len() {
                    let (i, ray) = (next, &rays[next]);
                    next += 1;
                    let Some(start @ (r, t0, (cx, cy))) = self.start(ray) else {
                        walked[i] = Walked::From(ray.t_min);
                        continue;
                    };
                    if self.walk == 0 {
                        walked[i] = Walked::From(t0);
                        continue;
                    }
                    let p = r.origin;
                    (g.origin[0][k], g.origin[1][k], g.origin[2][k]) = (p.x, p.y, p.z);
                    g.at[0][k] = t0;
                    (g.at[1][k], g.at[2][k], g.at[3][k]) =
                        (p.x + t0 * d.x, p.y + t0 * d.y, p.z + t0 * d.z);
                    (g.cell[0][k], g.cell[1][k]) = (cx as i32, cy as i32);
                    (g.ray[k], g.start[k], g.steps[k]) = (i, Some(start), 0);
                    g.active |= 1 << k;
                }
            }
        };
        // One cell of every active lane's walk.
        let step = |g: &mut LaneWalks, walked: &mut [Walked], steps: &mut [u32]| {
            let mut active = g.active;
            if active == 0 {
                return;
            }
            for k in (0..LANES).filter(|k| active >> k & 1 != 0) {
                steps[g.ray[k]] += 1;
                g.steps[k] += 1;
            }
            let (ox, oy, oz) = (load(&g.origin[0]), load(&g.origin[1]), load(&g.origin[2]));
            let (t_a, xa, ya, za) =
                (load(&g.at[0]), load(&g.at[1]), load(&g.at[2]), load(&g.at[3]));
            let cx = _mm_loadu_si128(g.cell[0].as_ptr() as *const __m128i);
            let cy = _mm_loadu_si128(g.cell[1].as_ptr() as *const __m128i);
            let (dx, dy, dz) = (_mm256_set1_pd(d.x), _mm256_set1_pd(d.y), _mm256_set1_pd(d.z));
            // The bound at each cell's entry point.
            let block = _mm_add_epi32(
                _mm_mullo_epi32(_mm_srl_epi32(cy, shift), stride_y),
                _mm_mullo_epi32(_mm_srl_epi32(cx, shift), stride_x),
            );
            let bound = _mm256_cvtps_pd(_mm_i32gather_ps::<4>(self.bound.as_ptr(), block));
            let lit =
                _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(za, margin), bound))
                    & active;
            // Where each ray leaves its cell.
            let (fx, fy) = (_mm256_cvtepi32_pd(cx), _mm256_cvtepi32_pd(cy));
            let tx = if d.x != 0.0 {
                let next_x =
                    _mm256_cvtepi32_pd(_mm_add_epi32(cx, _mm_set1_epi32((d.x > 0.0) as i32)));
                _mm256_mul_pd(_mm256_sub_pd(next_x, ox), _mm256_set1_pd(inv.x))
            } else {
                infinity
            };
            let ty = if d.y != 0.0 {
                let next_y =
                    _mm256_cvtepi32_pd(_mm_add_epi32(cy, _mm_set1_epi32((d.y > 0.0) as i32)));
                _mm256_mul_pd(_mm256_sub_pd(next_y, oy), _mm256_set1_pd(inv.y))
            } else {
                infinity
            };
            let t_b = _mm256_min_pd(tx, ty);
            let xb = _mm256_add_pd(ox, _mm256_mul_pd(t_b, dx));
            let yb = _mm256_add_pd(oy, _mm256_mul_pd(t_b, dy));
            let zb = _mm256_add_pd(oz, _mm256_mul_pd(t_b, dz));
            // The cell's corners and its two planes.
            let i = _mm_add_epi32(cx, _mm_mullo_epi32(cy, _mm_set1_epi32(w)));
            let base = samples.as_ptr();
            let gather = |offset: i32| {
                let index = _mm_add_epi32(i, _mm_set1_epi32(offset));
                _mm256_cvtps_pd(_mm_i32gather_ps::<4>(base, index))
            };
            let (a, b, c, e) = (gather(0), gather(1), gather(w), gather(w + 1));
            let ad = _mm256_cmp_pd::<_CMP_LE_OQ>(_mm256_add_pd(a, e), _mm256_add_pd(b, c));
            let (c_a, e_b) = (_mm256_sub_pd(c, a), _mm256_sub_pd(e, b));
            let planes = [
                (a, _mm256_sub_pd(b, a), _mm256_blendv_pd(c_a, e_b, ad)),
                (
                    _mm256_blendv_pd(_mm256_sub_pd(_mm256_add_pd(b, c), e), a, ad),
                    _mm256_sub_pd(e, c),
                    _mm256_blendv_pd(e_b, c_a, ad),
                ),
            ];
            let (ua, va) = (_mm256_sub_pd(xa, fx), _mm256_sub_pd(ya, fy));
            let (ub, vb) = (_mm256_sub_pd(xb, fx), _mm256_sub_pd(yb, fy));
            let mut above = _mm256_cmp_pd::<_CMP_EQ_OQ>(zero, zero);
            for (p0, pu, pv) in planes {
                let at_a =
                    _mm256_add_pd(_mm256_add_pd(p0, _mm256_mul_pd(pu, ua)), _mm256_mul_pd(pv, va));
                let at_b =
                    _mm256_add_pd(_mm256_add_pd(p0, _mm256_mul_pd(pu, ub)), _mm256_mul_pd(pv, vb));
                above = _mm256_and_pd(
                    above,
                    _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(za, at_a), margin),
                );
                above = _mm256_and_pd(
                    above,
                    _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(zb, at_b), margin),
                );
            }
            let above = _mm256_movemask_pd(above);
            let failed = active & !lit & !above;
            for k in (0..LANES).filter(|k| lit >> k & 1 != 0) {
                walked[g.ray[k]] = Walked::Lit;
            }
            if failed != 0 {
                let (mut ta_out, mut tb_out) = ([0.0f64; 4], [0.0f64; 4]);
                store(&mut ta_out, t_a);
                store(&mut tb_out, t_b);
                for k in (0..LANES).filter(|k| failed >> k & 1 != 0) {
                    let r = &g.start[k].as_ref().expect("an active lane has a ray").0;
                    let here = (g.cell[0][k] as usize, g.cell[1][k] as usize);
                    walked[g.ray[k]] = if self.inside(samples, here, r, ta_out[k], tb_out[k]) {
                        Walked::Occluded
                    } else {
                        Walked::From(ta_out[k])
                    };
                }
            }
            let going = active & !lit & above;
            // Step to the next cell; leaving the grid with every cell cleared proves the ray.
            let step_x = _mm256_set1_pd(if d.x > 0.0 { 1.0 } else { -1.0 });
            let step_y = _mm256_set1_pd(if d.y > 0.0 { 1.0 } else { -1.0 });
            let sx = _mm256_cvtpd_epi32(_mm256_blendv_pd(
                zero,
                step_x,
                _mm256_cmp_pd::<_CMP_EQ_OQ>(tx, t_b),
            ));
            let sy = _mm256_cvtpd_epi32(_mm256_blendv_pd(
                zero,
                step_y,
                _mm256_cmp_pd::<_CMP_EQ_OQ>(ty, t_b),
            ));
            let (nx, ny) = (_mm_add_epi32(cx, sx), _mm_add_epi32(cy, sy));
            let outside = _mm_or_si128(
                _mm_or_si128(_mm_cmplt_epi32(nx, _mm_setzero_si128()), _mm_cmpgt_epi32(nx, last_x)),
                _mm_or_si128(_mm_cmplt_epi32(ny, _mm_setzero_si128()), _mm_cmpgt_epi32(ny, last_y)),
            );
            let left = _mm_movemask_ps(_mm_castsi128_ps(outside)) & going;
            for k in (0..LANES).filter(|k| left >> k & 1 != 0) {
                walked[g.ray[k]] = Walked::Lit;
            }
            let moving = going & !left;
            let (m64, m32) = (mask64(moving), mask32(moving));
            if moving != 0 {
                // The two rows of the cell a few steps ahead of each ray that moves on.
                let mut index = [0i32; 4];
                _mm_storeu_si128(index.as_mut_ptr() as *mut __m128i, i);
                for k in (0..LANES).filter(|k| moving >> k & 1 != 0) {
                    let ahead = samples.as_ptr().wrapping_offset((index[k] + look_ahead) as isize);
                    prefetch_address(ahead);
                    prefetch_address(ahead.wrapping_offset(w as isize));
                }
            }
            _mm_storeu_si128(g.cell[0].as_mut_ptr() as *mut __m128i, _mm_blendv_epi8(cx, nx, m32));
            _mm_storeu_si128(g.cell[1].as_mut_ptr() as *mut __m128i, _mm_blendv_epi8(cy, ny, m32));
            store(&mut g.at[0], _mm256_blendv_pd(t_a, t_b, m64));
            store(&mut g.at[1], _mm256_blendv_pd(xa, xb, m64));
            store(&mut g.at[2], _mm256_blendv_pd(ya, yb, m64));
            store(&mut g.at[3], _mm256_blendv_pd(za, zb, m64));
            active = moving;
            // A ray that has walked its cells is traced from where it stopped.
            for k in 0..LANES {
                if active >> k & 1 != 0 && g.steps[k] == self.walk {
                    walked[g.ray[k]] = Walked::From(g.at[0][k]);
                    active &= !(1 << k);
                }
            }
            g.active = active;
        };
        let mut groups: [LaneWalks; GROUPS] = Default::default();
        loop {
            for g in groups.iter_mut() {
                refill(g, walked);
            }
            if groups.iter().all(|g| g.active == 0) {
                return;
            }
            for g in groups.iter_mut() {
                step(g, walked, steps);
            }
        }
    }

    /// [`SunShadows::walk_triangles`] of up to [`LANES`] rays (`None`: undecided) at once.
    #[inline]
    pub(super) fn walk_triangles_lanes(
        &self,
        lanes: &[Option<Start>; LANES],
        decided: &mut [Walked],
        steps: &mut [u32],
    ) {
        let (cells_x, cells_y) = (self.grid.cells_x(), self.grid.cells_y());
        let (w, samples, margin) = (self.field.width(), self.field.samples(), self.margin);
        let (Some(first), n) = (lanes.iter().flatten().next(), decided.len()) else {
            return;
        };
        // Every ray has the sun's direction.
        let (d, inv) = (first.0.dir, first.0.inv_dir);
        let (up_x, up_y) = ((d.x > 0.0) as usize, (d.y > 0.0) as usize);
        let step_x = if d.x > 0.0 { 1 } else { usize::MAX };
        let step_y = if d.y > 0.0 { 1 } else { usize::MAX };
        let leave = |c: usize, up: usize, o: f64, d: f64, inv: f64| {
            if d != 0.0 {
                ((c + up) as f64 - o) * inv
            } else {
                f64::INFINITY
            }
        };
        let mut origin = [DVec3::ZERO; LANES];
        let mut at = [[0.0f64; 4]; LANES];
        let mut cell = [(0usize, 0usize); LANES];
        let mut active = [false; LANES];
        for k in 0..n {
            if let Some((r, t0, c)) = &lanes[k] {
                decided[k] = Walked::From(*t0);
                let o = r.origin;
                origin[k] = o;
                at[k] = [*t0, o.x + t0 * d.x, o.y + t0 * d.y, o.z + t0 * d.z];
                cell[k] = *c;
                active[k] = true;
            }
        }
        for _ in 0..self.walk {
            if !active.iter().any(|&a| a) {
                return;
            }
            for k in 0..n {
                if !active[k] {
                    continue;
                }
                steps[k] += 1;
                let (o, (cx, cy)) = (origin[k], cell[k]);
                let [t_a, xa, ya, za] = at[k];
                if za - margin > self.bound_at(cx, cy) as f64 {
                    (decided[k], active[k]) = (Walked::Lit, false);
                    continue;
                }
                let (tx, ty) = (leave(cx, up_x, o.x, d.x, inv.x), leave(cy, up_y, o.y, d.y, inv.y));
                let t_b = tx.min(ty);
                let (xb, yb, zb) = (o.x + t_b * d.x, o.y + t_b * d.y, o.z + t_b * d.z);
                let planes = triangle_planes(samples, w, cx, cy);
                let (ua, va, ub, vb) =
                    (xa - cx as f64, ya - cy as f64, xb - cx as f64, yb - cy as f64);
                let mut above = true;
                for (p0, pu, pv) in planes {
                    above &= (za - (p0 + pu * ua + pv * va) > margin)
                        & (zb - (p0 + pu * ub + pv * vb) > margin);
                }
                if !above {
                    let r = &lanes[k].as_ref().expect("an active lane has a ray").0;
                    decided[k] = if self.inside(samples, (cx, cy), r, t_a, t_b) {
                        Walked::Occluded
                    } else {
                        Walked::From(t_a)
                    };
                    active[k] = false;
                    continue;
                }
                let (nx, ny) = (
                    if tx == t_b { cx.wrapping_add(step_x) } else { cx },
                    if ty == t_b { cy.wrapping_add(step_y) } else { cy },
                );
                if nx >= cells_x || ny >= cells_y {
                    (decided[k], active[k]) = (Walked::Lit, false);
                    continue;
                }
                cell[k] = (nx, ny);
                at[k] = [t_b, xb, yb, zb];
                decided[k] = Walked::From(t_b);
            }
        }
    }

    /// Whether the rays start so close together (more than [`DENSE_RAYS_PER_CELL`] a cell
    /// over the box of their starting points) that the wrapped tracer's batch, which shares
    /// its work between neighbouring rays, traces them faster than the walks decide them.
    pub(super) fn dense(&self, rays: &[Ray]) -> bool {
        if rays.len() < 2 {
            return false;
        }
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for ray in rays {
            let p = ray.at(ray.t_min);
            (lo, hi) = (lo.min(p), hi.max(p));
        }
        let cells = (hi - lo) * self.field.geometry().grid_scale();
        let area = (cells.x.abs() + 1.0) * (cells.y.abs() + 1.0);
        rays.len() as f64 > DENSE_RAYS_PER_CELL * area
    }

    /// Asks the memory system early for what deciding `ray` will read: the samples of the
    /// cells under its first [`PREFETCH_CELLS`] steps along the sun's dominant axis and the
    /// bounds of their blocks.
    #[inline]
    pub(super) fn prefetch(&self, ray: &Ray) {
        if ray.dir != self.towards_sun || self.bound.is_empty() {
            return;
        }
        let r = self.grid.to_cell_space_dir_only(ray);
        let p = r.origin + r.t_min * r.dir;
        let (cells_x, cells_y) = (self.grid.cells_x() as f64, self.grid.cells_y() as f64);
        if !(p.x >= 0.0 && p.x <= cells_x && p.y >= 0.0 && p.y <= cells_y) {
            return;
        }
        let major = if self.major_is_x { r.dir.x.abs() } else { r.dir.y.abs() };
        let (sx, sy) = (r.dir.x / major, r.dir.y / major);
        let (w, samples) = (self.field.width(), self.field.samples());
        let rows = match self.grid.surface() {
            Surface::Boxes => 1,
            Surface::Triangles => 2,
        };
        for s in 0..PREFETCH_CELLS {
            let x = (p.x + s as f64 * sx).clamp(0.0, cells_x - 1.0) as usize;
            let y = (p.y + s as f64 * sy).clamp(0.0, cells_y - 1.0) as usize;
            prefetch(&self.bound[self.bound_index(x, y)]);
            for row in y..y + rows {
                if let Some(sample) = samples.get(x + row * w) {
                    prefetch(sample);
                }
            }
        }
    }
}

/// Groups of lanes the AVX2 walk advances in turn (`relief bench`'s shadow rays on the fBm
/// views at 4096^2: 2 groups 4-5% faster than 1 on the three-quarter and top-down views, 4
/// groups 5% slower than 2).
const GROUPS: usize = 2;

/// How many cells ahead of a walking ray (diagonally, towards the sun) the AVX2 walk asks
/// the memory system for the samples (`relief bench`'s shadow rays: 3 about 3% faster than
/// none on the three-quarter and top-down views, 6 about as fast as none).
const AHEAD: i32 = 3;

/// The walks in progress in one group of [`LANES`] lanes, between cells: each lane's ray
/// (its index in the batch and its start), origin, where it enters its cell (`t`, x, y, z),
/// the cell, and the cells it has walked.
#[derive(Default)]
struct LaneWalks {
    ray: [usize; LANES],
    start: [Option<Start>; LANES],
    origin: [[f64; LANES]; 3],
    at: [[f64; LANES]; 4],
    cell: [[i32; LANES]; 2],
    steps: [u32; LANES],
    /// The lanes walking, a bit each.
    active: i32,
}
