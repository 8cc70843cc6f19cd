//! The resolve of a flight's frames (the channels the shading reads) sixteen pixels of a row
//! at a time in AVX-512 registers: each pixel's triangle corners and their colour and normal
//! gathered, interpolated at its barycentrics and normalized with the same IEEE operations in
//! the same order as the pixel-by-pixel resolve (`triangle_resolve.rs`), so the G-buffer is
//! the same bit for bit. A pixel whose smooth normal does not face its ray (the geometric
//! normal stands in) is left to the pixel-by-pixel resolve.
#![allow(unsafe_code)]

use crate::gbuffer::GBufferRows;
use crate::triangle_resolve::{DrawnMeshes, RayParts};
use crate::GBufferPixel;
use relief_mesh::RasterTarget;
use std::arch::x86_64::*;

/// Pixels a run resolves at once.
pub(crate) const LANES: usize = 16;

/// Whether the lanes can resolve pixels of `drawn`: six attributes a vertex (colour, then
/// normal) in every mesh, and indices small enough for 32-bit gathers.
pub(crate) fn can_resolve(drawn: &DrawnMeshes) -> bool {
    drawn.meshes.iter().all(|m| {
        m.attributes_per_vertex() == 6
            && m.triangles().len() < (i32::MAX / 3) as usize
            && m.attributes().len() < i32::MAX as usize
    })
}

/// Resolves the `n` (at most [`LANES`]) pixels from column `i` of image row `j` (target index
/// `index`) into `strip` from its pixel `k`: distance, normal and colour. Returns the lanes
/// left to the pixel-by-pixel resolve (bit `l`: pixel `i + l`).
///
/// # Safety
/// The processor runs AVX-512 F, VL, DQ and BW (`LaneWidth::Avx512`); `drawn` passes
/// [`can_resolve`]; `target` keeps barycentrics; the pixels lie in the target and the strip.
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw")]
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn resolve_run(
    target: &RasterTarget,
    drawn: &DrawnMeshes,
    rays: &RayParts,
    [i, j]: [usize; 2],
    index: usize,
    n: usize,
    strip: &mut GBufferRows,
    k: usize,
) -> u16 {
    let valid: u16 = if n >= LANES { u16::MAX } else { (1u16 << n) - 1 };
    // SAFETY (loads and gathers below): masked to the `n` pixels of the target; corner and
    // attribute indices come from the meshes, whose sizes `can_resolve` bounded.
    let ids =
        unsafe { _mm512_maskz_loadu_epi32(valid, target.triangle.as_ptr().add(index).cast()) };
    let hit =
        valid & _mm512_cmpneq_epu32_mask(ids, _mm512_set1_epi32(RasterTarget::NO_TRIANGLE as i32));
    let mut lanes = Lanes::default();
    if hit != 0 {
        lanes = unsafe { interpolate(target, drawn, rays, [i, j], index, ids, hit) };
    }
    let resolved = hit & lanes.normal_ok;
    let distance = &mut strip.distance[k..k + n];
    let normal = &mut strip.normal[k..k + n];
    let material = &mut strip.material[k..k + n];
    for l in 0..n {
        if resolved >> l & 1 == 1 {
            distance[l] = target.distance[index + l];
            normal[l] = [lanes.normal[0][l], lanes.normal[1][l], lanes.normal[2][l]];
            material[l] = [lanes.colour[0][l], lanes.colour[1][l], lanes.colour[2][l], 1.0];
        } else if hit >> l & 1 == 0 {
            distance[l] = GBufferPixel::MISS.distance;
            normal[l] = GBufferPixel::MISS.normal;
            material[l] = GBufferPixel::MISS.material;
        }
    }
    hit & !lanes.normal_ok
}

/// What the lanes found: each lane's unit normal and colour, and which normals are good.
#[derive(Default)]
struct Lanes {
    normal: [[f32; LANES]; 3],
    colour: [[f32; LANES]; 3],
    normal_ok: u16,
}

/// The lanes `hit` of ids `ids`: their colours and smooth normals interpolated, and the
/// normals that face their rays, normalized.
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw")]
unsafe fn interpolate(
    target: &RasterTarget,
    drawn: &DrawnMeshes,
    rays: &RayParts,
    [i, j]: [usize; 2],
    index: usize,
    ids: __m512i,
    hit: u16,
) -> Lanes {
    // The barycentrics, pairs (b1, b2) of eight pixels a register, split into b1s and b2s.
    let pairs = |first: usize, lanes: u16| unsafe {
        let mask = spread(lanes);
        _mm512_maskz_loadu_ps(mask, target.barycentrics.as_ptr().add(index + first).cast())
    };
    let (low, high) = (pairs(0, hit & 0xff), pairs(8, hit >> 8));
    let evens = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
    let odds = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
    let b1 = _mm512_permutex2var_ps(low, evens, high);
    let b2 = _mm512_permutex2var_ps(low, odds, high);
    let zero = _mm512_setzero_ps();
    let b0 = _mm512_max_ps(_mm512_sub_ps(_mm512_sub_ps(_mm512_set1_ps(1.0), b1), b2), zero);

    // Each corner's six attributes, gathered mesh by mesh.
    let mut corners = [[zero; 6]; 3];
    for (m, mesh) in drawn.meshes.iter().enumerate() {
        let first = _mm512_set1_epi32(drawn.first_ids[m] as i32);
        let mut lanes = hit & _mm512_cmpge_epu32_mask(ids, first);
        if let Some(&next) = drawn.first_ids.get(m + 1) {
            lanes &= _mm512_cmplt_epu32_mask(ids, _mm512_set1_epi32(next as i32));
        }
        if lanes == 0 {
            continue;
        }
        let local = _mm512_sub_epi32(ids, first);
        let at = _mm512_mullo_epi32(local, _mm512_set1_epi32(3));
        let triangles = mesh.triangles().as_ptr().cast::<i32>();
        let attributes = mesh.attributes().as_ptr();
        for (c, corner) in corners.iter_mut().enumerate() {
            let offset = _mm512_add_epi32(at, _mm512_set1_epi32(c as i32));
            let vertex = unsafe {
                _mm512_mask_i32gather_epi32::<4>(_mm512_setzero_si512(), lanes, offset, triangles)
            };
            let base = _mm512_mullo_epi32(vertex, _mm512_set1_epi32(6));
            for (a, value) in corner.iter_mut().enumerate() {
                let offset = _mm512_add_epi32(base, _mm512_set1_epi32(a as i32));
                *value =
                    unsafe { _mm512_mask_i32gather_ps::<4>(*value, lanes, offset, attributes) };
            }
        }
    }
    // `b0 c0 + b1 c1 + b2 c2`, left to right.
    let value: [__m512; 6] = std::array::from_fn(|a| {
        _mm512_add_ps(
            _mm512_add_ps(_mm512_mul_ps(b0, corners[0][a]), _mm512_mul_ps(b1, corners[1][a])),
            _mm512_mul_ps(b2, corners[2][a]),
        )
    });
    let smooth = [value[3], value[4], value[5]];
    let length = _mm512_sqrt_ps(_mm512_add_ps(
        _mm512_add_ps(_mm512_mul_ps(smooth[0], smooth[0]), _mm512_mul_ps(smooth[1], smooth[1])),
        _mm512_mul_ps(smooth[2], smooth[2]),
    ));
    let mut normal_ok = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(length, zero)
        & _mm512_cmp_ps_mask::<_CMP_LT_OQ>(length, _mm512_set1_ps(f32::INFINITY));
    // The facing in f64, eight lanes a register: the ray `forward + across + up`.
    for half in 0..2 {
        let along: [__m512d; 3] = std::array::from_fn(|c| {
            let forward = _mm512_set1_pd(rays.forward[c]);
            if rays.perspective {
                let across = unsafe { _mm512_loadu_pd(rays.across[c].as_ptr().add(i + 8 * half)) };
                _mm512_add_pd(_mm512_add_pd(forward, across), _mm512_set1_pd(rays.up[c][j]))
            } else {
                forward
            }
        });
        let wide = |v: __m512| -> __m512d {
            let part = if half == 0 {
                _mm512_castps512_ps256(v)
            } else {
                _mm256_castpd_ps(_mm512_extractf64x4_pd::<1>(_mm512_castps_pd(v)))
            };
            _mm512_cvtps_pd(part)
        };
        let facing = _mm512_add_pd(
            _mm512_add_pd(
                _mm512_mul_pd(wide(smooth[0]), along[0]),
                _mm512_mul_pd(wide(smooth[1]), along[1]),
            ),
            _mm512_mul_pd(wide(smooth[2]), along[2]),
        );
        let toward = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(facing, _mm512_setzero_pd()) as u16;
        normal_ok &= !(0xffu16 << (8 * half)) | (toward << (8 * half));
    }
    let inverse = _mm512_div_ps(_mm512_set1_ps(1.0), length);
    let mut lanes = Lanes { normal_ok, ..Lanes::default() };
    for c in 0..3 {
        let normal = _mm512_mul_ps(smooth[c], inverse);
        // SAFETY: each array holds sixteen f32.
        unsafe {
            _mm512_storeu_ps(lanes.normal[c].as_mut_ptr(), normal);
            _mm512_storeu_ps(lanes.colour[c].as_mut_ptr(), value[c]);
        }
    }
    lanes
}

/// Eight lanes' mask, each bit doubled (for the pairs of floats of eight lanes).
#[inline(always)]
fn spread(lanes: u16) -> u16 {
    (0..8).filter(|l| lanes >> l & 1 == 1).fold(0, |m, l| m | 0b11 << (2 * l))
}
