//! The render thread: frames are rendered (and the simulation stepped) away from the event
//! loop, which never waits for one.

use crate::frame::{Cancel, Frame, FrameStats, SceneRenderer};
use crate::progressive::FrameRequest;
use crate::{SimulationReport, SimulationRequest, ViewSettings};
use relief_core::Camera;
use relief_render::antialias::grid_mean;
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

/// A frame to render.
pub(crate) struct Job {
    /// The frame's size and the view's version.
    pub request: FrameRequest,
    /// The camera at the frame's size.
    pub camera: Camera,
    /// The settings to render with.
    pub settings: ViewSettings,
    /// Whether the camera was moving when the frame was asked for.
    pub moving: bool,
    /// Set when the viewer no longer wants the frame.
    pub cancel: Cancel,
    /// The simulation's steps to take before the frame.
    pub simulate: Option<SimulationRequest>,
}

/// What the render thread sends back.
pub(crate) enum Rendered {
    /// A frame rendered for `request`, in `elapsed`, after the simulation's steps `simulated`.
    Frame {
        request: FrameRequest,
        frame: Frame,
        elapsed: Duration,
        moving: bool,
        simulated: Option<SimulationReport>,
    },
    /// A frame the viewer cancelled (the simulation's steps before it were taken).
    Cancelled(Option<SimulationReport>),
    /// The renderer or the simulation failed, saying why.
    Failed(String),
}

/// The render thread: it renders the jobs sent to it and hands each result to `deliver`,
/// stopping when `deliver` says no one listens any more.
pub(crate) fn spawn_render_thread(
    renderer: Arc<dyn SceneRenderer>,
    deliver: impl Fn(Rendered) -> bool + Send + 'static,
) -> (mpsc::Sender<Job>, std::thread::JoinHandle<()>) {
    let (send, receive) = mpsc::channel::<Job>();
    let worker = std::thread::spawn(move || {
        for job in receive {
            let simulated = match job.simulate.map(|r| renderer.simulate(&r)).transpose() {
                Ok(report) => report,
                Err(e) => {
                    deliver(Rendered::Failed(e));
                    return;
                }
            };
            // The frame's time is the rendering's (the scheduler sizes frames by it).
            let started = Instant::now();
            let frame = match job.request.samples {
                1 => renderer.render(&job.camera, &job.settings, &job.cancel),
                n => render_antialiased(renderer.as_ref(), &job, n),
            };
            let rendered = match frame {
                Ok(_) if job.cancel.is_set() => Rendered::Cancelled(simulated),
                Ok(frame) => Rendered::Frame {
                    request: job.request,
                    frame,
                    elapsed: started.elapsed(),
                    moving: job.moving,
                    simulated,
                },
                Err(e) => Rendered::Failed(e),
            };
            if !deliver(rendered) {
                return;
            }
        }
    });
    (send, worker)
}

/// `job`'s frame anti-aliased on an `n x n` grid, as `relief render --aa N` draws it
/// ([`grid_mean`]). A cancelled job's frames stop early (their tracers do) and are dropped.
fn render_antialiased(renderer: &dyn SceneRenderer, job: &Job, n: u32) -> Result<Frame, String> {
    let mut last: Option<Frame> = None;
    let mut rays = 0;
    let rgb = grid_mean::<String>(&job.camera, n, |camera| {
        let mut frame = renderer.render(camera, &job.settings, &job.cancel)?;
        rays += frame.stats.rays;
        let rgb = std::mem::take(&mut frame.rgb);
        last = Some(frame);
        Ok(rgb)
    })?;
    let frame = last.ok_or("no frame was rendered")?;
    Ok(Frame { rgb, stats: FrameStats { rays, ..frame.stats }, ..frame })
}
