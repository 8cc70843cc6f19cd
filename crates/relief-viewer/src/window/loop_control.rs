//! What the viewer's state asks of the event loop it runs in, so that the same state runs in
//! a window (winit's loop) and without one (the headless loop).

use winit::event_loop::ActiveEventLoop;

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
