//! The hybrid renderer's far field: the cells it ray casts, searched at their levels of
//! precision inside their proxy boxes (the paper's section 3), or exactly from the nearest
//! proxy-box entry (relief's `--far exact`).

use super::heuristic::{CellChoice, HybridHeuristic};
use super::projection::{project_box, PixelRect};
use crate::{Tile, TILE_SIZE};
use rayon::prelude::*;
use relief_core::{Aabb, Camera, HeightField, Ray};
use relief_mesh::RasterTarget;
use relief_trace::hybrid::{lop_cast, HybridCells, LopSteps};
use relief_trace::{Hit, Tracer};
use std::fmt;
use std::str::FromStr;

/// How the hybrid renderer casts the cells it does not rasterize.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum FarField {
    /// The paper's levels of precision: a linear then a binary search with the cell's level's
    /// steps inside its proxy box. Approximate (see the metrics of `relief compare`), and on a
    /// CPU slower than the exact far field (docs/hybrid.md).
    Lop,
    /// The exact tracer between the nearest proxy-box entry and the rasterized depth: the
    /// whole image then equals the exact tracer's. The default.
    #[default]
    Exact,
}

impl FarField {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            FarField::Lop => "lop",
            FarField::Exact => "exact",
        }
    }
}

impl fmt::Display for FarField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for FarField {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "lop" => Ok(FarField::Lop),
            "exact" => Ok(FarField::Exact),
            other => Err(format!("unknown far field '{other}' (expected lop or exact)")),
        }
    }
}

/// What drew a pixel, for `--show-lop` (the paper's Figure 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PixelSource {
    /// Nothing: the sky.
    Nothing,
    /// A rasterized mesh cell.
    Mesh,
    /// A ray-cast cell at a level of precision (0 the most precise).
    RayCast(u8),
    /// The exact far field.
    Exact,
}

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

    /// The exact far field: per pixel, the nearest entry `t0` into a ray-cast cell's proxy
    /// box (the cells whose projected box holds the pixel, tested front to back, stopping at
    /// the first whose box is farther than what is already known); wherever it is nearer than
    /// the rasterized near field, `tracer` searches `[t0, near depth]` exactly, tile by tile
    /// (its coherent batches). Pixels in no ray-cast box that no mesh drew see the sky: every
    /// visible surface lies in some cell's box. Returns the number of rays traced.
    pub(super) fn cast_exact(
        &self,
        tracer: &dyn Tracer,
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
                let bottom = top + rows - 1;
                let in_strip: Vec<&FarCell> = self
                    .cells
                    .iter()
                    .filter(|c| c.pixels.j0 as usize <= bottom && c.pixels.j1 as usize >= top)
                    .collect();
                let mut traced = 0;
                let (mut rays, mut found, mut steps, mut at, mut in_tile) =
                    (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
                for tile_x in (0..width).step_by(TILE_SIZE) {
                    let tile = Tile::new(tile_x, top, width, top + rows);
                    let right = (tile_x + TILE_SIZE).min(width) - 1;
                    in_tile.clear();
                    in_tile.extend(in_strip.iter().copied().filter(|c| {
                        c.pixels.i0 as usize <= right && c.pixels.i1 as usize >= tile_x
                    }));
                    rays.clear();
                    at.clear();
                    let mut wanted = 0;
                    for (i, j) in tile.pixels() {
                        let end = near.distance[i + j * width] as f64;
                        let ray = camera.ray(i as u32, j as u32);
                        let start = nearest_entry(&in_tile, &ray, i as u32, j as u32, end);
                        // The whole tile goes to the tracer, so its packets stay whole; a
                        // pixel with nothing to search gets an empty range.
                        if start < end {
                            wanted += 1;
                            rays.push(ray.with_range(start, end));
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
            .sum()
    }
}

/// The nearest entry of `ray` (pixel (i, j)) into the boxes of `cells` (sorted front to back)
/// below `limit`, lowered by a relative margin over rounding and at least 0; `limit` when
/// the ray enters none before it. The scan stops at the first cell whose box is farther than
/// the entry found (or `limit`): no box behind it can be entered sooner.
fn nearest_entry(cells: &[&FarCell], ray: &Ray, i: u32, j: u32, limit: f64) -> f64 {
    let mut best = limit;
    for cell in cells {
        if cell.near >= best {
            break;
        }
        let p = cell.pixels;
        if i < p.i0 || i > p.i1 || j < p.j0 || j > p.j1 {
            continue;
        }
        if let Some(clip) = cell.world_box.clip(ray) {
            let entry = (clip.t_enter * (1.0 - 1e-9) - 1e-9).max(0.0);
            best = best.min(entry);
        }
    }
    best
}
