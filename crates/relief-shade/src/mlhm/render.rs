//! The whole MLHM rendering, Nilles & Müller (2025), section 4.6: the renderer's visibility
//! pass into a G-buffer, then the deferred MLHM lighting over it.

use super::lighting::shade_mlhm_marked;
use super::ray_counts::MlhmRayCounts;
use super::renderer::MlhmRenderer;
use super::shading::MlhmShading;
use crate::{GBuffer, PixelMask, ShadeError};
use relief_core::Camera;
use relief_trace::MlhmTracer;

/// A rendered MLHM image.
#[derive(Debug, Clone, PartialEq)]
pub struct MlhmImage {
    /// What the camera rays hit (distance, position, normal; material weights are bedrock,
    /// sand, water and air, one-hot; and the exact hits).
    pub gbuffer: GBuffer,
    /// Linear radiance per pixel, row-major, row 0 the top row.
    pub radiance: Vec<[f32; 3]>,
    /// The rays traced.
    pub counts: MlhmRayCounts,
}

/// Renders the MLHM that `tracer` traces, as `camera` sees it, with `shading`: the camera
/// rays into a G-buffer ([`MlhmRenderer::render_into`], `progress` getting the pixels of each
/// traced tile), then the deferred lighting over it ([`super::shade_mlhm`]). The result does not
/// depend on the thread count.
///
/// Fails when a parameter is invalid or the image cannot be allocated.
pub fn render_mlhm(
    tracer: &dyn MlhmTracer,
    camera: &Camera,
    shading: &MlhmShading,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<MlhmImage, ShadeError> {
    render_with(MlhmRenderer::new(tracer), tracer, camera, shading, None, progress)
}

/// [`render_mlhm`] of the pixels `mask` marks only: each gets the radiance [`render_mlhm`]
/// gives it, and every other pixel is black, at almost no cost (how an anti-aliasing pass
/// samples again only the pixels that need it). It draws into `reused`, the G-buffer of an
/// earlier image of the same size (its other pixels are not read), where one is given.
///
/// Fails as [`render_mlhm`] does, and when the mask is not of the camera's image size.
pub fn render_mlhm_marked(
    tracer: &dyn MlhmTracer,
    camera: &Camera,
    shading: &MlhmShading,
    mask: &PixelMask,
    reused: Option<GBuffer>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<MlhmImage, ShadeError> {
    let renderer = MlhmRenderer::new(tracer).marked(mask);
    render_with(renderer, tracer, camera, shading, reused, progress)
}

/// The image `renderer` traces (of `tracer`'s scene) and the deferred lighting shades, into
/// the `reused` G-buffer where it is of the camera's size.
fn render_with(
    mut renderer: MlhmRenderer,
    tracer: &dyn MlhmTracer,
    camera: &Camera,
    shading: &MlhmShading,
    reused: Option<GBuffer>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<MlhmImage, ShadeError> {
    shading.validate()?;
    let (width, height) = (camera.width() as usize, camera.height() as usize);
    let mut gbuffer = match reused {
        Some(gbuffer) if (gbuffer.width, gbuffer.height) == (width, height) => gbuffer,
        _ => GBuffer::new(width, height)?,
    };
    let mask = renderer.mask();
    let primary = renderer.render_into(camera, &mut gbuffer, progress)?;
    let (radiance, counts) = shade_mlhm_marked(&gbuffer, tracer, camera, shading, mask)?;
    let counts = MlhmRayCounts { primary, ..counts };
    Ok(MlhmImage { gbuffer, radiance, counts })
}
