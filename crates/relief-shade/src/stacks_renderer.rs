//! Material-stack terrains drawn through the rasterizer (Löffler et al. 2011): the LOD mesh
//! for the camera (node meshes cached across frames) rasterized into relief's G-buffer, with
//! the meshes' smooth normals and vertex colours, for the one deferred shading pass.

use crate::render::fill_gbuffer;
use crate::{GBuffer, ShadeError};
use rayon::prelude::*;
use relief_core::{Aabb, Camera, DVec3};
use relief_mesh::{MeshStats, RasterTarget, Rasterizer, StacksMesher};
use relief_trace::Hit;
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

/// Draws a stacks terrain's LOD mesh for a camera into a G-buffer.
#[derive(Debug)]
pub struct StacksRenderer {
    mesher: StacksMesher,
    tau_px: f64,
    rasterizer: Rasterizer,
    target: RasterTarget,
}

impl StacksRenderer {
    /// A renderer of `mesher`'s terrain whose cells cover at most `tau_px` pixels (the
    /// paper's τ, 10 px in its measurements). Fails when `tau_px` is not finite and positive.
    pub fn new(mesher: StacksMesher, tau_px: f64) -> Result<Self, ShadeError> {
        if !(tau_px.is_finite() && tau_px > 0.0) {
            return Err(ShadeError::parameter("tau", format!("{tau_px}: must be positive")));
        }
        Ok(StacksRenderer {
            mesher,
            tau_px,
            rasterizer: Rasterizer::new(),
            target: RasterTarget::new(0, 0),
        })
    }

    /// The mesher (its mipmap and cache).
    pub fn mesher(&self) -> &StacksMesher {
        &self.mesher
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
        gbuffer.validate_for(camera)?;
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
        if (self.target.width, self.target.height) != (gbuffer.width, gbuffer.height) {
            self.target = RasterTarget::for_camera(camera);
        } else {
            self.target.clear();
        }
        let offsets = [0, meshes[0].triangle_count() as u32];
        for (m, &offset) in meshes.iter().zip(&offsets) {
            self.rasterizer
                .draw(camera, m, offset, &mut self.target)
                .map_err(|e| ShadeError::Limits(e.to_string()))?;
        }
        stats.raster_ms = ms(start);

        let start = Instant::now();
        let target = &self.target;
        // Position from the exact ray-plane hit; normal and colour interpolated.
        let surfaces: Vec<Option<(Hit, [f32; 3])>> = (0..gbuffer.len())
            .into_par_iter()
            .map(|index| {
                let id = target.triangle[index];
                if id == RasterTarget::NO_TRIANGLE {
                    return None;
                }
                let part = usize::from(id >= offsets[1]);
                let (mesh, triangle) = (&meshes[part], id - offsets[part]);
                let (i, j) = ((index % gbuffer.width) as u32, (index / gbuffer.width) as u32);
                let ray = camera.ray(i, j);
                let h = mesh.hit(triangle, &ray)?;
                let mut a = [0f32; 6];
                mesh.interpolate_attributes(triangle, h.barycentrics, &mut a).ok()?;
                let smooth = DVec3::new(a[3] as f64, a[4] as f64, a[5] as f64);
                let normal = match smooth.try_normalize() {
                    Some(n) if n.dot(ray.dir) < 0.0 => n,
                    _ => h.normal,
                };
                Some((Hit { t: h.t, position: h.position, normal }, [a[0], a[1], a[2]]))
            })
            .collect();
        fill_gbuffer(gbuffer, camera, bounds, |index, _, _| surfaces[index].map(|s| s.0));
        gbuffer.material.par_iter_mut().zip(&surfaces).for_each(|(m, s)| {
            if let Some((_, c)) = s {
                *m = [c[0], c[1], c[2], 1.0];
            }
        });
        stats.resolve_ms = ms(start);
        Ok(stats)
    }
}

fn ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}
