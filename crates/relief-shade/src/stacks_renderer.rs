//! Material-stack terrains drawn through the rasterizer (Löffler et al. 2011): the LOD mesh
//! for the camera (node meshes cached across frames) rasterized into relief's G-buffer, with
//! the meshes' smooth normals and vertex colours, for the one deferred shading pass.

use crate::resolve_shade::{resolve_and_shade_srgb8, StripBuffers};
use crate::triangle_resolve::{resolve_triangles, DrawnMeshes, ResolvedChannels, RowsResolve};
use crate::{GBuffer, Renderer, ShadeError, ShadingParams, StageTimings};
use rayon::prelude::*;
use relief_core::{Aabb, Camera, DVec3, MaterialStacks};
use relief_mesh::{Culling, IndexedMesh, MeshStats, RasterTarget, Rasterizer, StacksMesher};
use std::time::Instant;

/// Counts and stage timings of one stacks frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StacksFrameStats {
    /// The octree's selection and meshing.
    pub mesh: MeshStats,
    /// Triangles drawn.
    pub triangles: usize,
    /// Milliseconds choosing and meshing nodes (cached ones are free).
    pub mesh_ms: f64,
    /// Milliseconds rasterizing.
    pub raster_ms: f64,
    /// Milliseconds writing the G-buffer.
    pub resolve_ms: f64,
}

impl StacksFrameStats {
    /// The frame's stages: `mesh`, `raster`, `resolve`.
    pub fn timings(&self) -> StageTimings {
        let mut timings = StageTimings::new();
        timings.push("mesh", self.mesh_ms);
        timings.push("raster", self.raster_ms);
        timings.push("resolve", self.resolve_ms);
        timings
    }
}

/// Draws a stacks terrain's LOD mesh for a camera into a G-buffer.
#[derive(Debug)]
pub struct StacksRenderer {
    mesher: StacksMesher,
    tau_px: f64,
    rasterizer: Rasterizer,
    target: RasterTarget,
    texture_bounds: Aabb,
    /// The small G-buffers of [`StacksRenderer::render_srgb8`]'s strips.
    strips: StripBuffers,
}

impl StacksRenderer {
    /// A renderer of `mesher`'s terrain whose cells cover at most `tau_px` pixels (the
    /// paper's τ, 10 px in its measurements). Fails when `tau_px` is not finite and positive.
    pub fn new(mesher: StacksMesher, tau_px: f64) -> Result<Self, ShadeError> {
        if !(tau_px.is_finite() && tau_px > 0.0) {
            return Err(ShadeError::parameter("tau", format!("{tau_px}: must be positive")));
        }
        let texture_bounds =
            mesher.mipmap().level(0).map_or(Aabb::new(DVec3::ZERO, DVec3::ONE), stacks_bounds);
        Ok(StacksRenderer {
            mesher,
            tau_px,
            rasterizer: Rasterizer::new(),
            target: RasterTarget::new(0, 0),
            texture_bounds,
            strips: StripBuffers::default(),
        })
    }

    /// The renderer with texture coordinates spanning `bounds` in [`Renderer::render_frame`]
    /// (by default the stacks' footprint and height range).
    #[must_use]
    pub fn with_texture_bounds(mut self, bounds: Aabb) -> Self {
        self.texture_bounds = bounds;
        self
    }

    /// The mesher (its mipmap and cache).
    pub fn mesher(&self) -> &StacksMesher {
        &self.mesher
    }

    /// Sets the node meshes a frame makes at most (see [`StacksMesher::set_node_budget`]).
    pub fn set_node_budget(&mut self, budget: Option<usize>) {
        self.mesher.set_node_budget(budget);
    }

    /// Renders the view of `camera` into `gbuffer` (every pixel overwritten): the solid and
    /// the water, depth-tested together. `bounds` is the box texture coordinates span. The
    /// G-buffer's material weights hold each pixel's linear RGB colour (for
    /// [`crate::Albedo::GBufferColour`]).
    pub fn render_into(
        &mut self,
        camera: &Camera,
        bounds: &Aabb,
        gbuffer: &mut GBuffer,
    ) -> Result<StacksFrameStats, ShadeError> {
        self.render(camera, bounds, gbuffer, ResolvedChannels::All)
    }

    /// [`StacksRenderer::render_into`] writing only what the deferred shading of the colours
    /// reads: each pixel's distance, normal and material weights (the other channels left as
    /// they were). A frame of a flight, shaded and let go.
    pub fn render_for_shading_into(
        &mut self,
        camera: &Camera,
        bounds: &Aabb,
        gbuffer: &mut GBuffer,
    ) -> Result<StacksFrameStats, ShadeError> {
        self.render(camera, bounds, gbuffer, ResolvedChannels::Shading)
    }

    /// The 8-bit sRGB picture of `camera`'s view shaded with `params` (no shadows; `bounds`
    /// is the box texture coordinates span), resolved and shaded strip by strip without a
    /// whole-frame G-buffer: the picture [`StacksRenderer::render_for_shading_into`] and
    /// [`crate::shade_to_srgb8`] (with no occluders) give, bit for bit. A frame of a flight.
    /// Its `resolve_ms` counts the shading too.
    pub fn render_srgb8(
        &mut self,
        camera: &Camera,
        bounds: &Aabb,
        params: &ShadingParams,
    ) -> Result<(Vec<[u8; 3]>, StacksFrameStats), ShadeError> {
        let mut strips = std::mem::take(&mut self.strips);
        let shaded = self.render_with(camera, |target, drawn| {
            let rows =
                RowsResolve::for_frame(camera, bounds, target, drawn, ResolvedChannels::Shading);
            resolve_and_shade_srgb8(&rows, camera, params, &mut strips)
        });
        self.strips = strips;
        shaded
    }

    /// Draws `camera`'s view into the `channels` of `gbuffer`.
    fn render(
        &mut self,
        camera: &Camera,
        bounds: &Aabb,
        gbuffer: &mut GBuffer,
        channels: ResolvedChannels,
    ) -> Result<StacksFrameStats, ShadeError> {
        gbuffer.validate_for(camera)?;
        let ((), stats) = self.render_with(camera, |target, drawn| {
            resolve_triangles(gbuffer, camera, bounds, target, drawn, channels);
            Ok(())
        })?;
        Ok(stats)
    }

    /// Meshes and rasterizes `camera`'s view, then `resolve`s the target it drew (the time
    /// it takes counted as the resolve's).
    fn render_with<T>(
        &mut self,
        camera: &Camera,
        resolve: impl FnOnce(&RasterTarget, &DrawnMeshes) -> Result<T, ShadeError>,
    ) -> Result<(T, StacksFrameStats), ShadeError> {
        let (width, height) = (camera.width() as usize, camera.height() as usize);
        let start = Instant::now();
        let (meshes, mesh_stats) = self
            .mesher
            .draw_meshes_for_camera(camera, self.tau_px)
            .map_err(|e| ShadeError::Limits(e.to_string()))?;
        let mut stats = StacksFrameStats {
            mesh: mesh_stats,
            triangles: meshes.iter().map(|m| m.triangle_count()).sum(),
            mesh_ms: ms(start),
            ..Default::default()
        };

        let start = Instant::now();
        if (self.target.width, self.target.height) != (width, height) {
            self.target = RasterTarget::with_barycentrics(width, height);
        } else {
            self.target.clear();
        }
        let offsets = [0, meshes[0].triangle_count() as u32];
        for (m, &offset) in meshes.iter().zip(&offsets) {
            // A closed mesh seen from outside shows only its front faces.
            let culling =
                if seen_from_outside(camera, m) { Culling::BackFaces } else { Culling::None };
            self.rasterizer
                .with_culling(culling)
                .draw(camera, m, offset, &mut self.target)
                .map_err(|e| ShadeError::Limits(e.to_string()))?;
        }
        stats.raster_ms = ms(start);

        let start = Instant::now();
        let drawn = DrawnMeshes { meshes, first_ids: &offsets };
        let resolved = resolve(&self.target, &drawn)?;
        stats.resolve_ms = ms(start);
        self.mesher.begin_meshing_ahead();
        Ok((resolved, stats))
    }
}

impl Renderer for StacksRenderer {
    /// [`StacksRenderer::render_into`] with the renderer's texture bounds.
    fn render_frame(
        &mut self,
        camera: &Camera,
        gbuffer: &mut GBuffer,
    ) -> Result<StageTimings, ShadeError> {
        let bounds = self.texture_bounds;
        Ok(self.render_into(camera, &bounds, gbuffer)?.timings())
    }
}

/// Whether `camera`'s eye is certainly outside the closed `mesh`: a pinhole whose eye no
/// triangle lies over (the vertical ray up from the eye crosses none). Then every camera ray
/// enters the solid before it leaves it, and the first surface a ray meets is a front face:
/// drawing the front faces alone gives the same picture. Not so for an eye under an overhang,
/// in a cave or in the water, or an orthographic camera, which draw both faces.
fn seen_from_outside(camera: &Camera, mesh: &IndexedMesh) -> bool {
    if camera.fov_deg().is_none() {
        return false;
    }
    let eye = camera.eye();
    let positions = mesh.positions();
    mesh.triangles().par_iter().all(|tri| {
        let [a, b, c] = tri.map(|v| positions[v as usize]);
        let below = a.z < eye.z && b.z < eye.z && c.z < eye.z;
        let beside = (a.x < eye.x && b.x < eye.x && c.x < eye.x)
            || (a.x > eye.x && b.x > eye.x && c.x > eye.x)
            || (a.y < eye.y && b.y < eye.y && c.y < eye.y)
            || (a.y > eye.y && b.y > eye.y && c.y > eye.y);
        below || beside
    })
}

/// The box over the footprint and height range of `stacks` (a unit of height for a flat or
/// empty one).
fn stacks_bounds(stacks: &MaterialStacks) -> Aabb {
    let (low, high) = stacks.height_range().unwrap_or((0.0, 1.0));
    let (o, s) = (stacks.origin(), stacks.spacing());
    Aabb::new(
        DVec3::new(o.x, o.y, low as f64),
        DVec3::new(
            o.x + s.x * stacks.width() as f64,
            o.y + s.y * stacks.height() as f64,
            (high as f64).max(low as f64 + 1e-3),
        ),
    )
}

fn ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::{DVec2, MaterialStacks, Ray, StackLayer, StackMaterial, StacksMipmap};
    use relief_mesh::{StacksMeshParams, StacksMesher};

    /// Ground with an overhanging slab and a pond.
    fn mesher() -> StacksMesher {
        let mut stacks = Vec::new();
        for y in 0..20 {
            for x in 0..20 {
                let ground = 4.0 + 1.5 * (x as f32 / 3.0).sin() * (y as f32 / 4.0).cos();
                let mut layers = vec![StackLayer::new(0.0, ground, 0)];
                if (12..18).contains(&x) && (2..8).contains(&y) {
                    layers.push(StackLayer::new(ground, ground + 2.0, 2));
                }
                if (4..12).contains(&x) && (6..16).contains(&y) {
                    layers.push(StackLayer::new(8.0, 10.0, 0));
                }
                stacks.push(layers);
            }
        }
        let stacks = MaterialStacks::from_stacks(
            20,
            20,
            DVec2::ONE,
            DVec2::ZERO,
            StackMaterial::defaults(),
            &stacks,
        )
        .unwrap();
        StacksMesher::new(
            StacksMipmap::new(stacks).unwrap(),
            StacksMeshParams { node_cells: 4, ..Default::default() },
        )
        .unwrap()
    }

    /// The nearest hit of `ray` with any triangle, brute force (Möller-Trumbore).
    fn nearest(ray: &Ray, triangles: &[[DVec3; 3]]) -> f64 {
        let mut best = f64::INFINITY;
        for [a, b, c] in triangles {
            let (e1, e2) = (*b - *a, *c - *a);
            let p = ray.dir.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-14 {
                continue;
            }
            let s = ray.origin - *a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = ray.dir.dot(q) / det;
            let t = e2.dot(q) / det;
            if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0 {
                best = best.min(t);
            }
        }
        best
    }

    #[test]
    fn the_rasterized_depth_is_the_meshs_exact_depth() {
        let camera = Camera::look_at(
            DVec3::new(-6.0, -8.0, 18.0),
            DVec3::new(10.0, 10.0, 4.0),
            DVec3::Z,
            55.0,
            64,
            48,
        )
        .unwrap();
        let bounds = Aabb::new(DVec3::new(0.0, 0.0, 0.0), DVec3::new(20.0, 20.0, 10.0));
        let mut renderer = StacksRenderer::new(mesher(), 3.0).unwrap();
        let mut gbuffer = GBuffer::new(64, 48).unwrap();
        let stats = renderer.render_into(&camera, &bounds, &mut gbuffer).unwrap();
        assert!(stats.mesh.per_level.iter().filter(|&&n| n > 0).count() >= 2);
        // The same meshes (the nodes from the cache), as triangles.
        let (meshes, _) = renderer.mesher.draw_meshes_for_camera(&camera, 3.0).unwrap();
        let triangles: Vec<[DVec3; 3]> = meshes
            .iter()
            .flat_map(|m| m.triangles().iter().map(|t| t.map(|v| m.positions()[v as usize])))
            .collect();
        let mut off = 0;
        let mut hits = 0;
        for j in 0..48 {
            for i in 0..64 {
                let expected = nearest(&camera.ray(i, j), &triangles);
                let got = gbuffer.distance[(i + j * 64) as usize] as f64;
                hits += usize::from(expected.is_finite());
                let agree = if expected.is_finite() {
                    (got - expected).abs() <= 1e-4 * expected
                } else {
                    got.is_infinite()
                };
                off += usize::from(!agree);
            }
        }
        assert!(hits > 500, "{hits} pixels see the terrain");
        assert!(off <= 2, "{off} pixels differ from the brute-force depth");
    }

    #[test]
    fn an_amortised_flight_catches_up_to_the_still_frame() {
        let bounds = Aabb::new(DVec3::new(0.0, 0.0, 0.0), DVec3::new(20.0, 20.0, 10.0));
        let camera = |x: f64| {
            Camera::look_at(
                DVec3::new(x, -8.0, 16.0),
                DVec3::new(10.0, 10.0, 4.0),
                DVec3::Z,
                55.0,
                64,
                48,
            )
            .unwrap()
        };
        let still = camera(-6.0);
        let mut fresh = StacksRenderer::new(mesher(), 3.0).unwrap();
        let mut want = GBuffer::new(64, 48).unwrap();
        let stats = fresh.render_into(&still, &bounds, &mut want).unwrap();
        assert_eq!(stats.mesh.waiting, 0, "a first frame meshes every node");
        // From far away, closing in, then holding still, 16 node meshes a frame.
        let mut flying = StacksRenderer::new(mesher(), 3.0).unwrap();
        flying.set_node_budget(Some(16));
        let mut got = GBuffer::new(64, 48).unwrap();
        let (mut waited, mut frames) = (0, 0);
        for x in [-60.0, -40.0, -20.0] {
            let stats = flying.render_into(&camera(x), &bounds, &mut got).unwrap();
            waited += stats.mesh.waiting;
            frames += 1;
        }
        assert!(waited > 0, "some nodes waited for their turn");
        loop {
            let stats = flying.render_into(&still, &bounds, &mut got).unwrap();
            frames += 1;
            if stats.mesh.waiting == 0 {
                break;
            }
            assert!(frames < 200, "the flight never caught up");
        }
        assert!(got == want, "the caught-up frame differs from the still frame");
    }

    #[test]
    fn strips_shade_the_pixels_the_whole_g_buffer_shades() {
        let bounds = Aabb::new(DVec3::new(0.0, 0.0, 0.0), DVec3::new(20.0, 20.0, 10.0));
        let mut params = crate::ShadingParams::for_terrain(&bounds).unwrap();
        params.albedo = crate::Albedo::GBufferColour { fallback: [0.3; 3] };
        params.shadows = false;
        // Heights that leave a short last strip; an eye outside, one under the slab.
        for (eye, size) in [((-6.0, -8.0, 16.0), (64, 61)), ((8.0, 10.0, 7.0), (50, 37))] {
            let camera = Camera::look_at(
                DVec3::new(eye.0, eye.1, eye.2),
                DVec3::new(10.0, 10.0, 4.0),
                DVec3::Z,
                55.0,
                size.0,
                size.1,
            )
            .unwrap();
            let mut whole = StacksRenderer::new(mesher(), 3.0).unwrap();
            let mut gbuffer = GBuffer::new(size.0 as usize, size.1 as usize).unwrap();
            whole.render_for_shading_into(&camera, &bounds, &mut gbuffer).unwrap();
            let want = crate::shade_to_srgb8(
                &gbuffer,
                &relief_trace::adapters::NoOccluders,
                &camera,
                &params,
            )
            .unwrap()
            .0;
            let mut strips = StacksRenderer::new(mesher(), 3.0).unwrap();
            let (got, _) = strips.render_srgb8(&camera, &bounds, &params).unwrap();
            assert!(got == want, "the strips' picture differs from eye {eye:?}");
        }
    }
}
