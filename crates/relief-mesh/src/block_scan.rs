//! [`TriangleSetup::scan`] in AVX-512 registers: the pixels of the image's grid of 4 x 4
//! blocks, sixteen lanes (two registers of eight) an operation. Each lane computes what the
//! row-by-row scan computes for its pixel with the same IEEE operations in the same order (a
//! multiply, then an add: nothing fused), so it finds the same pixels with the same keys.
#![allow(unsafe_code)]

use crate::triangle_setup::{ScreenProjection, TriangleSetup, BLOCK_LANES, BLOCK_SIDE};
use std::arch::x86_64::*;

/// Calls `write(bx, by, keys)` for every block of the image's grid of 4 x 4 blocks that has a
/// pixel of `[x0, x1] x [y0, y1]` the triangle covers in front of the eye: `(bx, by)` is the
/// block's top-left pixel and `keys` its lanes' depth keys, row after row, NaN where a lane is
/// not covered. Returns the number of pixels covered.
#[target_feature(enable = "avx512f,avx512dq")]
pub(crate) fn scan_blocks(
    setup: &TriangleSetup,
    projection: &ScreenProjection,
    [x0, y0, x1, y1]: [usize; 4],
    mut write: impl FnMut(usize, usize, &[f64; BLOCK_LANES]),
) -> usize {
    let splat = _mm512_set1_pd;
    let [e0, e1, e2] = setup.edges;
    let across = [splat(e0[0]), splat(e1[0]), splat(e2[0])];
    let down = [splat(e0[1]), splat(e1[1]), splat(e2[1])];
    let constant = [splat(e0[2]), splat(e1[2]), splat(e2[2])];
    // Where a lane exactly on an edge is covered (top-left rule).
    let on_edge = setup.top_left.map(|t| if t { 0xff } else { 0 });
    let key_sign = splat(if projection.perspective { 1.0 } else { -1.0 });
    let (key_row, key_up, key_across) =
        (splat(setup.key_row), splat(setup.key_up), splat(setup.key_across));
    let (zero, half, infinity, nan) =
        (splat(0.0), splat(0.5), splat(f64::INFINITY), splat(f64::NAN));
    // A register holds two rows of a block: its lanes' columns, and rows in the block.
    let columns = _mm512_setr_pd(0.0, 1.0, 2.0, 3.0, 0.0, 1.0, 2.0, 3.0);
    let rows = [
        _mm512_setr_pd(0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0),
        _mm512_setr_pd(2.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0, 3.0),
    ];
    let mut written = 0;
    let mut by = y0 - y0 % BLOCK_SIDE;
    while by <= y1 {
        let top = splat(by as f64);
        let sy = &projection.sy[by..by + BLOCK_SIDE];
        let mut row_terms = [[zero; 3]; 2];
        let mut row_keys = [zero; 2];
        for half_block in 0..2 {
            // Exactly `j as f64 + 0.5`: the integers are small.
            let py = _mm512_add_pd(_mm512_add_pd(top, rows[half_block]), half);
            for k in 0..3 {
                row_terms[half_block][k] = _mm512_add_pd(_mm512_mul_pd(down[k], py), constant[k]);
            }
            let (a, b) = (sy[2 * half_block], sy[2 * half_block + 1]);
            let sy = _mm512_setr_pd(a, a, a, a, b, b, b, b);
            row_keys[half_block] = _mm512_add_pd(key_row, _mm512_mul_pd(sy, key_up));
        }
        // The block's rows inside the rectangle, four lanes a row.
        let mut inside_rows = 0u16;
        for r in 0..BLOCK_SIDE {
            if (y0..=y1).contains(&(by + r)) {
                inside_rows |= 0xf << (BLOCK_SIDE * r);
            }
        }
        let mut bx = x0 - x0 % BLOCK_SIDE;
        while bx <= x1 {
            let px = _mm512_add_pd(_mm512_add_pd(splat(bx as f64), columns), half);
            let sx = &projection.sx[bx..bx + BLOCK_SIDE];
            let sx = _mm512_setr_pd(sx[0], sx[1], sx[2], sx[3], sx[0], sx[1], sx[2], sx[3]);
            let column_keys = _mm512_mul_pd(sx, key_across);
            let mut inside_columns = 0u16;
            for c in 0..BLOCK_SIDE {
                if (x0..=x1).contains(&(bx + c)) {
                    inside_columns |= 0x1111 << c;
                }
            }
            let inside = inside_rows & inside_columns;
            let mut keys = [zero; 2];
            let mut covered = [0u8; 2];
            for half_block in 0..2 {
                let mut mask = (inside >> (8 * half_block)) as u8;
                for k in 0..3 {
                    let v = _mm512_add_pd(_mm512_mul_pd(across[k], px), row_terms[half_block][k]);
                    let positive = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(v, zero);
                    let on = _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(v, zero) & on_edge[k];
                    mask &= positive | on;
                }
                let key = _mm512_add_pd(row_keys[half_block], column_keys);
                let ahead = _mm512_mul_pd(key, key_sign);
                mask &= _mm512_cmp_pd_mask::<_CMP_GT_OQ>(ahead, zero)
                    & _mm512_cmp_pd_mask::<_CMP_LT_OQ>(ahead, infinity);
                keys[half_block] = _mm512_mask_blend_pd(mask, nan, key);
                covered[half_block] = mask;
            }
            let count = covered[0].count_ones() + covered[1].count_ones();
            if count != 0 {
                written += count as usize;
                let mut lanes = [0.0; BLOCK_LANES];
                // SAFETY: `lanes` holds sixteen f64, two registers of eight.
                unsafe {
                    _mm512_storeu_pd(lanes.as_mut_ptr(), keys[0]);
                    _mm512_storeu_pd(lanes.as_mut_ptr().add(8), keys[1]);
                }
                write(bx, by, &lanes);
            }
            bx += BLOCK_SIDE;
        }
        by += BLOCK_SIDE;
    }
    written
}
