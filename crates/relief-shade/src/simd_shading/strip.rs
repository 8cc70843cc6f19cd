//! A strip of the deferred pass in `f32` lanes: shadow rays traced tile by tile in `f64` as
//! the `f64` pass traces them, then every row lit by the kernel.

use relief_core::DVec3;

use super::ShadingKernel;
use crate::deferred::{trace_shadows, ShadingPass};
use crate::{shadow_ray, Albedo, RayBatch, ShadingNormals, Tile, TraceStats, TILE_SIZE};

/// Shades the image rows from `top` on (at most [`TILE_SIZE`], all in the pass's G-buffer)
/// into `out` with `kernel`, and counts the shadow rays.
///
/// The shadow rays are the `f64` pass's, bit for bit and in the same batches (each tile's
/// pixels in Morton order): from the point the pixel's `f64` camera ray reaches at the stored
/// distance, for pixels whose `f64` normal faces the sun. So shadows and the counts are the
/// same; the kernel does the rest of the arithmetic.
pub(crate) fn shade_strip_in_lanes(
    pass: &ShadingPass,
    kernel: &ShadingKernel,
    top: usize,
    out: &mut [[u8; 3]],
) -> TraceStats {
    let gbuffer = pass.gbuffer;
    let width = gbuffer.width;
    let rows = out.len() / width;
    let params = pass.params;
    let mut stats = TraceStats::default();
    let lights = params.sun.is_up() && params.sun.irradiance > 0.0;
    let mut visibility = vec![if lights && !params.shadows { 1.0f32 } else { 0.0 }; out.len()];
    if lights && params.shadows {
        let mut batch = RayBatch::default();
        let mut owners = Vec::new();
        for tile_x in (0..width).step_by(TILE_SIZE) {
            batch.clear();
            owners.clear();
            let tile = Tile::new(tile_x, top, width, top + rows);
            if pass.mask.is_some_and(|m| !m.any_in_tile(tile)) {
                continue;
            }
            for (i, j) in tile.pixels() {
                let Some((ray, distance, normal)) = drawn_hit(pass, kernel, i, j) else {
                    continue;
                };
                if normal.dot(pass.to_sun) > 0.0 {
                    batch.rays.push(shadow_ray(ray.at(distance), normal, distance, pass.to_sun));
                    owners.push(i + (j - top) * width);
                }
            }
            trace_shadows(&mut batch, pass.tracer, &owners, &mut visibility, &mut stats);
        }
    }
    let normals = shading_normals(pass, kernel, top, rows);
    for r in 0..rows {
        let k = pass.index(0, top + r);
        let colours = matches!(params.albedo, Albedo::GBufferColour { .. });
        let mut shade = |first: usize, n: usize| {
            let (g, pixels) = (k + first..k + first + n, r * width + first..r * width + first + n);
            let normal = match &normals {
                Some(normals) => &normals[pixels.clone()],
                None => &gbuffer.normal[g.clone()],
            };
            let colour = colours.then(|| &gbuffer.material[g.clone()]);
            let row = kernel.row_pixels(
                top + r,
                first,
                (&gbuffer.distance[g], normal),
                colour,
                &visibility[pixels.clone()],
            );
            kernel.shade_pixels(&row, &mut out[pixels]);
        };
        match pass.mask {
            None => shade(0, width),
            // Each run of marked pixels of the row.
            Some(mask) => {
                let mut i = 0;
                while i < width {
                    let first = i;
                    while i < width && mask.contains(i, top + r) {
                        i += 1;
                    }
                    if i > first {
                        shade(first, i - first);
                    }
                    i += 1;
                }
            }
        }
    }
    stats
}

/// The normals that light the `rows` image rows from `top` on, row-major, where they are not
/// the G-buffer's (smooth normals): each hit's [`ShadingNormals::at`] at the point the
/// pixel's `f64` camera ray reaches, as the `f64` pass finds it; zeros for a miss.
fn shading_normals(
    pass: &ShadingPass,
    kernel: &ShadingKernel,
    top: usize,
    rows: usize,
) -> Option<Vec<[f32; 3]>> {
    if matches!(pass.params.normals, ShadingNormals::Faceted) {
        return None;
    }
    let gbuffer = pass.gbuffer;
    let width = gbuffer.width;
    let mut normals = vec![[0.0f32; 3]; rows * width];
    for (r, row) in normals.chunks_mut(width).enumerate() {
        let j = top + r;
        if pass.mask.is_some_and(|m| !m.any_in_rows(j, 1)) {
            continue;
        }
        for (i, normal) in row.iter_mut().enumerate() {
            let Some((ray, distance, geometric)) = drawn_hit(pass, kernel, i, j) else {
                continue;
            };
            let shading = pass.params.normals.at(ray.at(distance), geometric, distance);
            *normal = shading.as_vec3().to_array();
        }
    }
    Some(normals)
}

/// What pixel (i, j) of the pass sees, if it is drawn and hits: its `f64` camera ray, the
/// stored distance and the unit geometric normal.
#[inline]
fn drawn_hit(
    pass: &ShadingPass,
    kernel: &ShadingKernel,
    i: usize,
    j: usize,
) -> Option<(relief_core::Ray, f64, DVec3)> {
    if pass.mask.is_some_and(|m| !m.contains(i, j)) {
        return None;
    }
    let k = pass.index(i, j);
    let distance = pass.gbuffer.distance[k] as f64;
    if !distance.is_finite() {
        return None;
    }
    let normal = DVec3::from(pass.gbuffer.normal[k].map(f64::from)).normalize_or_zero();
    let ray = pass.camera.ray_through(kernel.screen_x_f64[i], kernel.screen_y_f64[j]);
    Some((ray, distance, normal))
}
