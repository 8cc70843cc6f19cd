//! Progress bars for long work (hidden when stderr is not a terminal).

use indicatif::{ProgressBar, ProgressStyle};
use std::sync::Mutex;

/// A bar counting `total` items of `what`.
pub fn bar(total: u64, what: &str) -> ProgressBar {
    let bar = ProgressBar::new(total);
    let style =
        ProgressStyle::with_template("{msg:>12} [{bar:40}] {percent:>3}% {elapsed_precise}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> ");
    bar.set_style(style);
    bar.set_message(what.to_string());
    bar
}

/// A spinner for work whose amount is not known ahead, ticking on its own.
pub fn spinner(what: &str) -> ProgressBar {
    let bar = ProgressBar::new_spinner();
    bar.set_message(what.to_string());
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    bar
}

/// The scene layer's progress shown as bars: a [`bar`] for each stage of known length, a
/// [`spinner`] for the others.
#[derive(Default)]
pub struct Bars {
    current: Mutex<Option<ProgressBar>>,
}

impl Bars {
    /// The bar of the stage under way, if any.
    fn with(&self, f: impl FnOnce(&ProgressBar)) {
        if let Some(bar) = self.current.lock().expect("no bar panicked").as_ref() {
            f(bar);
        }
    }
}

impl relief_render::Progress for Bars {
    fn begin(&self, what: &str, total: Option<u64>) {
        let bar = match total {
            Some(total) => bar(total, what),
            None => spinner(what),
        };
        if let Some(old) = self.current.lock().expect("no bar panicked").replace(bar) {
            old.finish_and_clear();
        }
    }

    fn advance(&self, n: u64) {
        self.with(|bar| bar.inc(n));
    }

    fn set(&self, done: u64) {
        self.with(|bar| bar.set_position(done));
    }

    fn end(&self) {
        if let Some(bar) = self.current.lock().expect("no bar panicked").take() {
            bar.finish_and_clear();
        }
    }
}
