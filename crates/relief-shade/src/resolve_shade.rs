//! A rasterized frame resolved and shaded strip after strip, without a whole-frame G-buffer:
//! each strip of rows is resolved into a small G-buffer of its worker's (it stays in the
//! processor's caches) and shaded from it at once. The pixels are the ones resolving the
//! whole frame into a G-buffer and shading it give (the same per-pixel steps), with a
//! fraction of the memory traffic. For the frames of a flight, which keep only the picture.

use crate::deferred::ShadingPass;
use crate::gbuffer::image_plane;
use crate::triangle_resolve::RowsResolve;
use crate::{GBuffer, ShadeError, ShadingKernel, ShadingParams};
use rayon::prelude::*;
use relief_core::Camera;
use relief_trace::adapters::NoOccluders;
use std::sync::Mutex;

/// Rows a strip: its shading channels (32 bytes a pixel) stay in a core's cache.
const STRIP_ROWS: usize = 8;

/// The small G-buffers the workers resolve their strips into, one a thread of the pool.
#[derive(Debug, Default)]
pub(crate) struct StripBuffers {
    buffers: Vec<Mutex<GBuffer>>,
}

impl StripBuffers {
    /// The buffers for strips `width` pixels wide (made anew when the width or the pool
    /// changed).
    fn for_width(&mut self, width: usize) -> Result<&[Mutex<GBuffer>], ShadeError> {
        let threads = rayon::current_num_threads().max(1);
        let fits = |b: &Mutex<GBuffer>| b.lock().is_ok_and(|g| g.width == width);
        if self.buffers.len() != threads || !self.buffers.iter().all(fits) {
            self.buffers = (0..threads)
                .map(|_| GBuffer::new(width, STRIP_ROWS).map(Mutex::new))
                .collect::<Result<_, _>>()?;
        }
        Ok(&self.buffers)
    }
}

/// The 8-bit sRGB picture of `camera` that [`crate::shade_to_srgb8`] gives of the G-buffer
/// `rows` resolves (with no occluders: `params` must not ask for shadows), made strip by
/// strip in `strips`.
pub(crate) fn resolve_and_shade_srgb8(
    rows: &RowsResolve,
    camera: &Camera,
    params: &ShadingParams,
    strips: &mut StripBuffers,
) -> Result<Vec<[u8; 3]>, ShadeError> {
    params.validate()?;
    if params.shadows {
        return Err(ShadeError::parameter("shadows", "a frame shaded by strips casts none"));
    }
    let (width, height) = (camera.width() as usize, camera.height() as usize);
    let buffers = strips.for_width(width)?;
    let kernel = ShadingKernel::new(camera, params);
    let mut rgb = image_plane(width * height, [0u8; 3], "shaded image")?;
    rgb.par_chunks_mut(STRIP_ROWS * width).enumerate().for_each(|(s, out)| {
        let top = s * STRIP_ROWS;
        let worker = rayon::current_thread_index().unwrap_or(0) % buffers.len();
        let mut gbuffer = buffers[worker].lock().expect("no strip panicked");
        rows.resolve(top, &mut gbuffer.rows_mut(out.len() / width));
        let pass = ShadingPass::new(&gbuffer, top, &NoOccluders, camera, params);
        pass.shade_strip_srgb8(top, out, kernel.as_ref());
    });
    Ok(rgb)
}
