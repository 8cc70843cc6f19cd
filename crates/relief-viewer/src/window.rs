//! The window and its event loop: input goes to the camera and the settings, frames are
//! rendered on a separate thread (the loop never waits for one), and the newest frame is
//! shown scaled to the window with the overlay.
//!
//! This file holds the viewer's state ([`App`]: what it shows, schedules and records, and
//! how it acts on a key or a rendered frame) and [`run`]; beside it, in `window/`: the
//! render thread, the loop control the state asks of its loop (winit's or the headless
//! one), the configuration, camera recording, the files it saves, and winit's events.

use crate::frame::{Cancel, Frame, SceneRenderer};
use crate::input_map::{action_for, motion_from, Action, Key};
use crate::progressive::{FrameRequest, ProgressiveScheduler};
use crate::script::SCRIPT_FRAME_S;
use crate::summary::{FrameRecord, ViewerSummary};
use crate::{CameraController, ViewSettings, ViewerError};
use crate::{SimulationControl, SimulationReport};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};
use winit::event_loop::EventLoop;
use winit::window::Window;

mod camera_recording;
mod loop_control;
mod output_files;
mod render_thread;
mod viewer_config;
mod winit_events;

use camera_recording::CameraRecording;
use output_files::save_screenshot;
// The names the crate reaches through this file (lib.rs, headless.rs), defined beside it.
pub(crate) use loop_control::LoopControl;
pub(crate) use render_thread::{spawn_render_thread, Job, Rendered};
pub use viewer_config::ViewerConfig;

/// How long after the last mouse movement a drag still counts as moving.
const DRAG_SETTLE: Duration = Duration::from_millis(150);

/// Refuses, before any scene is loaded, to run where there is no X display to open a window
/// on (`DISPLAY` unset or empty).
pub fn check_display() -> Result<(), ViewerError> {
    if std::env::var_os("DISPLAY").is_none_or(|d| d.is_empty()) {
        return Err(ViewerError::NoDisplay(
            "relief view opens an X11 window and DISPLAY is not set (on a machine without a \
             screen, run it under Xvfb: xvfb-run relief view ...)"
                .into(),
        ));
    }
    Ok(())
}

/// Opens the window and runs until it is closed (or `config.frames` are done).
pub fn run(
    renderer: Arc<dyn SceneRenderer>,
    config: ViewerConfig,
) -> Result<ViewerSummary, ViewerError> {
    check_display()?;
    let event_loop = EventLoop::<Rendered>::with_user_event()
        .build()
        .map_err(|e| ViewerError::NoDisplay(format!("cannot connect to the X server: {e}")))?;
    let proxy = event_loop.create_proxy();
    let (jobs, worker) =
        spawn_render_thread(renderer.clone(), move |rendered| proxy.send_event(rendered).is_ok());
    let mut app = App::new(renderer, config, jobs);
    let ran = event_loop.run_app(&mut app);
    drop(app.jobs.take());
    let _ = worker.join();
    ran.map_err(|e| ViewerError::Window(e.to_string()))?;
    app.finish()
}

/// The window's state.
pub(crate) struct App {
    renderer: Arc<dyn SceneRenderer>,
    config: ViewerConfig,
    pub(crate) jobs: Option<mpsc::Sender<Job>>,
    window: Option<Rc<Window>>,
    surface: Option<softbuffer::Surface<Rc<Window>, Rc<Window>>>,
    pub(crate) busy: bool,
    /// The frame being rendered: its view's version, whether the camera was moving, and
    /// its cancel token.
    in_flight: Option<(u64, bool, Cancel)>,
    controller: CameraController,
    home: CameraController,
    settings: ViewSettings,
    scheduler: ProgressiveScheduler,
    held: BTreeSet<Key>,
    cursor: Option<(f64, f64)>,
    dragging: bool,
    last_drag: Option<Instant>,
    last_tick: Instant,
    shown: Option<(Frame, Duration)>,
    show_help: bool,
    show_hud: bool,
    /// The camera path being recorded.
    recording: Option<CameraRecording>,
    script_frame: usize,
    /// Whether the script's current frame holds keys that move the camera.
    script_moving: bool,
    records: Vec<FrameRecord>,
    last_shown: Option<Instant>,
    screenshot: Option<PathBuf>,
    error: Option<ViewerError>,
    /// The scene's simulation, where it has one.
    simulation: Option<SimulationControl>,
}

impl App {
    pub(crate) fn new(
        renderer: Arc<dyn SceneRenderer>,
        config: ViewerConfig,
        jobs: mpsc::Sender<Job>,
    ) -> Self {
        let controller = CameraController::new(&config.camera, renderer.scene_size());
        let scheduler = ProgressiveScheduler::new(config.size, config.frame_budget);
        let simulation = renderer.has_simulation().then(SimulationControl::new);
        App {
            simulation,
            home: controller.clone(),
            controller,
            settings: config.settings.clone(),
            scheduler,
            renderer,
            config,
            jobs: Some(jobs),
            window: None,
            surface: None,
            busy: false,
            in_flight: None,
            held: BTreeSet::new(),
            cursor: None,
            dragging: false,
            last_drag: None,
            last_tick: Instant::now(),
            shown: None,
            show_help: false,
            show_hud: true,
            recording: None,
            script_frame: 0,
            script_moving: false,
            records: Vec::new(),
            last_shown: None,
            screenshot: None,
            error: None,
        }
    }

    fn scripted(&self) -> bool {
        self.config.frames.is_some()
    }

    /// Ends the run: the camera path being recorded and the stats are written.
    pub(crate) fn finish(mut self) -> Result<ViewerSummary, ViewerError> {
        if let Some(error) = self.error.take() {
            return Err(error);
        }
        if self.recording.is_some() {
            self.toggle_recording()?;
        }
        if let Some(path) = &self.config.stats {
            let text = serde_json::to_string_pretty(&serde_json::json!({ "frames": self.records }))
                .expect("frame records serialise");
            std::fs::write(path, text + "\n")
                .map_err(|source| ViewerError::Io { path: path.clone(), source })?;
        }
        Ok(ViewerSummary { frames: self.records, screenshot: self.screenshot })
    }

    /// Stops the event loop with `error`.
    fn fail(&mut self, event_loop: &dyn LoopControl, error: ViewerError) {
        self.error.get_or_insert(error);
        event_loop.exit();
    }

    /// Sends the next frame to the render thread, if it is idle and there is one to render.
    fn schedule(&mut self, event_loop: &dyn LoopControl) {
        if self.busy {
            return;
        }
        let Some(request) = self.scheduler.next() else { return };
        self.send(event_loop, request);
    }

    /// Sends `request` to the render thread with the current camera and settings.
    fn send(&mut self, event_loop: &dyn LoopControl, request: FrameRequest) {
        let camera = match self.controller.camera(request.width, request.height) {
            Ok(camera) => camera,
            Err(e) => return self.fail(event_loop, ViewerError::Render(e.to_string())),
        };
        let (moving, cancel) = (self.moving(), Cancel::new());
        self.in_flight = Some((request.version, moving, cancel.clone()));
        // A scripted run steps a running simulation once a frame, so that it is the same
        // every run; an interactive one as often as fits half the frame budget.
        let budget = (!self.scripted()).then_some(self.config.frame_budget / 2);
        let simulate = self.simulation.as_mut().and_then(|s| s.take_request(budget));
        let settings = self.settings.clone();
        let job = Job { request, camera, settings, moving, cancel, simulate };
        if let Some(jobs) = &self.jobs {
            self.busy = jobs.send(job).is_ok();
        }
    }

    /// Cancels the frame being rendered if it was asked for at rest and the view has changed
    /// since: a full-size frame can take long, and the new view should not wait for it.
    /// (Frames asked for while moving fit the frame budget and are shown.)
    fn cancel_outdated(&self) {
        if let Some((version, false, cancel)) = &self.in_flight {
            if *version != self.scheduler.version() {
                cancel.set();
            }
        }
    }

    /// Whether the view is changing: the camera moves, or the simulation runs.
    fn moving(&self) -> bool {
        if self.simulation.as_ref().is_some_and(|s| s.running) {
            return true;
        }
        if self.scripted() {
            return self.script_moving;
        }
        let dragged = self.last_drag.is_some_and(|t| t.elapsed() < DRAG_SETTLE);
        motion_from(&self.held).is_moving() || dragged
    }

    /// Carries out `action`.
    fn act(&mut self, event_loop: &dyn LoopControl, action: Action) {
        let result = match action {
            Action::Quit => {
                event_loop.exit();
                Ok(())
            }
            Action::ToggleHelp => {
                self.show_help = !self.show_help;
                Ok(())
            }
            Action::ToggleHud => {
                self.show_hud = !self.show_hud;
                Ok(())
            }
            Action::ToggleNavigation => {
                self.controller.toggle_navigation();
                Ok(())
            }
            Action::ResetView => {
                let navigation = self.controller.navigation();
                self.controller = self.home.clone();
                if self.controller.navigation() != navigation {
                    self.controller.toggle_navigation();
                }
                self.scheduler.changed();
                Ok(())
            }
            Action::Screenshot => self.save_screenshot(None).map(|_| ()),
            Action::ToggleRecording => self.toggle_recording(),
            Action::ToggleSimulation | Action::StepSimulation | Action::ToggleRain => {
                if let Some(simulation) = &mut self.simulation {
                    if simulation.apply(action) {
                        self.scheduler.changed();
                    }
                    self.scheduler.set_moving(self.moving());
                }
                Ok(())
            }
            other => {
                if self.settings.apply(other) {
                    self.scheduler.changed();
                }
                Ok(())
            }
        };
        if let Err(e) = result {
            self.fail(event_loop, e);
        }
        if let Some(window) = &self.window {
            window.request_redraw();
        }
    }

    /// Writes the frame shown (without the overlay) to `path`, or to the next
    /// free `relief-view-NNN.png` of the output folder.
    fn save_screenshot(&mut self, path: Option<&Path>) -> Result<Option<PathBuf>, ViewerError> {
        let Some((frame, _)) = &self.shown else { return Ok(None) };
        save_screenshot(frame, path, &self.config.output_dir).map(Some)
    }

    /// Starts recording, or stops and writes the next free `relief-path-NNN.json`.
    fn toggle_recording(&mut self) -> Result<(), ViewerError> {
        match self.recording.take() {
            None => self.recording = Some(CameraRecording::start(self.script_frame)),
            Some(recording) => recording.write(&self.config.output_dir)?,
        }
        Ok(())
    }

    /// Applies the script's frame `k`: its presses, then its held keys for one frame's time.
    pub(crate) fn play_script_frame(&mut self, event_loop: &dyn LoopControl, k: usize) {
        let frame = self.config.script.frame(k);
        for key in frame.pressed {
            if let Some(action) = action_for(key) {
                self.act(event_loop, action);
            }
        }
        let motion = motion_from(&frame.held);
        if self.controller.apply(motion, SCRIPT_FRAME_S) {
            self.scheduler.changed();
        }
        self.script_moving = motion.is_moving();
        // Past its script, a scripted run pauses the simulation, so that it comes to rest.
        if k >= self.config.script.len() {
            if let Some(simulation) = &mut self.simulation {
                simulation.running = false;
            }
        }
        self.scheduler.set_moving(self.moving());
    }

    /// A frame came back from the render thread.
    pub(crate) fn on_rendered(&mut self, event_loop: &dyn LoopControl, rendered: Rendered) {
        self.busy = false;
        self.in_flight = None;
        let (request, frame, elapsed, moving) = match rendered {
            Rendered::Frame { request, frame, elapsed, moving, simulated } => {
                self.record_simulation(simulated);
                (request, frame, elapsed, moving)
            }
            Rendered::Cancelled(simulated) => {
                self.record_simulation(simulated);
                if self.scripted() {
                    return self.drive_script(event_loop);
                }
                return self.schedule(event_loop);
            }
            Rendered::Failed(e) => return self.fail(event_loop, ViewerError::Render(e)),
        };
        self.scheduler.shown(request, elapsed);
        let now = Instant::now();
        let interval = self.last_shown.map(|t| now.duration_since(t));
        self.last_shown = Some(now);
        self.records.push(FrameRecord {
            width: frame.width,
            height: frame.height,
            moving,
            render_ms: elapsed.as_secs_f64() * 1e3,
            interval_ms: interval.map(|d| d.as_secs_f64() * 1e3),
            rays: frame.stats.rays,
        });
        self.shown = Some((frame, elapsed));
        let (scripted, script_frame) = (self.scripted(), self.script_frame);
        if let Some(recording) = &mut self.recording {
            recording.push(&self.controller, scripted.then_some(script_frame));
        }
        if let Some(window) = &self.window {
            window.request_redraw();
        }
        let current = self.scheduler.version() == request.version;
        if self.scripted() && current {
            // One script frame for each view shown.
            self.advance_script(event_loop);
        }
        if self.simulation.as_ref().is_some_and(|s| s.running) {
            // The next frame shows the next step.
            self.scheduler.changed();
        }
        if self.scripted() {
            return self.drive_script(event_loop);
        }
        self.schedule(event_loop);
    }

    /// Takes note of the steps the simulation took before a frame.
    fn record_simulation(&mut self, report: Option<SimulationReport>) {
        if let (Some(simulation), Some(report)) = (&mut self.simulation, report) {
            simulation.record(&report);
        }
    }

    /// Plays the script's next frame.
    fn advance_script(&mut self, event_loop: &dyn LoopControl) {
        self.script_frame += 1;
        self.play_script_frame(event_loop, self.script_frame);
    }

    /// Keeps a scripted run going while nothing is being rendered: renders the next frame the
    /// scheduler asks for; where it asks for none, plays the script's next frame, renders the
    /// full view again until `frames` were shown, or saves the screenshot and ends the run.
    /// Once the run is ending it does nothing: the loop calls it again (`about_to_wait`)
    /// before it stops, and the screenshot is saved once.
    pub(crate) fn drive_script(&mut self, event_loop: &dyn LoopControl) {
        let Some(frames) = self.config.frames else { return };
        while !self.busy && self.error.is_none() && !event_loop.exiting() {
            if self.scheduler.next().is_some() {
                return self.schedule(event_loop);
            }
            if self.script_frame < self.config.script.len() {
                self.advance_script(event_loop);
                continue;
            }
            if self.records.len() < frames as usize {
                let request = self.scheduler.full_request();
                return self.send(event_loop, request);
            }
            let target = self.config.screenshot.clone();
            match target.map(|p| self.save_screenshot(Some(&p))).transpose() {
                Ok(saved) => self.screenshot = saved.flatten(),
                Err(e) => return self.fail(event_loop, e),
            }
            return event_loop.exit();
        }
    }
}
