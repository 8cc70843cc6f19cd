//! The window's side of the event loop: winit's events (the window made on resume, keys,
//! the mouse, resizing, the loop's idle turn) handed to the viewer's state, and the newest
//! frame drawn into the window with the overlay.

use super::{App, Rendered};
use crate::frame::blit;
use crate::hud::{hud_lines, HudState};
use crate::input_map::{action_for, motion_from, Key, KEY_HELP};
use crate::winit_keys::key_of;
use crate::{overlay, ViewerError};
use std::num::NonZeroU32;
use std::rc::Rc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::keyboard::PhysicalKey;
use winit::window::{Window, WindowId};

impl App {
    /// Draws the newest frame, scaled to the window, and the overlay.
    pub(super) fn present(&mut self) -> Result<(), ViewerError> {
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
