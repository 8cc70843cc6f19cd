//! The hybrid renderer's far field: the cells it ray casts, searched at their levels of
//! precision inside their proxy boxes (the paper's section 3), or exactly from the nearest
//! proxy-box entry (relief's `--far exact`).

use super::PixelSource;
use crate::{ShadeError, Tile, TILE_SIZE};
use rayon::prelude::*;
use relief_core::{Aabb, Camera, DVec3, HeightField};
use relief_mesh::{IndexedMesh, RasterTarget, Rasterizer};
use relief_trace::hybrid::{
    lop_cast, project_box, CellChoice, HybridCells, HybridHeuristic, LopSteps, PixelRect,
};
use relief_trace::{Hit, Tracer};

/// One ray-cast cell of a frame.
#[derive(Debug, Clone, Copy)]
struct FarCell {
    index: usize,
    level: u8,
    steps: LopSteps,
    pixels: PixelRect,
    world_box: Aabb,
    /// Distance from the eye to the box's nearest point: the front-to-back order.
    near: f64,
}

/// The frame's ray-cast cells, front to back.
pub(super) struct FarCells {
    cells: Vec<FarCell>,
}

/// A pixel's far-field answer: its hit and what found it.
pub(super) type FarHit = Option<(Hit, PixelSource)>;

impl FarCells {
    /// The cells `choices` ray casts, with their pixels, sorted front to back.
    pub(super) fn new(
        cells: &HybridCells,
        heuristic: &HybridHeuristic,
        choices: &[CellChoice],
        camera: &Camera,
    ) -> Self {
        let (w, h) = (camera.width(), camera.height());
        let eye = camera.eye();
        let mut far: Vec<FarCell> = choices
            .iter()
            .enumerate()
            .filter_map(|(index, choice)| {
                let CellChoice::RayCast { level } = *choice else { return None };
                let world_box = cells.proxy_box(index)?;
                let pixels = project_box(camera, &world_box).pixels(w, h)?;
                let nearest = eye.clamp(world_box.min, world_box.max);
                let steps = heuristic.steps()[level as usize];
                Some(FarCell {
                    index,
                    level,
                    steps,
                    pixels,
                    world_box,
                    near: eye.distance(nearest),
                })
            })
            .collect();
        far.sort_by(|a, b| a.near.total_cmp(&b.near).then(a.index.cmp(&b.index)));
        FarCells { cells: far }
    }

    /// The paper's far field: in every strip of rows, each cell front to back casts the rays
    /// of its pixels with its level's steps ([`lop_cast`]) where its box's entry is nearer than
    /// what the pixel already holds (the rasterized depth, or an earlier cell's hit). Returns
    /// the number of rays cast.
    pub(super) fn cast_levels(
        &self,
        field: &HeightField,
        cells: &HybridCells,
        camera: &Camera,
        near: &RasterTarget,
        hits: &mut [FarHit],
    ) -> u64 {
        let width = camera.width() as usize;
        let strip = TILE_SIZE * width;
        hits.par_chunks_mut(strip)
            .enumerate()
            .map(|(s, hits)| {
                let (top, rows) = (s * TILE_SIZE, hits.len() / width);
                let mut best: Vec<f64> = near.distance[s * strip..s * strip + hits.len()]
                    .iter()
                    .map(|&d| d as f64)
                    .collect();
                let mut rays = 0;
                for cell in &self.cells {
                    let (j0, j1) = (cell.pixels.j0 as usize, cell.pixels.j1 as usize);
                    if j1 < top || j0 >= top + rows {
                        continue;
                    }
                    for j in j0.max(top)..=j1.min(top + rows - 1) {
                        for i in cell.pixels.i0 as usize..=cell.pixels.i1 as usize {
                            let k = i + (j - top) * width;
                            let ray = camera.ray(i as u32, j as u32);
                            let Some(clip) = cell.world_box.clip(&ray) else { continue };
                            if clip.t_enter >= best[k] {
                                continue;
                            }
                            rays += 1;
                            if let Some(hit) = lop_cast(field, cells, cell.index, &ray, cell.steps)
                            {
                                if hit.t < best[k] {
                                    best[k] = hit.t;
                                    hits[k] = Some((hit, PixelSource::RayCast(cell.level)));
                                }
                            }
                        }
                    }
                }
                rays
            })
            .sum()
    }

    /// The exact far field: the ray-cast cells' proxy boxes, each widened by a pixel, are
    /// rasterized for the nearest box entry `t0` per pixel; wherever `t0` is nearer than the
    /// rasterized near field, `tracer` searches `[t0, near depth]` exactly, tile by tile (its
    /// coherent batches). Pixels that no box covers and no mesh drew see the sky: every
    /// visible surface lies in some cell's box. Returns the number of rays traced.
    pub(super) fn cast_exact(
        &self,
        tracer: &dyn Tracer,
        rasterizer: &Rasterizer,
        camera: &Camera,
        near: &RasterTarget,
        hits: &mut [FarHit],
    ) -> Result<u64, ShadeError> {
        let width = camera.width() as usize;
        let (boxes, behind) = self.entry_mesh(camera);
        let mut entries = RasterTarget::for_camera(camera);
        if !behind {
            rasterizer
                .draw(camera, &boxes, 0, &mut entries)
                .map_err(|e| ShadeError::Limits(e.to_string()))?;
        }
        let strip = TILE_SIZE * width;
        let traced = hits
            .par_chunks_mut(strip)
            .enumerate()
            .map(|(s, hits)| {
                let (top, rows) = (s * TILE_SIZE, hits.len() / width);
                let mut traced = 0;
                let (mut rays, mut found, mut steps, mut at) =
                    (Vec::new(), Vec::new(), Vec::new(), Vec::new());
                for tile_x in (0..width).step_by(TILE_SIZE) {
                    let tile = Tile::new(tile_x, top, width, top + rows);
                    rays.clear();
                    at.clear();
                    let mut wanted = 0;
                    for (i, j) in tile.pixels() {
                        let index = i + j * width;
                        let end = near.distance[index] as f64;
                        // Widened by a relative margin over the f32 rounding of the entries.
                        let start = if behind {
                            0.0
                        } else {
                            entries.distance[index] as f64 * (1.0 - 1e-5)
                        };
                        let ray = camera.ray(i as u32, j as u32);
                        // The whole tile goes to the tracer, so its packets stay whole; a
                        // pixel with nothing to search gets an empty range.
                        if start.is_finite() && start < end {
                            wanted += 1;
                            rays.push(ray.with_range(start.max(0.0), end));
                        } else {
                            rays.push(ray.with_range(1.0, 0.0));
                        }
                        at.push(i + (j - top) * width);
                    }
                    if wanted == 0 {
                        continue;
                    }
                    found.clear();
                    found.resize(rays.len(), None);
                    steps.clear();
                    steps.resize(rays.len(), 0);
                    tracer.intersect_batch(&rays, &mut found, &mut steps);
                    traced += wanted;
                    for (&k, hit) in at.iter().zip(&found) {
                        if let Some(hit) = hit {
                            hits[k] = Some((*hit, PixelSource::Exact));
                        }
                    }
                }
                traced
            })
            .sum();
        Ok(traced)
    }

    /// The twelve triangles of every ray-cast cell's proxy box, wound outward (so that the
    /// culling rasterizer draws the faces a ray enters by), widened by the width of a
    /// pixel at its farthest corner (so that the rasterizer's sub-pixel snapping cannot lose a
    /// ray that grazes it), and whether a box reaches the eye's plane (then no rasterized
    /// entry bounds the rays: they are searched from their start).
    fn entry_mesh(&self, camera: &Camera) -> (IndexedMesh, bool) {
        let (eye, forward) = (camera.eye(), camera.forward());
        let mut positions = Vec::with_capacity(8 * self.cells.len());
        let mut triangles = Vec::with_capacity(12 * self.cells.len());
        let mut behind = false;
        for cell in &self.cells {
            let b = cell.world_box;
            let corner = |k: usize| {
                DVec3::new(
                    if k & 1 == 0 { b.min.x } else { b.max.x },
                    if k & 2 == 0 { b.min.y } else { b.max.y },
                    if k & 4 == 0 { b.min.z } else { b.max.z },
                )
            };
            let far = (0..8).map(|k| corner(k).distance(eye)).fold(0.0, f64::max);
            let margin = camera.pixel_footprint(far);
            let (lo, hi) = (b.min - DVec3::splat(margin), b.max + DVec3::splat(margin));
            let base = positions.len() as u32;
            for k in 0..8 {
                let p = DVec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                behind |= (p - eye).dot(forward) <= 0.0;
                positions.push(p);
            }
            for [a, b, c, d] in BOX_FACES {
                triangles.push([base + a, base + b, base + c]);
                triangles.push([base + a, base + c, base + d]);
            }
        }
        let mesh = IndexedMesh::new(positions, triangles).unwrap_or_default();
        (mesh, behind)
    }
}

/// The six faces of a box whose corner `k` has bit 0 for max x, bit 1 for max y, bit 2 for
/// max z, each as four corners around it.
const BOX_FACES: [[u32; 4]; 6] =
    [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
