//! A rendered frame, what the scene renderer reports of it, and its copy into the window's
//! framebuffer, scaled to the window.

use relief_core::Camera;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// What rendering a frame cost.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameStats {
    /// Rays cast (camera, shadow and any other).
    pub rays: u64,
    /// Mean traversal steps per camera ray, where the tracer counts them.
    pub steps_per_ray: Option<f64>,
}

/// A rendered image: sRGB, 8 bits a channel, rows from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` RGB triples.
    pub rgb: Vec<[u8; 3]>,
    /// What it cost.
    pub stats: FrameStats,
    /// What the renderer did other than asked, if anything (e.g. "the safety tracer draws
    /// triangles only: drawn by the mipmap tracer"), shown in the overlay.
    pub note: Option<String>,
}

/// Set by the viewer when it no longer needs the frame being rendered (the view changed while
/// a frame at rest was on its way); a renderer may then stop early, and its frame is
/// discarded.
#[derive(Debug, Clone, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A token not set.
    pub fn new() -> Self {
        Cancel::default()
    }

    /// Asks the renderer to stop.
    pub fn set(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether the frame is no longer wanted.
    pub fn is_set(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// The flag itself, set when the frame is no longer wanted: what a tracer stopped by it
    /// (`relief_trace::adapters::Interruptible`) watches.
    pub fn flag(&self) -> &AtomicBool {
        &self.0
    }
}

/// Renders frames of one scene: the viewer's only way to draw, so that it has no rendering
/// logic of its own. Called from the viewer's render thread.
pub trait SceneRenderer: Send + Sync {
    /// The scene in a few words, e.g. "4096x4096 height field".
    fn describe(&self) -> String;

    /// The diagonal of the scene's bounds, in metres: sets the flying speed.
    fn scene_size(&self) -> f64;

    /// Renders the view of `camera` with `settings`; it may stop early once `cancel` is set.
    fn render(
        &self,
        camera: &Camera,
        settings: &crate::ViewSettings,
        cancel: &Cancel,
    ) -> Result<Frame, String>;

    /// Whether the scene has a simulation the viewer can run, pause and step (MLHM scenes).
    fn has_simulation(&self) -> bool {
        false
    }

    /// Advances the scene's simulation as `request` asks: the frames rendered after it show
    /// the new state. Called from the render thread, before the frame it is asked with.
    fn simulate(
        &self,
        request: &crate::SimulationRequest,
    ) -> Result<crate::SimulationReport, String> {
        let _ = request;
        Err("this scene has no simulation".into())
    }
}

/// Copies `frame` into `target` (0RGB pixels, `width` x `height`), scaled to fill it by the
/// nearest pixel.
pub fn blit(frame: &Frame, target: &mut [u32], width: u32, height: u32) {
    if frame.width == 0 || frame.height == 0 || width == 0 || height == 0 {
        return;
    }
    let columns: Vec<usize> = (0..width)
        .map(|x| ((u64::from(x) * u64::from(frame.width)) / u64::from(width)) as usize)
        .collect();
    for (y, row) in target.chunks_exact_mut(width as usize).take(height as usize).enumerate() {
        let source_row = (y as u64 * u64::from(frame.height) / u64::from(height)) as usize;
        let source = &frame.rgb[source_row * frame.width as usize..][..frame.width as usize];
        for (pixel, &column) in row.iter_mut().zip(&columns) {
            let [r, g, b] = source[column];
            *pixel = (u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_is_scaled_by_the_nearest_pixel() {
        let frame = Frame {
            width: 2,
            height: 1,
            rgb: vec![[255, 0, 0], [0, 0, 255]],
            stats: FrameStats::default(),
            note: None,
        };
        let mut target = vec![0u32; 4 * 2];
        blit(&frame, &mut target, 4, 2);
        let (red, blue) = (0xff0000, 0x0000ff);
        assert_eq!(target, [red, red, blue, blue, red, red, blue, blue]);
    }
}
