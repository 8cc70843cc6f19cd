//! The window and its event loop: input goes to the camera and the settings, frames are
//! rendered on a separate thread (the loop never waits for one), and the newest frame is
//! shown scaled to the window with the overlay.

use crate::camera_path::{CameraKey, CameraPath};
use crate::frame::{blit, Cancel, Frame, SceneRenderer};
use crate::hud::{hud_lines, HudState};
use crate::input_map::{action_for, motion_from, Action, Key, KEY_HELP};
use crate::progressive::{FrameRequest, ProgressiveScheduler};
use crate::script::{Script, SCRIPT_FRAME_S};
use crate::summary::{FrameRecord, ViewerSummary};
use crate::winit_keys::key_of;
use crate::{overlay, CameraController, ViewSettings, ViewerError};
use crate::{SimulationControl, SimulationReport, SimulationRequest};
use relief_core::Camera;
use std::collections::BTreeSet;
use std::num::NonZeroU32;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::PhysicalKey;
use winit::window::{Window, WindowId};

/// How long after the last mouse movement a drag still counts as moving.
const DRAG_SETTLE: Duration = Duration::from_millis(150);

/// What the viewer opens with.
#[derive(Debug, Clone)]
pub struct ViewerConfig {
    /// The full image size (and the window's first inner size), pixels.
    pub size: (u32, u32),
    /// The starting camera.
    pub camera: Camera,
    /// The starting settings.
    pub settings: ViewSettings,
    /// Stop after this many frames shown (and once the view is at full resolution), saving
    /// the last one to `screenshot`.
    pub frames: Option<u32>,
    /// Input played frame by frame instead of the keyboard (with `frames`).
    pub script: Script,
    /// Where the last frame goes when `frames` ends the run.
    pub screenshot: Option<PathBuf>,
    /// Where screenshots (P) and camera paths (R) are written.
    pub output_dir: PathBuf,
    /// Where to write every frame's timing as JSON when the viewer closes.
    pub stats: Option<PathBuf>,
    /// The time a frame may take while the camera moves.
    pub frame_budget: Duration,
}

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

/// What the viewer's loop asks of the loop it runs in: to stop, and whether it is stopping
/// (winit's event loop with a window, or `Headless` without).
pub(crate) trait LoopControl {
    /// Stops the loop once the current event is handled.
    fn exit(&self);
    /// Whether the loop was asked to stop.
    fn exiting(&self) -> bool;
}

impl LoopControl for ActiveEventLoop {
    fn exit(&self) {
        ActiveEventLoop::exit(self);
    }

    fn exiting(&self) -> bool {
        ActiveEventLoop::exiting(self)
    }
}

/// A frame to render.
pub(crate) struct Job {
    request: FrameRequest,
    camera: Camera,
    settings: ViewSettings,
    moving: bool,
    cancel: Cancel,
    /// The simulation's steps to take before the frame.
    simulate: Option<SimulationRequest>,
}

/// What the render thread sends back.
pub(crate) enum Rendered {
    Frame {
        request: FrameRequest,
        frame: Frame,
        elapsed: Duration,
        moving: bool,
        simulated: Option<SimulationReport>,
    },
    /// A frame the viewer cancelled (the simulation's steps before it were taken).
    Cancelled(Option<SimulationReport>),
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
            let rendered = match renderer.render(&job.camera, &job.settings, &job.cancel) {
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
    /// The camera path being recorded, and when (and at which script frame) it started.
    recording: Option<(Instant, usize, CameraPath)>,
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
        let path = match path {
            Some(p) => p.to_path_buf(),
            None => next_free(&self.config.output_dir, "relief-view", "png"),
        };
        let rgb: Vec<u8> = frame.rgb.iter().flatten().copied().collect();
        relief_io::write_png_rgb8(&path, frame.width, frame.height, &rgb)?;
        eprintln!("saved {} ({}x{})", path.display(), frame.width, frame.height);
        Ok(Some(path))
    }

    /// Starts recording, or stops and writes the next free `relief-path-NNN.json`.
    fn toggle_recording(&mut self) -> Result<(), ViewerError> {
        match self.recording.take() {
            None => {
                self.recording = Some((Instant::now(), self.script_frame, CameraPath::default()))
            }
            Some((_, _, path)) => {
                let file = next_free(&self.config.output_dir, "relief-path", "json");
                path.write(&file)?;
                eprintln!("saved {} ({} cameras)", file.display(), path.keys.len());
            }
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
        if let Some((started, start_frame, path)) = &mut self.recording {
            // A scripted run's clock is its frames, so that its recordings are the same every
            // run.
            let time_s = if scripted {
                (script_frame - *start_frame) as f64 * SCRIPT_FRAME_S
            } else {
                started.elapsed().as_secs_f64()
            };
            let c = &self.controller;
            path.push(CameraKey {
                time_s,
                eye: c.eye().to_array(),
                target: c.target().to_array(),
                up: c.up().to_array(),
                fov_deg: c.fov_deg(),
            });
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

    /// Draws the newest frame, scaled to the window, and the overlay.
    fn present(&mut self) -> Result<(), ViewerError> {
        let (Some(window), Some(surface)) = (&self.window, &mut self.surface) else {
            return Ok(());
        };
        let size = window.inner_size();
        let (Some(w), Some(h)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
            return Ok(());
        };
        let err = |e: softbuffer::SoftBufferError| ViewerError::Window(e.to_string());
        surface.resize(w, h).map_err(err)?;
        let mut buffer = surface.buffer_mut().map_err(err)?;
        buffer.fill(0);
        let mut lines = Vec::new();
        if let Some((frame, elapsed)) = &self.shown {
            blit(frame, &mut buffer, w.get(), h.get());
            if self.show_hud {
                lines = hud_lines(&HudState {
                    scene: &self.renderer.describe(),
                    navigation: self.controller.navigation(),
                    frame,
                    elapsed: *elapsed,
                    settings: &self.settings,
                    recording: self.recording.is_some(),
                    simulation: self.simulation.as_ref(),
                });
            }
        }
        if self.show_help {
            lines.extend(KEY_HELP.iter().map(|(keys, what)| format!("{keys:<11} {what}")));
        }
        overlay::draw_panel(&mut buffer, w.get() as usize, h.get() as usize, &lines);
        buffer.present().map_err(err)
    }
}

impl ApplicationHandler<Rendered> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let (w, h) = self.config.size;
        let attributes = Window::default_attributes()
            .with_title(format!("relief view: {}", self.renderer.describe()))
            .with_inner_size(winit::dpi::PhysicalSize::new(w, h));
        let made =
            event_loop.create_window(attributes).map_err(|e| e.to_string()).and_then(|window| {
                let window = Rc::new(window);
                let context =
                    softbuffer::Context::new(window.clone()).map_err(|e| e.to_string())?;
                let surface = softbuffer::Surface::new(&context, window.clone())
                    .map_err(|e| e.to_string())?;
                Ok((window, surface))
            });
        match made {
            Ok((window, surface)) => {
                self.window = Some(window);
                self.surface = Some(surface);
            }
            Err(e) => return self.fail(event_loop, ViewerError::Window(e)),
        }
        self.last_tick = Instant::now();
        if self.scripted() {
            self.play_script_frame(event_loop, 0);
            return self.drive_script(event_loop);
        }
        self.schedule(event_loop);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.present() {
                    self.fail(event_loop, e);
                }
            }
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else { return };
                let Some(key) = key_of(code) else { return };
                // A scripted run takes only Esc from the keyboard.
                if self.scripted() && key != Key::Escape {
                    return;
                }
                match event.state {
                    ElementState::Pressed => {
                        if !event.repeat {
                            if let Some(action) = action_for(key) {
                                self.act(event_loop, action);
                            }
                        }
                        self.held.insert(key);
                    }
                    ElementState::Released => {
                        self.held.remove(&key);
                    }
                }
            }
            WindowEvent::MouseInput { state, button: MouseButton::Left, .. } => {
                self.dragging = state == ElementState::Pressed && !self.scripted();
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (true, Some((x, y))) = (self.dragging, self.cursor) {
                    self.controller.drag(now.0 - x, now.1 - y);
                    self.last_drag = Some(Instant::now());
                    self.scheduler.changed();
                }
                self.cursor = Some(now);
            }
            WindowEvent::MouseWheel { delta, .. } if !self.scripted() => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 50.0,
                };
                self.controller.wheel(steps);
                self.scheduler.changed();
            }
            WindowEvent::Resized(size) => {
                // The full frame follows the window, but a scripted run keeps --size, so that
                // it renders the same frames whatever a window manager does to its window.
                if !self.scripted() {
                    self.scheduler.resize((size.width, size.height));
                }
                if let Some(window) = &self.window {
                    window.request_redraw();
                }
            }
            _ => {}
        }
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, rendered: Rendered) {
        self.on_rendered(event_loop, rendered);
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        let dt = now.duration_since(self.last_tick).as_secs_f64().min(0.25);
        self.last_tick = now;
        if !self.scripted() {
            if self.controller.apply(motion_from(&self.held), dt) {
                self.scheduler.changed();
            }
            self.scheduler.set_moving(self.moving());
            self.cancel_outdated();
            self.schedule(event_loop);
        } else {
            self.drive_script(event_loop);
        }
        event_loop.set_control_flow(if self.moving() {
            ControlFlow::WaitUntil(now + Duration::from_millis(10))
        } else {
            ControlFlow::Wait
        });
    }
}

/// `dir/PREFIX-NNN.EXT` with the smallest number from 001 that names no file yet, so that
/// a new run does not overwrite the screenshots and paths of an earlier one.
fn next_free(dir: &Path, prefix: &str, extension: &str) -> PathBuf {
    (1u32..)
        .map(|n| dir.join(format!("{prefix}-{n:03}.{extension}")))
        .find(|path| !path.exists())
        .expect("a free number")
}
