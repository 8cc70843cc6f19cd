//! The hybrid renderer of one height field: per frame the heuristic's choice per cell, the
//! near field rasterized, the far field cast, and every pixel's hit written into the G-buffer.

use super::far_field::{FarCells, FarField, FarHit, PixelSource};
use super::heuristic::{CellChoice, HybridHeuristic, HybridParams};
use super::near_field::{mesh_hit, NearField};
use super::projection::bottom_visible;
use crate::render::fill_gbuffer;
use crate::{GBuffer, Renderer, ShadeError, StageTimings};
use relief_core::{Aabb, Camera, CoreError, HeightField, Projection, Ray, SampleRegion, Surface};
use relief_mesh::{Culling, RasterTarget, Rasterizer};
use relief_trace::hybrid::HybridCells;
use relief_trace::{MipmapTracer, Tracer};
use std::sync::Arc;
use std::time::Instant;

/// Counts and stage timings of one hybrid frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HybridStats {
    /// Cells culled by the view frustum (or without surface).
    pub culled_cells: usize,
    /// Cells rasterized as meshes.
    pub mesh_cells: usize,
    /// Cells ray cast, per level of precision.
    pub ray_cast_cells: Vec<usize>,
    /// Triangles sent to the rasterizer.
    pub triangles: usize,
    /// Pixels whose rays the far field searched (per cell for levels of precision).
    pub far_rays: u64,
    /// Milliseconds choosing per cell.
    pub heuristic_ms: f64,
    /// Milliseconds building the mesh cells' meshes missing from the cache.
    pub mesh_build_ms: f64,
    /// Milliseconds rasterizing.
    pub raster_ms: f64,
    /// Milliseconds in the far field.
    pub far_ms: f64,
    /// Milliseconds writing the G-buffer.
    pub resolve_ms: f64,
}

impl HybridStats {
    /// The frame's stages: `heuristic`, `mesh_build`, `raster`, `far`, `resolve`.
    pub fn timings(&self) -> StageTimings {
        let mut timings = StageTimings::new();
        timings.push("heuristic", self.heuristic_ms);
        timings.push("mesh_build", self.mesh_build_ms);
        timings.push("raster", self.raster_ms);
        timings.push("far", self.far_ms);
        timings.push("resolve", self.resolve_ms);
        timings
    }
}

/// The hybrid renderer of one height field: its cells, the heuristic's parameters, the far
/// field's kind, the exact tracer (for `--far exact`, for a camera inside the solid and for
/// shadow rays) and the mesh cache.
pub struct HybridRenderer {
    exact: MipmapTracer,
    cells: HybridCells,
    heuristic: HybridHeuristic,
    far: FarField,
    near: NearField,
    rasterizer: Rasterizer,
    target: RasterTarget,
    /// Per pixel, the far field's hit and what found it: kept across frames, so that a frame
    /// does not allocate (and fault in) a buffer of the image's size.
    far_hits: Vec<FarHit>,
}

impl HybridRenderer {
    /// The renderer of `surface` over `field` with `params` and `far`. Builds the exact
    /// tracer's pyramid and measures the cells (no other precomputation).
    ///
    /// Errors: parameters [`HybridParams::validate`] refuses.
    pub fn new(
        field: Arc<HeightField>,
        surface: Surface,
        params: HybridParams,
        far: FarField,
    ) -> Result<Self, ShadeError> {
        let heuristic = HybridHeuristic::new(params)?;
        let cells = HybridCells::new(&field, surface, params.cell).map_err(hybrid_parameter)?;
        let near = NearField::new(cells.len());
        Ok(HybridRenderer {
            exact: MipmapTracer::new(field, surface),
            cells,
            heuristic,
            far,
            near,
            // The solid is closed and its meshes wound outward: seen from outside (a camera
            // inside it is drawn by the exact tracer), its back faces are always hidden.
            rasterizer: Rasterizer::new().with_culling(Culling::BackFaces),
            target: RasterTarget::new(0, 0),
            far_hits: Vec::new(),
        })
    }

    /// The height field drawn.
    pub fn field(&self) -> &Arc<HeightField> {
        self.exact.field()
    }

    /// The exact tracer of the same surface (for shadow rays).
    pub fn tracer(&self) -> &dyn Tracer {
        &self.exact
    }

    /// The cells and their bounds.
    pub fn cells(&self) -> &HybridCells {
        &self.cells
    }

    /// The heuristic with its parameters.
    pub fn heuristic(&self) -> &HybridHeuristic {
        &self.heuristic
    }

    /// Edits the field with `edit` (which returns the region it changed, as
    /// [`HeightField::edit_region`] does), then updates what depends on the changed samples
    /// only: the exact tracer's pyramid above them, the cells holding them and their cached
    /// meshes (every mesh when the field's value range moved, since walls reach its lowest
    /// sample). The edit's error type is the caller's (a simulation's, say); a failed edit
    /// leaves the field as the closure left it and everything rebuilt from it.
    pub fn edit<E: From<CoreError>>(
        &mut self,
        edit: impl FnOnce(&mut HeightField) -> Result<SampleRegion, E>,
    ) -> Result<SampleRegion, E> {
        let range = field_range(self.field());
        let mut failure = None;
        let edited = self.exact.edit(|field| {
            edit(field).map_err(|e| {
                failure = Some(e);
                CoreError::Grid("the edit failed".into())
            })
        });
        let field = self.exact.field().clone();
        let region = match edited {
            Ok(region) => region,
            Err(e) => {
                self.rebuild_from(&field);
                return Err(failure.unwrap_or_else(|| E::from(e)));
            }
        };
        self.cells.update(&field, region);
        if field_range(&field) == range {
            self.near.invalidate(&self.cells, region);
        } else {
            self.near.invalidate_all();
        }
        Ok(region)
    }

    /// The cells and the mesh cache measured afresh from `field` (after a failed edit, which
    /// may have changed any sample).
    fn rebuild_from(&mut self, field: &HeightField) {
        self.cells.update(field, SampleRegion::whole(field.width(), field.height()));
        self.near.invalidate_all();
    }

    /// Renders the view of `camera` into `gbuffer` (every pixel overwritten), `bounds` the
    /// box the texture coordinates span; `sources`, when given, receives what drew each pixel.
    ///
    /// Fails when the G-buffer's size is not the camera's image size.
    pub fn render_into(
        &mut self,
        camera: &Camera,
        bounds: &Aabb,
        gbuffer: &mut GBuffer,
        sources: Option<&mut Vec<PixelSource>>,
    ) -> Result<HybridStats, ShadeError> {
        gbuffer.validate_for(camera)?;
        let (width, height) = (gbuffer.width, gbuffer.height);
        let mut stats = HybridStats::default();
        if self.starts_inside(camera) {
            // Rays that start inside the solid hit where they start, in no proxy box: the
            // exact tracer draws such a view.
            crate::render_gbuffer_into(&self.exact, camera, bounds, gbuffer, &|_| {})?;
            if let Some(sources) = sources {
                sources.clear();
                sources.extend(gbuffer.distance.iter().map(|d| {
                    if d.is_finite() {
                        PixelSource::Exact
                    } else {
                        PixelSource::Nothing
                    }
                }));
            }
            return Ok(stats);
        }
        let field = self.exact.field().clone();
        self.cells.set_floor_everywhere(bottom_visible(&self.cells, camera));

        let start = Instant::now();
        let choices = self.heuristic.choose(&self.cells, camera);
        stats.ray_cast_cells = vec![0; self.heuristic.steps().len()];
        for choice in &choices {
            match choice {
                CellChoice::Culled => stats.culled_cells += 1,
                CellChoice::Mesh => stats.mesh_cells += 1,
                CellChoice::RayCast { level } => stats.ray_cast_cells[*level as usize] += 1,
            }
        }
        stats.heuristic_ms = elapsed_ms(start);

        let start = Instant::now();
        let mesh = self.near.frame_mesh(&field, &self.cells, &choices)?;
        stats.triangles = mesh.triangle_count();
        stats.mesh_build_ms = elapsed_ms(start);

        let start = Instant::now();
        if (self.target.width, self.target.height) != (width, height) {
            self.target = RasterTarget::for_camera(camera);
        } else {
            self.target.clear();
        }
        self.rasterizer.draw(camera, &mesh, 0, &mut self.target).map_err(mesh_error)?;
        stats.raster_ms = elapsed_ms(start);

        let start = Instant::now();
        let far = FarCells::new(&self.cells, &self.heuristic, &choices, camera);
        let hits = &mut self.far_hits;
        hits.clear();
        hits.resize(width * height, None);
        stats.far_rays = match self.far {
            FarField::Lop => far.cast_levels(&field, &self.cells, camera, &self.target, hits),
            FarField::Exact => far.cast_exact(&self.exact, camera, &self.target, hits),
        };
        stats.far_ms = elapsed_ms(start);

        let start = Instant::now();
        let (target, hits) = (&self.target, &self.far_hits);
        fill_gbuffer(gbuffer, camera, bounds, |index, i, j| match hits[index] {
            Some((hit, _)) => Some(hit),
            None => match target.triangle[index] {
                RasterTarget::NO_TRIANGLE => None,
                triangle => mesh_hit(&mesh, triangle, &camera.ray(i, j)),
            },
        });
        if let Some(sources) = sources {
            sources.clear();
            sources.extend(gbuffer.distance.iter().enumerate().map(|(index, d)| {
                match (d.is_finite(), hits[index]) {
                    (false, _) => PixelSource::Nothing,
                    (true, Some((_, source))) => source,
                    (true, None) => PixelSource::Mesh,
                }
            }));
        }
        stats.resolve_ms = elapsed_ms(start);
        Ok(stats)
    }

    /// Whether the camera's rays start inside the solid (or, for an orthographic camera, may:
    /// its image plane meets the terrain's box), where no proxy box holds their hits.
    fn starts_inside(&self, camera: &Camera) -> bool {
        match camera.projection() {
            Projection::Perspective { .. } => {
                let eye = camera.eye();
                let probe = Ray::new(eye, camera.forward()).with_range(0.0, 0.0);
                self.exact.intersect(&probe).is_some()
            }
            Projection::Orthographic { .. } => {
                let b = self.cells.world_bounds();
                let f = camera.forward();
                let corners = (0..8).map(|k| {
                    relief_core::DVec3::new(
                        if k & 1 == 0 { b.min.x } else { b.max.x },
                        if k & 2 == 0 { b.min.y } else { b.max.y },
                        if k & 4 == 0 { b.min.z } else { b.max.z },
                    )
                });
                corners.into_iter().any(|c| (c - camera.eye()).dot(f) <= 0.0)
            }
        }
    }
}

impl Renderer for HybridRenderer {
    /// [`HybridRenderer::render_into`], texture coordinates spanning the field's world bounds,
    /// without what drew each pixel.
    fn render_frame(
        &mut self,
        camera: &Camera,
        gbuffer: &mut GBuffer,
    ) -> Result<StageTimings, ShadeError> {
        let bounds = self.field().world_bounds(self.cells.surface());
        Ok(self.render_into(camera, &bounds, gbuffer, None)?.timings())
    }
}

/// The field's value range, bit for bit.
fn field_range(field: &HeightField) -> (u32, u32) {
    (field.min_sample().to_bits(), field.max_sample().to_bits())
}

fn elapsed_ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// A hybrid parameter refused by relief-trace, as a [`ShadeError::Parameter`].
fn hybrid_parameter(e: relief_trace::TraceError) -> ShadeError {
    ShadeError::parameter("hybrid parameters", e.to_string())
}

/// A rasterizer error (a size mismatch or a mesh past the ids' limits).
fn mesh_error(e: relief_mesh::MeshError) -> ShadeError {
    ShadeError::Limits(e.to_string())
}
